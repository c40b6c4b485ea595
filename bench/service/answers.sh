#!/usr/bin/env bash
# How soon ddsimp-server answers (issue 28) in one command: builds the release server and
# ddsimp_bench_answers, makes the 1.18 M-triangle carotid if missing, starts ddsimp-server on
# free loopback ports with an empty data directory, measures (an alpha change: preview and exact
# level against the library's own time; a 20-value slider; two clients, one sending 100
# requests), stops the server and writes the table to bench/results/answers.md (JSON beside it).
#
# Usage: bench/service/answers.sh
# Environment: DDSIMP_BENCH_BUILD_DIR (programs already built there; no preset build),
#              DDSIMP_BENCH_SURFACE (another surface).
set -euo pipefail

here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
bench=$(dirname "$here")
root=$(dirname "$bench")
results="$bench/results"

cd "$root"
bench_targets="ddsimp_server ddsimp_bench_answers"
# shellcheck source=bench/service/prepare.sh
. "$here/prepare.sh"

# shellcheck source=bench/start-server.sh
. "$bench/start-server.sh"

mkdir -p "$results"
{
    echo "# How soon ddsimp-server answers"
    echo
    echo "$(date -u +%Y-%m-%d), commit $(git rev-parse --short HEAD), $(nproc) cores, load $(cut -d' ' -f1-3 /proc/loadavg), \`bench/service/answers.sh\`"
    echo
    "$build/bench/service/ddsimp_bench_answers" --port "$port" --http-port "$http_port" \
        --surface "$surface" --json "$results/answers.json"
} | tee "$results/answers.md"
