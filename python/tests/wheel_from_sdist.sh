#!/usr/bin/env bash
# Builds the package as a packager does and installs it as a user does, for the tests that run
# against the installed copy: the sdist of SOURCE (`python3 -m build --sdist`), unpacked into
# WORK/sdist, the wheel built from that unpacked sdist alone, offline (`--no-isolation`: the
# build requirements come from the system, and `build` checks that they are there), and that
# wheel installed into WORK/venv, a fresh virtual environment with --system-site-packages (for
# numpy, ASE, pymatgen, MDAnalysis and PyTorch). Then checks the metadata and that pip installed
# exactly the wheel's files. A file missing from the sdist fails the wheel's build or, if the
# Python tests need it, the tests run from WORK/sdist afterwards.
# WORK/sdist is always the same path, so ccache (with CCACHE_BASEDIR above it, as
# scripts/test.sh sets) reuses the compilations of earlier runs.
#   wheel_from_sdist.sh PYTHON SOURCE WORK
set -euo pipefail
python="$1" source="$2" work="$3"

rm -rf "$work/dist" "$work/sdist" "$work/venv"
mkdir -p "$work/dist" "$work/sdist"
"$python" -m build --no-isolation --sdist --outdir "$work/dist" "$source" > "$work/sdist.log"
sdist=$(ls "$work"/dist/tricell-*.tar.gz)
tar -xzf "$sdist" -C "$work/sdist"
unpacked=$(ls -d "$work"/sdist/tricell-*/)
"$python" -m build --no-isolation --wheel --outdir "$work/dist" "$unpacked" > "$work/wheel.log"
"$python" -m venv --system-site-packages "$work/venv"
"$work/venv/bin/python" -m pip install --no-index --no-cache-dir -q "$work"/dist/tricell-*.whl

cd "$work/venv"   # a directory that holds no package
"$work/venv/bin/python" - "$work" <<'PY'
import glob, os, sys, tarfile, zipfile
from importlib.metadata import metadata, version

import tricell

work = sys.argv[1]
venv = os.path.join(work, "venv")
package = os.path.dirname(tricell.__file__)
assert package.startswith(venv), f"tricell imported from {package}, not from the venv {venv}"
installed = sorted(os.path.relpath(os.path.join(d, f), os.path.dirname(package))
                   for d, _, files in os.walk(package) if "__pycache__" not in d for f in files)
wheel, = glob.glob(os.path.join(work, "dist", "tricell-*.whl"))
names = zipfile.ZipFile(wheel).namelist()
in_wheel = sorted(n for n in names if n.startswith("tricell/"))
assert installed == in_wheel, f"pip installed {installed}, the wheel holds {in_wheel}"
assert any(n.startswith("tricell/_tricell.") and n.endswith(".so") for n in in_wheel), in_wheel
assert any(n.endswith(".dist-info/LICENSE") for n in names), "the wheel holds no LICENSE"
assert version("tricell") == tricell.__version__, (version("tricell"), tricell.__version__)
meta = metadata("tricell")
assert meta["License"] == "BSD-3-Clause", meta["License"]
assert "License :: OSI Approved :: BSD License" in meta.get_all("Classifier"), meta
assert any(r.startswith("numpy") for r in meta.get_all("Requires-Dist")), meta
sdist, = glob.glob(os.path.join(work, "dist", "tricell-*.tar.gz"))
sdist_files = tarfile.open(sdist).getnames()
print(f"wheel_from_sdist: tricell {tricell.__version__}: {os.path.basename(sdist)} "
      f"({len(sdist_files)} entries), {os.path.basename(wheel)} ({len(in_wheel)} files) "
      f"built from it and installed in {venv}")
PY
