#!/usr/bin/env bash
# The long random campaign (tests/property/random_campaign_test.cpp): runs the Mixed test of
# random_campaign_test RUNS times, each with a fresh seed and SYSTEMS systems, and prints each
# run's seed and counts, then the totals of systems, pairs compared and oracle-checked systems.
# A failure names its seed and system index; the test prints the line that replays it.
#
#   scripts/random-campaign.sh [RUNS [SYSTEMS]]     (default: 10 runs of 200 systems)
#   TRICELL_CAMPAIGN_BINARY=build-asan/tests/random_campaign_test scripts/random-campaign.sh 2 20
set -euo pipefail
cd "$(dirname "$0")/.."
runs="${1:-10}"
systems="${2:-200}"
binary="${TRICELL_CAMPAIGN_BINARY:-build/tests/random_campaign_test}"
if [ ! -x "$binary" ]; then
    echo "no $binary: build it first (cmake --build build --target random_campaign_test)" >&2
    exit 2
fi
total_systems=0 total_pairs=0 total_oracle=0 failed=0
for ((run = 1; run <= runs; ++run)); do
    seed=$(od -An -N8 -tu8 /dev/urandom | tr -d ' ')
    status=0
    out=$(TRICELL_CAMPAIGN_SEED="$seed" TRICELL_CAMPAIGN_SYSTEMS="$systems" \
        "$binary" --gtest_filter=RandomCampaign.Mixed 2>&1) || status=$?
    line=$(grep '^\[campaign\]' <<<"$out" || true)
    echo "run $run: ${line:-[campaign] no summary}"
    if [ "$status" -ne 0 ]; then
        failed=$((failed + 1))
        grep -E 'Failure|replay with|differs|oracle|missing|not in' <<<"$out" | head -20
    fi
    if [[ $line =~ systems\ ([0-9]+),\ pairs\ compared\ ([0-9]+),\ oracle-checked\ systems\ ([0-9]+) ]]; then
        total_systems=$((total_systems + BASH_REMATCH[1]))
        total_pairs=$((total_pairs + BASH_REMATCH[2]))
        total_oracle=$((total_oracle + BASH_REMATCH[3]))
    fi
done
echo "random campaign: $runs runs, $failed failed; systems $total_systems, pairs compared" \
    "$total_pairs, oracle-checked systems $total_oracle"
[ "$failed" -eq 0 ]
