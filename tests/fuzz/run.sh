#!/usr/bin/env bash
# Builds every fuzz target with clang's libFuzzer, AddressSanitizer and UBSan (in build/fuzz), then
# fuzzes each for SECONDS, starting from its committed corpus (tests/fuzz/corpus/<target>).
# New inputs go to build/fuzz/corpus/<target>, crashing inputs to build/fuzz/crashes/<target>/,
# each target's log to build/fuzz/logs/<target>.log. Exits non-zero if any target crashed.
#
#   tests/fuzz/run.sh SECONDS [TARGET...]     e.g. tests/fuzz/run.sh 60 frame server_stream
#
# DDSIMP_FUZZ_JOBS=N fuzzes N targets at a time (default 1); DDSIMP_FUZZ_BUILD=DIR builds in DIR
# instead of build/fuzz (so that several people can fuzz from one work tree).
set -euo pipefail
cd "$(dirname "$0")/../.."

seconds=${1:?usage: tests/fuzz/run.sh SECONDS [TARGET...]}
shift
build=${DDSIMP_FUZZ_BUILD:-build/fuzz}
jobs=${DDSIMP_FUZZ_JOBS:-1}
sanitize="-fsanitize=fuzzer-no-link,address,undefined -fno-sanitize-recover=undefined"

command -v clang++ >/dev/null || { echo "run.sh: clang++ not found (scripts/install-deps.sh)" >&2; exit 2; }
cmake -S . -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo \
    -DCMAKE_C_COMPILER=clang -DCMAKE_CXX_COMPILER=clang++ \
    -DDDSIMP_FUZZ=ON -DDDSIMP_BUILD_BENCH=OFF -DDDSIMP_BUILD_MPI=OFF \
    "-DCMAKE_C_FLAGS=$sanitize -fno-omit-frame-pointer" \
    "-DCMAKE_CXX_FLAGS=$sanitize -fno-omit-frame-pointer" \
    "-DCMAKE_EXE_LINKER_FLAGS=-fsanitize=address,undefined" >/dev/null
targets=("$@")
if [[ ${#targets[@]} -gt 0 ]]; then # only the targets named
    cmake --build "$build" -j 2 --target "${targets[@]/#/fuzz_}"
else
    cmake --build "$build" --target fuzz_targets -j 2
    for bin in "$build"/tests/fuzz/fuzz_*; do targets+=("${bin##*/fuzz_}"); done
fi

export UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
# One target: fuzz it, then print a summary line.
fuzz_one() {
    local t=$1 bin="$build/tests/fuzz/fuzz_$1" seeds="tests/fuzz/corpus/$1"
    local work="$build/corpus/$t" crashes="$build/crashes/$t/" log="$build/logs/$t.log"
    [[ -x $bin ]] || { echo "$t: no such target" >&2; return 2; }
    mkdir -p "$work" "$crashes" "$build/logs" "$seeds"
    local status=0
    "$bin" -max_total_time="$seconds" -timeout=60 -print_final_stats=1 \
        -artifact_prefix="$crashes" "$work" "$seeds" >"$log" 2>&1 || status=$?
    local execs cov
    execs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -n 1)
    cov=$(grep -o 'cov: [0-9]* ft: [0-9]*' "$log" | tail -n 1)
    if [[ $status -eq 0 ]]; then
        echo "$t: ok, ${execs:-?} executions in ${seconds} s, ${cov:-no coverage line}"
    else
        echo "$t: CRASHED (status $status), see $log and $crashes"
    fi
    return $status
}

failed=0
running=0
for t in "${targets[@]}"; do
    if [[ $jobs -le 1 ]]; then
        fuzz_one "$t" || failed=1
        continue
    fi
    fuzz_one "$t" &
    running=$((running + 1))
    if [[ $running -ge $jobs ]]; then
        wait -n || failed=1
        running=$((running - 1))
    fi
done
while [[ $running -gt 0 ]]; do
    wait -n || failed=1
    running=$((running - 1))
done
exit $failed
