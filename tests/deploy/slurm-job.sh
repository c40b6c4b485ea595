#!/usr/bin/env bash
# Usage: slurm-job.sh ROOT SERVER. Runs deploy/slurm/ddsimp-server.sbatch the way Slurm runs the
# job, with `srun` replaced by a shim that runs its program (there is no Slurm here). The job must
# take the next port pair when the first is in use, write the address file and a private token,
# print the tunnel command, serve /healthz, and remove both files when the server stops.
set -euo pipefail
root=$1
server=$2
work=$(mktemp -d)
pids=()
cleanup() {
    for pid in "${pids[@]}"; do
        pkill -KILL -P "$pid" || true
        { kill -KILL "$pid" && wait "$pid"; } || true
    done 2>/dev/null
    rm -rf "$work"
}
trap cleanup EXIT
fail() {
    echo "FAIL: $*" >&2
    echo "--- job output:" >&2
    cat "$work/job.out" >&2 || true
    exit 1
}

mkdir -p "$work/bin" "$work/home"
cat >"$work/bin/srun" <<'SHIM'
#!/usr/bin/env bash
while [[ "$1" == --* ]]; do shift; done
exec "$@"
SHIM
chmod +x "$work/bin/srun"

# A pair of ports of our own, the first of them taken by another listener. Below Linux's ephemeral
# range (32768 up): there the other tests' servers (port 0) and connections take ports at any
# moment, and one took the job's port between its check and its bind.
base=$((20000 + 2 * (RANDOM % 6000)))
python3 -c "import socket, time
s = socket.socket(); s.bind(('127.0.0.1', $base)); s.listen(); time.sleep(300)" &
pids+=($!)
for _ in $(seq 50); do ss -Htln "sport = :$base" | grep -q . && break; sleep 0.1; done

HOME="$work/home" PATH="$work/bin:$PATH" SLURM_JOB_ID=4242 SLURM_CPUS_PER_TASK=2 \
    DDSIMP_SERVER="$server" DDSIMP_PORT="$base" DDSIMP_HTTP_PORT="$((base + 1))" \
    DDSIMP_LOGIN_HOST=login.example bash "$root/deploy/slurm/ddsimp-server.sbatch" \
    >"$work/job.out" 2>&1 &
job=$!
pids+=("$job")

address="$work/home/.ddsimp/server-4242.address"
token="$work/home/.ddsimp/server-4242.token"
port=$((base + 2))
http_port=$((base + 3))
healthy=false
for _ in $(seq 600); do
    if python3 -c "import urllib.request, sys
sys.exit(urllib.request.urlopen('http://127.0.0.1:$http_port/healthz', timeout=2).status != 200)" 2>/dev/null; then
        healthy=true
        break
    fi
    kill -0 "$job" 2>/dev/null || fail "the job ended before the server answered"
    sleep 0.1
done
$healthy || fail "no answer on /healthz of port $http_port"

node=$(hostname -f 2>/dev/null || hostname)
[[ "$(cat "$address")" == "$node:$port:$http_port" ]] || fail "address file holds '$(cat "$address")'"
[[ "$(stat -c %a "$token")" == 600 ]] || fail "token file mode $(stat -c %a "$token")"
grep -Eq '^[0-9a-f]{64}$' "$token" || fail "token is not 32 random bytes in hex"
grep -qF "ssh -N -L $port:$node:$port -L $http_port:$node:$http_port $(id -un)@login.example" \
    "$work/job.out" || fail "no tunnel command for ports $port and $http_port"
echo "ok: the job took ports $port/$http_port (the pair at $base was in use), wrote its address and token, printed the tunnel"

# The end of the job: Slurm's SIGTERM to the server, then the job's files go.
pkill -TERM -P "$job"
wait "$job" || fail "the job exited with status $?"
[[ ! -e "$address" && ! -e "$token" ]] || fail "the address or token file outlived the job"
echo "ok: SIGTERM stopped the server and the job removed its files"
