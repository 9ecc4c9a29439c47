#!/usr/bin/env bash
# Installs the Debian packages tricell needs for building, testing, the command line, the
# fixtures, the benchmarks and the documentation site. Idempotent: installs only what is missing, and runs
# `apt-get update` once, only when something is missing. Nothing is downloaded at build time.
set -euo pipefail

packages=(
    cmake g++ make
    ccache                     # scripts/test.sh: rebuilds compile only what changed
    libeigen3-dev              # tricell::core
    googletest libgtest-dev libgmock-dev
    libbenchmark-dev
    libsymspg-dev gemmi-dev tao-pegtl-dev libstb-dev   # tricell::io (spglib, gemmi)
    python3-pymatgen python3-ase python3-numpy          # fixtures and peer benchmarks
    clang-format
    gfortran                   # the Fortran module and its tests
    pybind11-dev python3-dev python3-pytest   # the Python module and its tests
    python3-venv python3-setuptools python3-wheel python3-build   # the sdist, the wheel, a venv
    python3-pybind11           # the wheel's build requirement pybind11, as a Python package
    python3-mdanalysis         # tricell.mdanalysis and its comparisons with MDAnalysis
    python3-torch libtorch-dev   # tricell.torch (the PyTorch op library) and its tests
    libopenmpi-dev openmpi-bin # tricell::mpi and its multi-rank tests
    clang-14 libclang-rt-14-dev   # libFuzzer harnesses
    libcairo2-dev              # plots (SVG and PNG)
    libfontconfig-dev          # plots: emptying its caches before exit (LeakSanitizer)
    python3-sphinx python3-myst-parser python3-breathe python3-sphinx-rtd-theme doxygen
                               # the documentation site (docs/CMakeLists.txt)
    chromium python3-websocket # the site read in headless Chromium (tests/docs/site_test.py)
)

missing=()
for package in "${packages[@]}"; do
    if ! dpkg-query -W -f='${Status}' "$package" 2>/dev/null | grep -q "install ok installed"; then
        missing+=("$package")
    fi
done

if [ ${#missing[@]} -eq 0 ]; then
    echo "install-deps: all ${#packages[@]} packages present"
    exit 0
fi

sudo_cmd=()
if [ "$(id -u)" -ne 0 ]; then
    sudo_cmd=(sudo)
fi
echo "install-deps: installing ${missing[*]}"
"${sudo_cmd[@]}" apt-get update -qq
DEBIAN_FRONTEND=noninteractive "${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}"
