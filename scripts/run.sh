#!/usr/bin/env bash
# The main job: install what is missing, build, and start ddsimp-server on localhost with the
# shipped sample surface (a cutting plane through a CVD reactor with temperature, pressure,
# velocity and species) already loaded. In another terminal:
#   build/release/tools/ddsimp remote list
#   build/release/tools/ddsimp remote simplify --surface ID --alpha 0.3 --keep 0.5,0.1 -o out/
# Stop it with Ctrl-C (or SIGTERM). Extra arguments go to the server (see --help).
set -euo pipefail
cd "$(dirname "$0")/.."

scripts/install-deps.sh
cmake --preset release >/dev/null
cmake --build --preset release --target ddsimp_server ddsimp_cli

exec build/release/server/ddsimp-server --data-dir build/release/ddsimp-data "$@"
