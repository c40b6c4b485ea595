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

free_port() {
    python3 -c 'import socket; s = socket.socket(); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])'
}
port=$(free_port)
http_port=$(free_port)
data_dir=$(mktemp -d)
log="$data_dir/server.log"
"$build/server/ddsimp-server" --bind 127.0.0.1 --port "$port" --http-port "$http_port" \
    --data-dir "$data_dir/store" --log-level warn >"$log" 2>&1 &
server=$!
cleanup() {
    kill "$server" 2>/dev/null || true
    wait "$server" 2>/dev/null || true
    rm -rf "$data_dir"
}
trap cleanup EXIT
for _ in $(seq 100); do
    if curl -sf "http://127.0.0.1:$http_port/healthz" >/dev/null 2>&1; then break; fi
    sleep 0.1
done

mkdir -p "$results"
{
    echo "# ddsimp-server on loopback"
    echo
    echo "$(date -u +%Y-%m-%d), commit $(git rev-parse --short HEAD), $(nproc) cores, load $(cut -d' ' -f1-3 /proc/loadavg), \`bench/service/run.sh $runs\`"
    echo
    "$build/bench/service/ddsimp_bench_service" --port "$port" --surface "$surface" \
        --runs "$runs" --server-pid "$server" --json "$results/service.json"
} | tee "$results/service.md"
