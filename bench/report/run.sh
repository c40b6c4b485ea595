#!/usr/bin/env bash
# The fidelity and speed report against the peers, in one command: builds (release preset) unless
# told where the programs are, makes the surfaces from ../shared/data, runs every reduction in its
# own process, and writes bench/results/report/ (git-ignored): report.md, results.csv,
# scaling.csv, data-error-vs-triangles.png, time-vs-size.png and earth-10pct.png (the surface and
# its reductions coloured by their data, rendered off-screen under Xvfb).
#
# Usage: bench/report/run.sh [--quick] [--resume] [--out DIR]
#   --quick   two small surfaces, one level (10%), no scaling and no rendering: the smoke test
#   --resume  keep the results of an interrupted run (DIR/runs) and do only what is missing;
#             bench/report/reuse.py seeds DIR/runs from the committed report, so that only the
#             runs a library change affects are made again
# Environment:
#   DDSIMP_REPORT_BUILD_DIR  use ddsimp and ddsimp_report already built there (skip the build)
#   DDSIMP_SHARED_DATA       the shared data directory (default: ../shared/data beside the repo)
#   DDSIMP_REPORT_COMMIT     the commit the programs were built from (default: git HEAD)
#   DDSIMP_REPORT_BUDGET     minutes after which no new run starts (default 75); what was not
#                            run is reported as "not run", most important runs first
# Needs: python3-matplotlib; for the images python3-vtk9 and xvfb (scripts/install-deps.sh); for
# meshoptimizer's attribute-aware simplifiers node and npm (Debian's nodejs, npm): a full run
# installs npm's meshoptimizer into bench/report/node_modules with `npm ci` (package-lock.json);
# --quick never does, and without node_modules the report leaves those peers out and says why.
# The full run takes about an hour on 2 cores.
set -euo pipefail

here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
root=$(dirname "$(dirname "$here")")
out="$root/bench/results/report"
quick=false
resume=()
while (($#)); do
    case "$1" in
    --quick) quick=true ;;
    --resume) resume=(--resume) ;;
    --out)
        out=$2
        shift
        ;;
    *)
        echo "usage: bench/report/run.sh [--quick] [--resume] [--out DIR]" >&2
        exit 2
        ;;
    esac
    shift
done

build="${DDSIMP_REPORT_BUILD_DIR:-}"
if [[ -z "$build" ]]; then
    (cd "$root" && cmake --preset release && cmake --build --preset release \
        --target ddsimp_cli ddsimp_report)
    build="$root/build/release"
fi
python=/usr/bin/python3 # Debian's, with python3-matplotlib and python3-vtk9
mkdir -p "$out"

if $quick; then
    surfaces="$out/surfaces"
    "$here/make-surfaces.sh" "$build" "$surfaces" --quick
    "$python" "$here/report.py" --build "$build" --surfaces "$surfaces" --out "$out" --quick
    exit 0
fi

# meshoptimizer's attribute-aware simplifiers (npm, WebAssembly): the version the lockfile names.
if command -v npm >/dev/null; then
    (cd "$here" && npm ci --no-audit --no-fund --loglevel=error) ||
        echo "run.sh: npm ci failed: meshoptimizer's attribute-aware peers are left out" >&2
else
    echo "run.sh: npm not found (Debian's npm): meshoptimizer's attribute-aware peers are left out" >&2
fi

# The full surfaces are big: keep them with the benchmark data (git-ignored) across runs.
surfaces="$root/bench/data/report"
"$here/make-surfaces.sh" "$build" "$surfaces"
"$here/make-surfaces.sh" "$build" "$surfaces" --scaling
# The committed report (bench/report/latest) is the baseline the goals are counted against;
# changes.md says what changed in the library since.
baseline=()
[[ -f "$here/latest/results.csv" ]] && baseline+=(--baseline "$here/latest/results.csv")
[[ -f "$here/changes.md" ]] && baseline+=(--notes "$here/changes.md")
"$python" "$here/report.py" --build "$build" --surfaces "$surfaces" --out "$out" \
    --scaling "$surfaces" --render-surface earth --budget-minutes "${DDSIMP_REPORT_BUDGET:-75}" \
    "${resume[@]}" "${baseline[@]}"
xvfb-run -a -s "-screen 0 1280x1024x24" "$python" "$here/render.py" \
    "$surfaces/earth.vtp" "$out/meshes" "$out/earth-10pct.png"
echo "run.sh: wrote $out/report.md"
