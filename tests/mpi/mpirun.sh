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
if [[ -n ${LSAN_OPTIONS:-} ]]; then
    export LSAN_OPTIONS="$LSAN_OPTIONS:fast_unwind_on_malloc=0:print_suppressions=0"
fi
exec mpirun --oversubscribe "${extra[@]}" -np "$ranks" "$@"
