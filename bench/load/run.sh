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

server_flags=${DDSIMP_LOAD_SERVER_FLAGS:-}
# shellcheck source=bench/start-server.sh
. "$root/bench/start-server.sh"
status=0
"$build/bench/load/ddsimp-load" --server "127.0.0.1:$port" --http-port "$http_port" \
    --server-pid "$server" "$@" || status=$?
if grep -q . "$data_dir/server.log"; then
    echo "server log (warnings and errors):"
    tail -20 "$data_dir/server.log"
fi
exit "$status"
