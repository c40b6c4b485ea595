#!/usr/bin/env bash
# Install what is missing, build everything, run every test (ctest).
#   scripts/test.sh --asan   then also build and run the same suite under AddressSanitizer + UBSan
#                            (the asan preset: build/asan, no benchmarks).
set -euo pipefail
cd "$(dirname "$0")/.."

asan=false
case "${1:-}" in
"") ;;
--asan) asan=true ;;
*)
    echo "usage: scripts/test.sh [--asan]" >&2
    exit 2
    ;;
esac

scripts/install-deps.sh
cmake --preset release >/dev/null
cmake --build --preset release
ctest --preset release -j 2

if $asan; then
    cmake --preset asan >/dev/null
    cmake --build --preset asan
    ctest --preset asan -j 2
fi
