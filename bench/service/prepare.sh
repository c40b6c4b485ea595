# Sourced by the service benchmarks (run.sh, answers.sh) from the root: builds the release targets in
# $bench_targets unless DDSIMP_BENCH_BUILD_DIR names programs already built, and makes the
# >= 1 M-triangle surface if DDSIMP_BENCH_SURFACE names none. Sets build and surface.
# shellcheck shell=bash disable=SC2154,SC2086 # root, bench and bench_targets are set by the script that sources this
build="${DDSIMP_BENCH_BUILD_DIR:-}"
if [[ -z "$build" ]]; then
    cmake --preset release >/dev/null
    cmake --build --preset release --target $bench_targets ddsimp_cli
    build="$root/build/release"
fi

surface="${DDSIMP_BENCH_SURFACE:-$bench/data/carotid-1m.vtp}"
if [[ ! -f "$surface" ]]; then
    DDSIMP="$build/tools/ddsimp" "$bench/make-data.sh"
fi
