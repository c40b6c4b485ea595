#!/usr/bin/env bash
# The load run in one command: starts the release ddsimp-server on free loopback ports with an
# empty data directory, runs ddsimp-load against it (N clients x M operations; its flags are
# passed on), reports the server's peak memory and counters, and stops the server.
#
# Usage: bench/load/run.sh [ddsimp-load flags...]
#        e.g. bench/load/run.sh --surface bench/data/carotid-1m.vtp -n 16 -m 50
# Environment: DDSIMP_BENCH_BUILD_DIR (programs already built there; no preset build),
#              DDSIMP_LOAD_SERVER_FLAGS (more flags for the server, e.g. "--threads 4").
set -euo pipefail

here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
root=$(dirname "$(dirname "$here")")
cd "$root"
build="${DDSIMP_BENCH_BUILD_DIR:-}"
if [[ -z "$build" ]]; then
    cmake --preset release >/dev/null
    cmake --build --preset release --target ddsimp_server ddsimp_load
    build="$root/build/release"
fi

free_port() {
    python3 -c 'import socket; s = socket.socket(); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])'
}
port=$(free_port)
http_port=$(free_port)
data_dir=$(mktemp -d)
# shellcheck disable=SC2086
"$build/server/ddsimp-server" --bind 127.0.0.1 --port "$port" --http-port "$http_port" \
    --data-dir "$data_dir/store" --log-level warn ${DDSIMP_LOAD_SERVER_FLAGS:-} \
    >"$data_dir/server.log" 2>&1 &
server=$!
cleanup() {
    kill "$server" 2>/dev/null || true
    wait "$server" 2>/dev/null || true
    rm -rf "$data_dir"
}
trap cleanup EXIT
for _ in $(seq 300); do
    if python3 -c "import socket; socket.create_connection(('127.0.0.1', $port), 1)" 2>/dev/null
    then break; fi
    sleep 0.1
done
status=0
"$build/bench/load/ddsimp-load" --server "127.0.0.1:$port" --http-port "$http_port" \
    --server-pid "$server" "$@" || status=$?
if grep -q . "$data_dir/server.log"; then
    echo "server log (warnings and errors):"
    tail -20 "$data_dir/server.log"
fi
exit "$status"
