#!/usr/bin/env bash
# Speed-up of ddsimp-mpi against ranks on a >= 4 M-triangle surface, with single-process
# `ddsimp simplify` as the peer in the same run. Every repetition runs every configuration once,
# interleaved, so that the machine's noise hits them alike; the table shows medians. Each
# configuration's result is also compared with the input once (`ddsimp compare`, data error).
#
# Usage: bench/mpi/run.sh [RANKS...]      (default: 1 2 4)
# Environment:
#   DDSIMP_BUILD_DIR           programs built there (default: build/release)
#   DDSIMP_MPI_BENCH_SURFACE   this surface instead of bench/data/carotid-4m.vtp (made if missing:
#                              isosurface scalars = 127 of the carotid volume resampled 6 times
#                              per axis, 4.7 M triangles)
#   DDSIMP_MPI_BENCH_REPETITIONS  repetitions (default 3)
#   DDSIMP_MPI_BENCH_OPTIONS   simplify options (default: --keep 0.1)
# Writes the table to bench/results/mpi.md and the raw JSON beside it (git-ignored).
set -euo pipefail

here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
root=$(cd "$here/../.." && pwd)
build="${DDSIMP_BUILD_DIR:-$root/build/release}"
ddsimp="$build/tools/ddsimp"
ddsimp_mpi="$build/tools/mpi/ddsimp-mpi"
repetitions="${DDSIMP_MPI_BENCH_REPETITIONS:-3}"
read -r -a options <<<"${DDSIMP_MPI_BENCH_OPTIONS:---keep 0.1}"
ranks=("$@")
[[ ${#ranks[@]} -eq 0 ]] && ranks=(1 2 4)
results="$root/bench/results"
work="$results/mpi"
mkdir -p "$work"

for program in "$ddsimp" "$ddsimp_mpi"; do
    if [[ ! -x "$program" ]]; then
        echo "run.sh: $program not built (set DDSIMP_BUILD_DIR)" >&2
        exit 1
    fi
done
command -v jq >/dev/null || {
    echo "run.sh: needs jq" >&2
    exit 1
}

surface="${DDSIMP_MPI_BENCH_SURFACE:-$root/bench/data/carotid-4m.vtp}"
if [[ ! -f "$surface" ]]; then
    volume="${DDSIMP_SHARED_DATA:-$(cd "$root/.." && pwd)/shared/data}/volumes/carotid.vtk"
    mkdir -p "$(dirname "$surface")"
    "$ddsimp" isosurface "$volume" --field scalars --value 127 --resample 6 -o "$surface"
fi

mpi_flags=(--oversubscribe)
[[ $(id -u) -eq 0 ]] && mpi_flags+=(--allow-run-as-root)

# run CONFIG REPETITION: one run; its JSON report goes to $work/CONFIG-REPETITION.json.
run() {
    local config=$1 repetition=$2 out="$work/$1.vtp"
    if [[ $config == ddsimp ]]; then
        "$ddsimp" simplify "$surface" -o "$out" "${options[@]}" --json >"$work/$config-$repetition.json"
    else
        mpirun "${mpi_flags[@]}" -np "${config#np}" "$ddsimp_mpi" simplify "$surface" -o "$out" \
            "${options[@]}" --json >"$work/$config-$repetition.json"
    fi
}

configs=(ddsimp)
for n in "${ranks[@]}"; do configs+=("np$n"); done
echo "surface: $surface ($(nproc) cores); options: ${options[*]}; $repetitions repetitions" >&2
for ((r = 1; r <= repetitions; ++r)); do
    for config in "${configs[@]}"; do
        echo "  repetition $r: $config" >&2
        run "$config" "$r"
        if [[ $r -eq 1 ]]; then
            "$ddsimp" compare "$surface" "$work/$config.vtp" --json >"$work/$config-compare.json"
        fi
    done
done

median() { sort -g | awk '{v[NR] = $1} END {print (NR % 2) ? v[(NR + 1) / 2] : (v[NR / 2] + v[NR / 2 + 1]) / 2}'; }
seconds_of() { for ((r = 1; r <= repetitions; ++r)); do jq .seconds "$work/$1-$r.json"; done | median; }

peer=$(seconds_of ddsimp)
{
    echo "| run | median s (simplification, without reading/writing) | speed-up vs ddsimp | slowest piece s | final pass s | stitched triangles | triangles out | data RMS error (vectors) |"
    echo "|---|---|---|---|---|---|---|---|"
    for config in "${configs[@]}"; do
        s=$(seconds_of "$config")
        first="$work/$config-1.json"
        piece=$(jq '[.pieces[]?.seconds] | max // "-"' "$first")
        final=$(jq '.final_pass_seconds // "-"' "$first")
        stitched=$(jq '.stitched_triangles // "-"' "$first")
        out=$(jq .triangles_out "$first")
        error=$(jq '[.fields[] | select(.name == "vectors") | .error.symmetric.rms][0] // "-"' \
            "$work/$config-compare.json")
        name=$config
        [[ $config == np* ]] && name="ddsimp-mpi -np ${config#np}"
        printf '| %s | %.2f | %.2f | %s | %s | %s | %s | %s |\n' "$name" "$s" \
            "$(echo "$peer / $s" | bc -l)" "$piece" "$final" "$stitched" "$out" "$error"
    done
} | tee "$results/mpi.md"
