#!/usr/bin/env bash
# The main job: install what is missing, build, and start ddsimp-server on localhost with the
# shipped sample surface (a 217,709-triangle isosurface of a carotid artery carrying the blood
# velocity, data/README.md) already loaded, and the browser renderer at http://localhost:7421/
# (built from web/ with npm when its sources changed). In another terminal:
#   build/release/tools/ddsimp remote list
#   build/release/tools/ddsimp remote simplify --surface ID --alpha 0.3 --keep 0.5,0.1 -o out/
# Stop it with Ctrl-C (or SIGTERM). Extra arguments go to the server (see --help).
set -euo pipefail
cd "$(dirname "$0")/.."

scripts/install-deps.sh
cmake --preset release >/dev/null
cmake --build --preset release --target ddsimp_server ddsimp_cli

# The browser renderer: web/dist, which the server serves at / by default.
web_stale() {
    [[ ! -f web/dist/index.html ]] || [[ -n $(find web/index.html web/src web/vite.config.js \
        web/package.json web/package-lock.json protocol/proto -newer web/dist/index.html -print -quit) ]]
}
if ! command -v npm >/dev/null; then
    echo "run.sh: npm is missing, so http://localhost:7421/ has no browser renderer" >&2
elif web_stale; then
    (cd web && npm ci --no-audit --no-fund && npm run build) ||
        echo "run.sh: the browser renderer did not build (see above); starting without it" >&2
fi
echo "run.sh: open http://localhost:7421/ in a browser (or /?session=NAME to share a view)"

exec build/release/server/ddsimp-server --data-dir build/release/ddsimp-data "$@"
