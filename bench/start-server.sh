# Sourced by the service benchmarks (bench/service/run.sh, bench/load/run.sh): starts
# "$build/server/ddsimp-server" on two free loopback ports with an empty data directory, with the
# extra flags in $server_flags (split into words) and the log level $server_log_level (warn), and waits until it listens. Sets port, http_port, server (its
# pid) and data_dir (server.log is there); the server is stopped and data_dir removed on exit.
# shellcheck shell=bash disable=SC2154,SC2086 # build is set by the script that sources this; flags split

free_port() {
    python3 -c 'import socket; s = socket.socket(); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])'
}
port=$(free_port)
http_port=$(free_port)
data_dir=$(mktemp -d)
"$build/server/ddsimp-server" --bind 127.0.0.1 --port "$port" --http-port "$http_port" \
    --data-dir "$data_dir/store" --log-level "${server_log_level:-warn}" ${server_flags:-} >"$data_dir/server.log" 2>&1 &
server=$!
stop_server() {
    kill "$server" 2>/dev/null || true
    wait "$server" 2>/dev/null || true
    rm -rf "$data_dir"
}
trap stop_server EXIT
for _ in $(seq 300); do
    if python3 -c "import socket; socket.create_connection(('127.0.0.1', $port), 1)" 2>/dev/null; then
        break
    fi
    sleep 0.1
done
