#!/usr/bin/env bash
# The whole benchmark in one command: builds the release preset, makes the surfaces if missing,
# runs the speed benchmark (5 repetitions, medians) and the memory runs (one fresh process per
# strategy), then prints a Markdown table and writes it to bench/results/latest.md (git-ignored,
# with the raw JSON beside it).
#
# Usage: bench/run.sh [--quick]     (--quick: the ~100 k surface instead of the >= 1 M one)
# Environment:
#   DDSIMP_BENCH_SURFACE    benchmark this surface instead
#   DDSIMP_BENCH_BUILD_DIR  use the programs already built there; skip the preset build
#   DDSIMP_BENCH_REPETITIONS  repetitions of the speed benchmark (default 5)
set -euo pipefail

here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
root=$(dirname "$here")
results="$here/results"

quick=false
case "${1:-}" in
"") ;;
--quick) quick=true ;;
*)
    echo "usage: bench/run.sh [--quick]" >&2
    exit 2
    ;;
esac
for tool in cmake jq; do
    if ! command -v "$tool" >/dev/null; then
        echo "run.sh: needs $tool" >&2
        exit 1
    fi
done

cd "$root"
build="${DDSIMP_BENCH_BUILD_DIR:-}"
if [[ -z "$build" ]]; then
    cmake --preset release
    cmake --build --preset release
    build="$root/build/release"
fi
bench="$build/bench/ddsimp_bench"
memory="$build/bench/ddsimp_bench_memory"

if [[ -n "${DDSIMP_BENCH_SURFACE:-}" ]]; then
    surface="$DDSIMP_BENCH_SURFACE"
elif $quick; then
    surface="$here/data/carotid-100k.vtp"
else
    surface="$here/data/carotid-1m.vtp"
fi
if [[ ! -f "$surface" ]]; then
    if [[ -n "${DDSIMP_BENCH_SURFACE:-}" ]]; then
        echo "run.sh: $surface not found" >&2
        exit 1
    fi
    DDSIMP="$build/tools/ddsimp" "$here/make-data.sh"
fi

mkdir -p "$results"
status=0
repetitions="${DDSIMP_BENCH_REPETITIONS:-5}"
load_before=$(cut -d' ' -f1-3 /proc/loadavg)

echo "run.sh: speed: $bench --surface=$surface" >&2
"$bench" "--surface=$surface" "--benchmark_repetitions=$repetitions" \
    --benchmark_report_aggregates_only=true --benchmark_enable_random_interleaving=true \
    "--benchmark_out=$results/speed.json" --benchmark_out_format=json >&2 || status=1

for strategy in edge vertex; do
    echo "run.sh: memory: $memory $surface --strategy $strategy" >&2
    if ! "$memory" "$surface" --strategy "$strategy" >"$results/memory-$strategy.json"; then
        status=1
    fi
done

# speed FIELD NAME: FIELD of NAME's median in speed.json (of its one run if there was only one
# repetition; "" if absent).
speed() {
    jq -r --arg name "$2" --arg field "$1" \
        '[.benchmarks[] | select(.run_name == $name)
          | select(.error_occurred != true)] as $runs
         | ([$runs[] | select(.aggregate_name == "median")][0]
            // [$runs[] | select(.run_type == "iteration")][0]) | .[$field] // empty' \
        "$results/speed.json" 2>/dev/null || true
}
# speed_error NAME: the error message NAME reported, if any.
speed_error() {
    jq -r --arg name "$1" \
        '[.benchmarks[] | select(.run_name == $name)
          | select(.error_occurred == true)][0].error_message // empty' \
        "$results/speed.json" 2>/dev/null || true
}
# memory FIELD STRATEGY: FIELD of that strategy's memory report ("" if absent).
memory_field() {
    jq -r --arg field "$1" '.[$field] // empty' "$results/memory-$2.json" 2>/dev/null || true
}
# fmt DECIMALS NUMBER: NUMBER rounded to DECIMALS places (thousands grouped when 0), or "—" for
# no number.
fmt() {
    if [[ -z "$2" ]]; then
        printf '—'
    elif (($1 == 0)); then
        LC_ALL=C printf '%.0f' "$2" | sed -E ':a; s/^([0-9]+)([0-9]{3})/\1,\2/; ta'
    else
        LC_ALL=C printf '%.*f' "$1" "$2"
    fi
}
# triangles NAME: "in → reached (target)".
triangles() {
    local in out target
    in=$(speed triangles_in "$1")
    out=$(speed triangles_out "$1")
    target=$(speed target "$1")
    printf '%s → %s (target %s)' "$(fmt 0 "$in")" "$(fmt 0 "$out")" "$(fmt 0 "$target")"
}

base_real=$(speed real_time meshopt_simplify)
row() { # row LABEL NAME STRATEGY
    local label="$1" name="$2" strategy="$3" cpu real ratio="—" mem="—" error
    error=$(speed_error "$name")
    if [[ -n "$error" ]]; then
        printf '| %s | failed: %s | | | | |\n' "$label" "$error"
        return
    fi
    cpu=$(speed cpu_time "$name")
    real=$(speed real_time "$name")
    if [[ -n "$real" && -n "$base_real" ]]; then
        ratio=$(LC_ALL=C awk -v a="$real" -v b="$base_real" 'BEGIN { printf "%.2f", a / b }')
    fi
    if [[ -n "$strategy" ]]; then
        local rss heap
        rss=$(memory_field bytes_per_triangle "$strategy")
        heap=$(memory_field heap_bytes_per_triangle "$strategy")
        if [[ -n "$rss" ]]; then
            mem="$(fmt 0 "$rss") (heap $(fmt 0 "$heap"))"
        else
            mem="failed"
        fi
    fi
    printf '| %s | %s | %s | %s | %s | %s |\n' "$label" "$(fmt 3 "$cpu")" \
        "$(fmt 3 "$real")" "$ratio" "$(triangles "$name")" "$mem"
}

commit=$(git -C "$root" rev-parse --short HEAD 2>/dev/null || echo unknown)
if [[ -n "$(git -C "$root" status --porcelain --untracked-files=no 2>/dev/null)" ]]; then
    commit="$commit + uncommitted changes"
fi
meshopt_version=$(jq -r '.context.meshoptimizer_version // empty | tonumber
    | "\((. / 1000) | floor).\((. % 1000 / 10) | floor)"' "$results/speed.json" 2>/dev/null || true)
cpu_model=$(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2- | sed 's/^ *//')

{
    echo "## ddsimp benchmark, $(date -u '+%Y-%m-%d %H:%M UTC')"
    echo
    echo "- surface: \`${surface#"$root/"}\`, reduced to 10% of its triangles," \
        "α = 0.5, midpoint placement unless a row says otherwise; meshopt on one thread"
    echo "- commit $commit; $cpu_model, $(nproc) cores; load average before: $load_before"
    echo "- time: median of $repetitions repetitions (Google Benchmark, interleaved), process CPU" \
        "seconds and wall seconds; ratio = ddsimp wall / meshopt wall"
    echo "- memory: (peak RSS − RSS before the call) / input triangles, fresh process;" \
        "heap = peak live operator-new bytes / input triangles"
    echo
    echo "| simplifier | median CPU s | median wall s | ratio to meshopt | triangles in → reached | peak bytes / input triangle |"
    echo "|---|---|---|---|---|---|"
    row "meshoptimizer $meshopt_version \`meshopt_simplify\` (geometry only)" meshopt_simplify ""
    for t in 1 2; do
        row "ddsimp EdgeCollapse, $t thread(s)" "ddsimp_EdgeCollapse/threads:$t" \
            "$([[ $t == 1 ]] && echo edge)"
        row "ddsimp EdgeCollapse, least-error placement (the default), $t thread(s)" \
            "ddsimp_EdgeCollapse_LeastError/threads:$t" ""
        row "ddsimp VertexRemoval, $t thread(s)" "ddsimp_VertexRemoval/threads:$t" \
            "$([[ $t == 1 ]] && echo vertex)"
    done
    echo
    # Scaling: wall time on t threads against one, and the serial fraction s that Amdahl's law
    # T(t) = T(1) (s + (1 - s) / t) gives for the two-thread time (beyond the cores, t > nproc,
    # the rows show the cost of the extra threads).
    echo "| threads | EdgeCollapse wall s | speed-up | VertexRemoval wall s | speed-up |"
    echo "|---|---|---|---|---|"
    e1=$(speed real_time "ddsimp_EdgeCollapse_LeastError/threads:1")
    v1=$(speed real_time "ddsimp_VertexRemoval/threads:1")
    for t in 1 2 4 8 16; do
        e=$(speed real_time "ddsimp_EdgeCollapse_LeastError/threads:$t")
        v=$(speed real_time "ddsimp_VertexRemoval/threads:$t")
        LC_ALL=C awk -v t="$t" -v e="$e" -v v="$v" -v e1="$e1" -v v1="$v1" 'BEGIN {
            printf "| %d | %.3f | %.2f | %.3f | %.2f |\n", t, e, e1 / e, v, v1 / v }'
    done
    for pair in "EdgeCollapse_LeastError:$e1" "VertexRemoval:$v1"; do
        two=$(speed real_time "ddsimp_${pair%%:*}/threads:2")
        LC_ALL=C awk -v n="${pair%%:*}" -v a="${pair#*:}" -v b="$two" 'BEGIN {
            printf "\nSerial fraction (%s, from 2 threads): %.2f", n, 2 * b / a - 1 }'
    done
    echo
    echo
    reproduce="bench/run.sh$($quick && echo ' --quick')"
    if [[ -n "${DDSIMP_BENCH_SURFACE:-}" ]]; then
        reproduce="DDSIMP_BENCH_SURFACE=${surface#"$root/"} $reproduce"
    fi
    echo "Reproduce: \`$reproduce\`"
} | tee "$results/latest.md"

exit "$status"
