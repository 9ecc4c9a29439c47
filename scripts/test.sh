#!/usr/bin/env bash
# The whole test suite, from a fresh clone: installs what is missing, builds tricell twice
# (optimised, and with AddressSanitizer + UndefinedBehaviorSanitizer), runs every test in
# both (the optimised build's also build the documentation site, build/docs/html, and read it
# in headless Chromium: tests/docs), and checks formatting; builds and runs the threading tests with ThreadSanitizer
# (build-tsan/); then builds the libFuzzer harnesses with clang-14 (build-fuzz/),
# replays their corpora and fuzzes each for a bounded time (tests/fuzz/README.md). Exit status
# non-zero if anything fails.
set -euo pipefail
cd "$(dirname "$0")/.."

jobs="${TRICELL_JOBS:-2}"
bash scripts/install-deps.sh

# Every configure below (and the nested ones: pip's build, the consumer projects) compiles
# through ccache, with paths taken relative to the repository root, so a second run on the same
# machine, from any clone, recompiles only what changed. TRICELL_CCACHE=0 turns it off.
if [ "${TRICELL_CCACHE:-1}" = 1 ] && command -v ccache >/dev/null; then
    export CMAKE_CXX_COMPILER_LAUNCHER=ccache CMAKE_C_COMPILER_LAUNCHER=ccache
    export CCACHE_BASEDIR="$PWD" CCACHE_NOHASHDIR=1
fi

# Optimised builds with line tables only (-g1): symbolised backtraces and sanitizer reports
# name file and line, and the builds compile in two thirds of the time full debug info takes.
optimised=(-DCMAKE_BUILD_TYPE=RelWithDebInfo "-DCMAKE_CXX_FLAGS_RELWITHDEBINFO=-O2 -g1 -DNDEBUG"
           "-DCMAKE_C_FLAGS_RELWITHDEBINFO=-O2 -g1 -DNDEBUG")
export TRICELL_FUZZ_FLAGS="-O2 -g1 -DNDEBUG"

# Each stage's header says how long the run has taken so far.
stage() { echo "== $1 (at $((SECONDS / 60)) min $((SECONDS % 60)) s)"; }

stage "format check"
bash scripts/format-check.sh

stage "optimised build (build/)"
cmake -S . -B build "${optimised[@]}"
cmake --build build -j "$jobs"
ctest --test-dir build -j "$jobs" --output-on-failure

stage "sanitizer build (build-asan/)"
cmake -S . -B build-asan "${optimised[@]}" -DTRICELL_SANITIZE=ON \
    -DTRICELL_BUILD_BENCHMARKS=OFF -DBUILD_SHARED_LIBS=ON
cmake --build build-asan -j "$jobs"
ctest --test-dir build-asan -j "$jobs" --output-on-failure

stage "thread sanitizer (build-tsan/: the threading tests only)"
cmake -S . -B build-tsan "${optimised[@]}" -DTRICELL_SANITIZE_THREAD=ON \
    -DTRICELL_BUILD_BENCHMARKS=OFF -DTRICELL_BUILD_PYTHON=OFF \
    -DTRICELL_BUILD_IO=OFF -DTRICELL_BUILD_MPI=OFF -DTRICELL_BUILD_FORTRAN=OFF \
    -DTRICELL_BUILD_EXAMPLES=OFF
cmake --build build-tsan -j "$jobs" \
    --target parallel_test concurrency_stress_test fork_test c_concurrency_stress_test
ctest --test-dir build-tsan -R 'stress|fork|ThreadTeam' -j "$jobs" --output-on-failure

stage "fuzzers (build-fuzz/, clang-14, ASan + UBSan + libFuzzer)"
bash scripts/fuzz-build.sh
ctest --test-dir build-fuzz -L fuzz -j "$jobs" --output-on-failure
stage "done: every stage passed"
