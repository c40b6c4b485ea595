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
build="${DDSIMP_BENCH_BUILD_DIR:-}"
if [[ -z "$build" ]]; then
    cmake --preset release >/dev/null
    cmake --build --preset release --target ddsimp_server ddsimp_bench_service ddsimp_cli
    build="$root/build/release"
fi

surface="${DDSIMP_BENCH_SURFACE:-$bench/data/carotid-1m.vtp}"
if [[ ! -f "$surface" ]]; then
    DDSIMP="$build/tools/ddsimp" "$bench/make-data.sh"
fi

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
