#!/usr/bin/env bash
# Install what is missing, build everything, run every test (ctest); then build and run the same
# suite under AddressSanitizer + UBSan (the asan preset: build/asan, no benchmarks).
set -euo pipefail
cd "$(dirname "$0")/.."

scripts/install-deps.sh
cmake --preset release >/dev/null
cmake --build --preset release
ctest --preset release -j 2

cmake --preset asan >/dev/null
cmake --build --preset asan
ctest --preset asan -j 2
