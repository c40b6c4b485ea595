#!/usr/bin/env bash
# Install what is missing, build everything, run every test (ctest): as released (build/release),
# the ParaView plugin (the paraview preset, build/paraview: it builds alone against ParaView's own
# VTK), then the release suite under AddressSanitizer + UBSan (the asan preset, build/asan), then
# the threaded engine's tests and the command line's under ThreadSanitizer (the tsan-engine
# presets, build/tsan). This is what CI runs (.ci/run). Every build here is a unity build
# (CMAKE_UNITY_BUILD: a few sources per compiler run, so that the headers and templates they share,
# Boost's and GoogleTest's above all, are compiled once per batch): the builds take about a
# third less time.
#   scripts/test.sh --release-only   the release build, the plugin and their tests (no sanitizers)
set -euo pipefail
cd "$(dirname "$0")/.."

sanitizers=true
case "${1:-}" in
"") ;;
--release-only) sanitizers=false ;;
*)
    echo "usage: scripts/test.sh [--release-only]" >&2
    exit 2
    ;;
esac

scripts/install-deps.sh
cmake --preset release -DCMAKE_UNITY_BUILD=ON >/dev/null
cmake --build --preset release
ctest --preset release -j 2

# The plugin's publish test uses the release build's server rather than compiling another.
cmake --preset paraview -DCMAKE_UNITY_BUILD=ON \
    -DDDSIMP_SERVER_BINARY="$PWD/build/release/server/ddsimp-server" >/dev/null
cmake --build --preset paraview
ctest --preset paraview -j 2

if $sanitizers; then
    cmake --preset asan -DCMAKE_UNITY_BUILD=ON >/dev/null
    cmake --build --preset asan
    ctest --preset asan -j 2

    cmake --preset tsan -DCMAKE_UNITY_BUILD=ON >/dev/null
    cmake --build --preset tsan-engine
    ctest --preset tsan-engine -j 2
fi
