#!/usr/bin/env bash
# Peak resident memory of 10^7-atom searches against the memory model (docs/memory.md): full and
# half on 1 and 2 threads, and a search whose pairs would pass max_pairs (refused before it
# allocates). One search per process. Usage: benchmarks/memory_bench.sh BUILD_DIR
set -euo pipefail
bench="${1:-build}/benchmarks/memory_bench"
for threads in 1 2; do
    "$bench" --atoms 1e7 --cutoff 5 --threads "$threads"
    "$bench" --atoms 1e7 --cutoff 5 --threads "$threads" --half
done
"$bench" --atoms 1e7 --cutoff 14
