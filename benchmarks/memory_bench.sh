#!/usr/bin/env bash
# Peak resident memory of 10^7-atom searches against the memory model (docs/memory.md): full and
# half on 1 and 2 threads, a search whose pairs would pass max_pairs and one whose memory would
# pass max_bytes (below max_pairs: 4e8 pairs with D, about 21 GB), both refused before they
# allocate. One search per process. Usage: benchmarks/memory_bench.sh BUILD_DIR [CASE...], CASE
# one of fits, half, grouped, sorted, threads, max_pairs, max_bytes (default: all).
set -euo pipefail
bench="${1:-build}/benchmarks/memory_bench"
shift || true
cases=("${@:-fits half grouped sorted threads max_pairs max_bytes}")
for c in ${cases[*]}; do
    case "$c" in
        fits) "$bench" --atoms 1e7 --cutoff 5 --threads 1 ;;
        half) "$bench" --atoms 1e7 --cutoff 5 --threads 1 --half ;;
        grouped) "$bench" --atoms 1e7 --cutoff 5 --threads 1 --grouped ;;
        sorted) "$bench" --atoms 1e7 --cutoff 5 --threads 1 --sorted ;;
        threads)
            "$bench" --atoms 1e7 --cutoff 5 --threads 2
            "$bench" --atoms 1e7 --cutoff 5 --threads 2 --half
            ;;
        max_pairs) "$bench" --atoms 1e7 --cutoff 14 ;;
        # 4.0e8 pairs of i, j, S, d, D: under max_pairs, over three quarters of 24 GiB.
        max_bytes) "$bench" --atoms 1e7 --cutoff 6.6 --quantities ijSdD ;;
        *) echo "memory_bench.sh: unknown case $c" >&2; exit 2 ;;
    esac
done
