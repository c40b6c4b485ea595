#!/usr/bin/env bash
# Install what is missing, build everything, run every test (ctest).
set -euo pipefail
cd "$(dirname "$0")/.."

scripts/install-deps.sh
cmake --preset release >/dev/null
cmake --build --preset release
ctest --preset release -j 2
