#!/usr/bin/env bash
# Makes the benchmark surfaces in bench/data/ (git-ignored) with `ddsimp isosurface`, from the
# carotid volume of the shared data set (76x49x45 image, fields `scalars` and `vectors`):
#
#   carotid-1m.vtp    isosurface scalars = ISO_1M of the volume resampled RESAMPLE_1M times per
#                     axis: >= 1 M triangles, carrying `vectors` (the speed and memory runs)
#   carotid-4m.vtp    the same at RESAMPLE_4M: >= 4 M triangles (the thread-scaling run on a
#                     larger surface; only with --4m)
#   carotid-100k.vtp  isosurface scalars = ISO_100K of the volume resampled RESAMPLE_100K times:
#                     ~100 k triangles, carrying `vectors` (quick runs: bench/run.sh --quick).
#                     Not the native resolution: its staircase isosurfaces are full of edges
#                     sharper than usual feature angles (with 60 degrees ddsimp stops at 40%).
#
# Usage: bench/make-data.sh [--force] [--4m]     (--force: remake files that exist)
# Environment:
#   DDSIMP              the ddsimp program (default: build/release/tools/ddsimp, else on PATH)
#   DDSIMP_SHARED_DATA  the shared data directory (default: ../shared/data beside the repository)
set -euo pipefail

readonly ISO_1M=127 RESAMPLE_1M=3
readonly ISO_100K=145 RESAMPLE_100K=2
readonly RESAMPLE_4M=6
readonly MIN_TRIANGLES_1M=1000000 MIN_TRIANGLES_4M=4000000

here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
root=$(dirname "$here")
data="$here/data"
volume="${DDSIMP_SHARED_DATA:-$(cd "$root/.." && pwd)/shared/data}/volumes/carotid.vtk"

force=false
large=false
for arg in "$@"; do
    case "$arg" in
    --force) force=true ;;
    --4m) large=true ;;
    *)
        echo "usage: bench/make-data.sh [--force] [--4m]" >&2
        exit 2
        ;;
    esac
done

ddsimp="${DDSIMP:-}"
if [[ -z "$ddsimp" ]]; then
    if [[ -x "$root/build/release/tools/ddsimp" ]]; then
        ddsimp="$root/build/release/tools/ddsimp"
    elif command -v ddsimp >/dev/null; then
        ddsimp=$(command -v ddsimp)
    else
        echo "make-data.sh: no ddsimp program; build it (cmake --preset release &&" \
            "cmake --build --preset release) or set DDSIMP" >&2
        exit 1
    fi
fi
if [[ ! -f "$volume" ]]; then
    echo "make-data.sh: $volume not found; set DDSIMP_SHARED_DATA" >&2
    exit 1
fi
if ! command -v jq >/dev/null; then
    echo "make-data.sh: needs jq (apt-get install jq)" >&2
    exit 1
fi
mkdir -p "$data"

# triangles FILE: the triangle count `ddsimp info --json` reports.
triangles() {
    "$ddsimp" info "$1" --json | jq -r '.triangles'
}

# make_surface OUT MIN_TRIANGLES ARGS...: runs `ddsimp isosurface` into OUT (through a temporary file, so
# that an interrupted run leaves nothing half-written) and checks the triangle count.
make_surface() {
    local out="$1" min="$2"
    shift 2
    if [[ -f "$out" ]] && ! $force; then
        echo "make-data.sh: $out exists ($(triangles "$out") triangles); --force remakes it"
        return
    fi
    local tmp="${out%.vtp}.partial.vtp"
    echo "make-data.sh: ddsimp isosurface $volume $* -o $out"
    "$ddsimp" isosurface "$volume" "$@" -o "$tmp"
    local n
    n=$(triangles "$tmp")
    if ((n < min)); then
        rm -f "$tmp"
        echo "make-data.sh: $out would have $n triangles, fewer than $min" >&2
        exit 1
    fi
    mv "$tmp" "$out"
    echo "make-data.sh: $out: $n triangles"
}

make_surface "$data/carotid-1m.vtp" "$MIN_TRIANGLES_1M" \
    --field scalars --value "$ISO_1M" --resample "$RESAMPLE_1M" --carry vectors
make_surface "$data/carotid-100k.vtp" 50000 \
    --field scalars --value "$ISO_100K" --resample "$RESAMPLE_100K" --carry vectors
if $large; then
    make_surface "$data/carotid-4m.vtp" "$MIN_TRIANGLES_4M" \
        --field scalars --value "$ISO_1M" --resample "$RESAMPLE_4M" --carry vectors
fi
