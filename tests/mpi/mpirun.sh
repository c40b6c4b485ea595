#!/usr/bin/env bash
# mpirun.sh NP PROGRAM [ARGS...]: runs PROGRAM on NP ranks of this machine, more ranks than cores
# allowed; as root (CI containers) Open MPI also wants --allow-run-as-root.
set -euo pipefail
ranks=$1
shift
extra=()
[[ $(id -u) -eq 0 ]] && extra+=(--allow-run-as-root)
exec mpirun --oversubscribe "${extra[@]}" -np "$ranks" "$@"
