#!/usr/bin/env bash
# The quick start's main job: installs what is missing, builds tricell and runs it on a
# bundled example structure. Extra arguments are passed to the program.
set -euo pipefail
cd "$(dirname "$0")/.."

bash scripts/install-deps.sh >&2
cmake -S . -B build -DCMAKE_BUILD_TYPE=RelWithDebInfo >/dev/null
cmake --build build -j "${TRICELL_JOBS:-2}" --target box_info >/dev/null
./build/examples/box_info "${@:-examples/data/sheared.box}"
