#!/usr/bin/env bash
# Configures and builds the libFuzzer harnesses in build-fuzz/ with clang-14 (ASan + UBSan +
# libFuzzer coverage on every tricell target). Used by scripts/test.sh and
# scripts/fuzz-campaign.sh.
set -euo pipefail
cd "$(dirname "$0")/.."
# $TRICELL_FUZZ_FLAGS replaces the optimised build's flags (scripts/test.sh: line tables only).
flags=()
if [ -n "${TRICELL_FUZZ_FLAGS:-}" ]; then
    flags=("-DCMAKE_CXX_FLAGS_RELWITHDEBINFO=$TRICELL_FUZZ_FLAGS")
fi
cmake -S . -B build-fuzz -DCMAKE_BUILD_TYPE=RelWithDebInfo "${flags[@]}" -DCMAKE_CXX_COMPILER=clang++-14 \
    -DTRICELL_SANITIZE=ON -DTRICELL_BUILD_FUZZERS=ON -DTRICELL_BUILD_TESTS=OFF \
    -DTRICELL_BUILD_BENCHMARKS=OFF >/dev/null
cmake --build build-fuzz -j "${TRICELL_JOBS:-2}" --target tricell_fuzzers
