#!/usr/bin/env bash
# mpirun.sh NP PROGRAM [ARGS...]: runs PROGRAM on NP ranks of this machine, more ranks than cores
# allowed; as root (CI containers) Open MPI also wants --allow-run-as-root.
set -euo pipefail
ranks=$1
shift
extra=()
[[ $(id -u) -eq 0 ]] && extra+=(--allow-run-as-root)
# Under LeakSanitizer (the asan preset): Open MPI is built without frame pointers, so only the slow
# unwinder follows a leak's stack into libmpi, where tests/sanitizers/lsan.supp names it; quietly.
# That unwinder runs at every allocation and makes a rank several times slower, so only a run on
# one rank looks for leaks; on more ranks AddressSanitizer still checks every access, and the
# splitting and stitching code is leak-checked in-process by test_pieces.cpp.
if [[ -n ${LSAN_OPTIONS:-} ]]; then
    if [[ $ranks -eq 1 ]]; then
        export LSAN_OPTIONS="$LSAN_OPTIONS:fast_unwind_on_malloc=0:print_suppressions=0"
    else
        export ASAN_OPTIONS="${ASAN_OPTIONS:+$ASAN_OPTIONS:}detect_leaks=0"
    fi
fi
exec mpirun --oversubscribe "${extra[@]}" -np "$ranks" "$@"
