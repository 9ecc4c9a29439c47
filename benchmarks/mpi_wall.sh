#!/usr/bin/env bash
# Wall-clock steps/s of mpi_md against the serial md_lj, interleaved runs, one pinned core per
# process, the median of each: 1 rank against md_lj at 4 000 and 32 000 atoms, 2 ranks against
# 1 rank at 32 000 (strong scaling). As the bound for that ratio, two serial md_lj at once at
# 32 000 atoms, one pinned to each core: ranks advance in lock step, so two ranks can go at most
# twice as fast as the slower of two independent copies of the work running side by side (the
# two cores of a virtual machine need not be equally fast). Besides the medians it prints each
# round's 2-rank speed-up as a share of that round's bound. Needs a quiet machine with at least 2
# cores.
#
#   benchmarks/mpi_wall.sh [build dir (build)] [runs (5)] [steps (200)]
set -euo pipefail
build=${1:-build}
runs=${2:-5}
steps=${3:-200}
mpirun_flags=(--allow-run-as-root --bind-to core --map-by core)
rate() { grep -o '[0-9.]* steps/s' | head -1 | cut -d' ' -f1; }
median() { sort -g | awk '{v[NR] = $1} END {print (NR % 2) ? v[(NR + 1) / 2] : (v[NR / 2] + v[NR / 2 + 1]) / 2}'; }
declare -A got
scratch=$(mktemp -d)
trap 'rm -rf "$scratch"' EXIT
for ((r = 0; r < runs; ++r)); do
    for n in 4000 32000; do
        got[md_lj.$n]+="$(taskset -c 0 "$build/examples/md_lj/md_lj" --atoms $n --steps $steps | rate) "
        got[np1.$n]+="$(mpirun "${mpirun_flags[@]}" -np 1 "$build/examples/mpi_md/mpi_md" --atoms $n --steps $steps | rate) "
    done
    got[np2.32000]+="$(mpirun "${mpirun_flags[@]}" -np 2 "$build/examples/mpi_md/mpi_md" --atoms 32000 --steps $steps | rate) "
    taskset -c 0 "$build/examples/md_lj/md_lj" --atoms 32000 --steps $steps >"$scratch/a" &
    taskset -c 1 "$build/examples/md_lj/md_lj" --atoms 32000 --steps $steps >"$scratch/b"
    wait
    got[pair.32000]+="$(cat <(rate <"$scratch/a") <(rate <"$scratch/b") | sort -g | awk 'NR == 1 {print 2 * $1}') "
done
for key in md_lj.4000 np1.4000 md_lj.32000 np1.32000 np2.32000 pair.32000; do
    m=$(tr ' ' '\n' <<<"${got[$key]}" | grep . | median)
    printf '%-12s median %8.2f steps/s  (runs: %s)\n' "$key" "$m" "${got[$key]}"
    declare "med_${key/./_}=$m"
done
awk -v a="$med_md_lj_4000" -v b="$med_np1_4000" -v c="$med_md_lj_32000" -v d="$med_np1_32000" \
    -v e="$med_np2_32000" -v f="$med_pair_32000" 'BEGIN {
    printf "1 rank / md_lj step time: 4 000 atoms %.2fx, 32 000 atoms %.2fx\n", a / b, c / d
    printf "2 ranks / 1 rank speed at 32 000 atoms: %.2fx\n", e / d
    printf "two md_lj at once, twice the slower one / one alone (the bound for 2 ranks): %.2fx\n", f / c }'
# Round by round (the cores' speeds drift between rounds): 2 ranks / 1 rank and its share of the
# round's bound, and the median share.
shares=$(awk -v np1="${got[np1.32000]}" -v np2="${got[np2.32000]}" -v lj="${got[md_lj.32000]}" \
    -v pair="${got[pair.32000]}" 'BEGIN {
    n = split(np1, one); split(np2, two); split(lj, serial); split(pair, bound)
    for (r = 1; r <= n; ++r) printf "%.4f %.4f\n", two[r] / one[r], (two[r] / one[r]) / (bound[r] / serial[r]) }')
printf '2 ranks / 1 rank by round (share of the bound):%s\n' \
    "$(awk '{printf " %.2fx (%.0f%%)", $1, 100 * $2}' <<<"$shares")"
printf 'median share of the bound: %.0f%%\n' "$(cut -d' ' -f2 <<<"$shares" | median | awk '{print 100 * $1}')"
