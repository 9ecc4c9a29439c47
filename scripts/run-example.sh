#!/usr/bin/env bash
# The quick start's main job: installs what is missing, builds the `tricell` command and lists
# the neighbours of the bundled quartz structure within 3 Angstrom. With arguments, runs
# `tricell ARGS...` instead (e.g. scripts/run-example.sh info examples/data/quartz.cif).
set -euo pipefail
cd "$(dirname "$0")/.."

bash scripts/install-deps.sh >&2
cmake -S . -B build -DCMAKE_BUILD_TYPE=RelWithDebInfo >/dev/null
cmake --build build -j "${TRICELL_JOBS:-2}" --target tricell >/dev/null
if [ $# -eq 0 ]; then
    set -- neighbors examples/data/quartz.cif --cutoff 3 --sorted
fi
./build/cli/tricell "$@"
