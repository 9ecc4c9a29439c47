#!/usr/bin/env bash
# The long fuzzing campaign (tests/fuzz/README.md). Builds the harnesses in build-fuzz/, then runs
# each one in turn as a single in-process job (no -jobs/-fork: the machine is shared), until it has executed RUNS inputs
# (default 10^7) or SECONDS have passed. Each starts from its corpus in tests/fuzz/corpus/<name>/
# and its regression inputs in tests/fuzz/regressions/<name>/, and keeps what it finds in
# build-fuzz/campaign/<name>/ (corpus/, artifacts/, log); the source tree is only read
# (scripts/fuzz-minimise.sh folds the finds into the corpus). At the end one line per harness:
# executions, exec/s (wall clock), exec per CPU second (user + system time of the process, the
# rate that counts on a shared machine), cov, ft, corpus size and the crash, timeout and OOM
# artifacts found. Each harness runs with the flags of tests/fuzz/<name>.flags, if any;
# TRICELL_FUZZ_EXTRA adds libFuzzer flags (e.g. -seed=7).
#
#   scripts/fuzz-campaign.sh [SECONDS_PER_HARNESS [HARNESS...]]
#   e.g. scripts/fuzz-campaign.sh 600 poscar xyz        (default: 3600 s; all harnesses)
#   TRICELL_FUZZ_RUNS=1000000 nice -n 10 taskset -c 1 scripts/fuzz-campaign.sh 3600 search
set -euo pipefail
cd "$(dirname "$0")/.."
seconds="${1:-3600}"
shift || true
harnesses=("$@")
if [ ${#harnesses[@]} -eq 0 ]; then
    harnesses=(poscar xyz cif search cli c_api)
fi
runs="${TRICELL_FUZZ_RUNS:-10000000}"
read -r -a extra <<<"${TRICELL_FUZZ_EXTRA:-}"

bash scripts/fuzz-build.sh
summary=()
for name in "${harnesses[@]}"; do
    # Absolute paths: cli_fuzzer works in a scratch directory of its own.
    dir="$PWD/build-fuzz/campaign/$name"
    mkdir -p "$dir/corpus" "$dir/artifacts"
    seeds=("$PWD/tests/fuzz/corpus/$name")
    if [ -d "tests/fuzz/regressions/$name" ]; then
        seeds+=("$PWD/tests/fuzz/regressions/$name")
    fi
    dict=()
    if [ -f "tests/fuzz/$name.dict" ]; then
        dict=("-dict=$PWD/tests/fuzz/$name.dict")
    fi
    flags=()
    if [ -f "tests/fuzz/$name.flags" ]; then # the harness's flags for mutating runs
        mapfile -t flags < <(grep '^-' "tests/fuzz/$name.flags")
    fi
    echo "== $name: up to $runs runs or $seconds s ${flags[*]}"
    status=0
    /usr/bin/time -f '%U %S' -o "$dir/cpu" \
        "build-fuzz/tests/fuzz/${name}_fuzzer" -rss_limit_mb=2048 -timeout=10 -close_fd_mask=3 \
        -runs="$runs" -max_total_time="$seconds" -print_final_stats=1 "${flags[@]}" "${extra[@]}" \
        "${dict[@]}" -artifact_prefix="$dir/artifacts/" "$dir/corpus" "${seeds[@]}" \
        >"$dir/log" 2>&1 || status=$?
    executed=$(grep -o 'stat::number_of_executed_units: *[0-9]*' "$dir/log" | tail -1 | grep -o '[0-9]*$' || echo "?")
    speed=$(grep -o 'stat::average_exec_per_sec: *[0-9]*' "$dir/log" | tail -1 | grep -o '[0-9]*$' || echo "?")
    cpu=$(awk '/^[0-9.]+ [0-9.]+$/ {print $1 + $2}' "$dir/cpu" | tail -1)
    per_cpu=$(awk -v n="$executed" -v c="${cpu:-0}" 'BEGIN {if (c > 0 && n ~ /^[0-9]+$/) printf "%.0f", n / c; else print "?"}')
    last=$(grep -E '^#[0-9]+' "$dir/log" | tail -1 || true)
    cov=$(echo "$last" | grep -o 'cov: [0-9]*' | grep -o '[0-9]*' || echo "?")
    ft=$(echo "$last" | grep -o 'ft: [0-9]*' | grep -o '[0-9]*' || echo "?")
    corpus=$(echo "$last" | grep -o 'corp: [^ ]*' | cut -d' ' -f2 || echo "?")
    found=$(ls "$dir/artifacts" | tr '\n' ' ')
    line="$name: executions $executed, exec/s $speed, CPU s ${cpu:-?}, exec per CPU s $per_cpu, cov $cov, ft $ft, corpus $corpus, exit $status, artifacts: ${found:-none}"
    echo "$line"
    summary+=("$line")
done
echo "== campaign summary"
printf '%s\n' "${summary[@]}"
