#!/usr/bin/env bash
# The load run in one command: starts the release ddsimp-server on free loopback ports with an
# empty data directory, runs ddsimp-load against it (N clients x M operations; its flags are
# passed on), reports the server's peak memory and counters, and stops the server.
#
# Usage: bench/load/run.sh [ddsimp-load flags...]
#        e.g. bench/load/run.sh --surface bench/data/carotid-1m.vtp -n 16 -m 50
#        bench/load/run.sh --hostile --surface bench/data/carotid-1m.vtp --keeps 0.1
#          (every attack at once: the server gets a token, TLS with a certificate made for the
#          run, logs at info level and the limits of $hostile_flags below unless
#          DDSIMP_LOAD_SERVER_FLAGS is set; its log is checked)
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
hostile=0
for arg in "$@"; do [[ "$arg" == --hostile ]] && hostile=1; done
if ((hostile)); then
    # Limits sized so that the documented memory total (docs/operations.md#memory) means
    # something on a small machine, the cache large enough to hold the carotid's record (about
    # 75 MB); the upload timeout short enough to expire during the attack.
    # The largest surface is the carotid (1.18 M triangles, 61 MB raw).
    hostile_flags="--max-clients 128 --max-frame-bytes 1048576 --max-queue-mb 32
        --max-queue-total-mb 256 --max-download-mb 64 --cache-mb 256 --surfaces-mb 64
        --max-upload-mb 256
        --max-surface-mb 64 --max-surface-triangles 1200000 --max-remembered-kb 4096
        --upload-timeout 20 --handshake-timeout 5"
    # TLS on both ports with a throw-away certificate: the attackers speak TLS, and some stop
    # halfway through the handshake.
    tls_dir=$(mktemp -d)
    openssl req -x509 -newkey rsa:2048 -nodes -days 1 -subj /CN=localhost \
        -keyout "$tls_dir/key.pem" -out "$tls_dir/cert.pem" 2>/dev/null
    server_flags="${DDSIMP_LOAD_SERVER_FLAGS:-$hostile_flags} --tls-cert $tls_dir/cert.pem
        --tls-key $tls_dir/key.pem"
    set -- --tls "$@"
    server_log_level=info
    DDSIMP_TOKEN=${DDSIMP_TOKEN:-$(python3 -c 'import secrets; print(secrets.token_hex(16))')}
    export DDSIMP_TOKEN
fi
# shellcheck source=bench/start-server.sh
. "$root/bench/start-server.sh"
if ((hostile)); then trap 'stop_server; rm -rf "$tls_dir"' EXIT; fi
status=0
"$build/bench/load/ddsimp-load" --server "127.0.0.1:$port" --http-port "$http_port" \
    --server-pid "$server" --server-log "$data_dir/server.log" "$@" || status=$?
if ((hostile)); then
    echo "server log: $(wc -l <"$data_dir/server.log") lines; the last warnings:"
    grep -a -E '^[^ ]+ (warning|error|critical) ' "$data_dir/server.log" | tail -5 || true
elif grep -q . "$data_dir/server.log"; then
    echo "server log (warnings and errors):"
    tail -20 "$data_dir/server.log"
fi
exit "$status"
