#!/usr/bin/env bash
# The service's loopback benchmark in one command (issue 4): builds the release server and
# ddsimp_bench_service, makes the >= 1 M-triangle surface if missing, starts ddsimp-server on free
# loopback ports with an empty data directory, measures (latency of a cached 10% level, streaming
# throughput against a plain socket copy, a 64-member session against a one-member session), stops
# the server and writes the Markdown table to bench/results/service.md (JSON beside it).
#
# Usage: bench/service/run.sh [RUNS]          (timed repetitions of each measure, default 9)
# Environment: DDSIMP_BENCH_BUILD_DIR (programs already built there; no preset build),
#              DDSIMP_BENCH_SURFACE (another surface).
set -euo pipefail

here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
bench=$(dirname "$here")
root=$(dirname "$bench")
runs="${1:-9}"
results="$bench/results"

cd "$root"
bench_targets="ddsimp_server ddsimp_bench_service"
# shellcheck source=bench/service/prepare.sh
. "$here/prepare.sh"

# shellcheck source=bench/start-server.sh
. "$bench/start-server.sh"

mkdir -p "$results"
{
    echo "# ddsimp-server on loopback"
    echo
    echo "$(date -u +%Y-%m-%d), commit $(git rev-parse --short HEAD), $(nproc) cores, load $(cut -d' ' -f1-3 /proc/loadavg), \`bench/service/run.sh $runs\`"
    echo
    "$build/bench/service/ddsimp_bench_service" --port "$port" --surface "$surface" \
        --runs "$runs" --server-pid "$server" --json "$results/service.json"
} | tee "$results/service.md"
