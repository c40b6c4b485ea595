#!/usr/bin/env bash
# Builds the browser renderer for the tests: npm ci (exactly the lockfile) in web/, then the
# Vite build into the given directory. Usage: build-web.sh WEB_SRC OUT_DIR
set -euo pipefail
web=$1
out=$2
cd "$web"
npm ci --no-audit --no-fund
npm run build -- --outDir "$out" --emptyOutDir
test -f "$out/index.html"
