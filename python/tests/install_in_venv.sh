#!/usr/bin/env bash
# Installs the package as its users do, for the tests that run against the installed copy:
# makes VENV (a virtual environment with --system-site-packages, for numpy, ASE, pymatgen and
# PyTorch), runs `pip install --no-build-isolation --no-index SOURCE` in it, then builds a
# wheel with `python3 -m build --no-isolation --wheel` into VENV/dist and checks that it holds
# exactly the files pip installed. BUILD is the package build directory (TRICELL_PIP_BUILD_DIR),
# shared by both, so the wheel is an incremental build.
#   install_in_venv.sh PYTHON SOURCE VENV BUILD
set -euo pipefail
python="$1" source="$2" venv="$3" build="$4"

rm -rf "$venv"
"$python" -m venv --system-site-packages "$venv"
export TRICELL_PIP_BUILD_DIR="$build"
"$venv/bin/python" -m pip install --no-build-isolation --no-index --no-cache-dir -q "$source"
"$venv/bin/python" -m build --no-isolation --wheel --outdir "$venv/dist" "$source" > "$venv/build.log"

cd "$venv"   # a directory that holds no package
"$venv/bin/python" - "$venv" <<'PY'
import glob, os, sys, zipfile
from importlib.metadata import version

import tricell

venv = sys.argv[1]
package = os.path.dirname(tricell.__file__)
assert package.startswith(venv), f"tricell imported from {package}, not from the venv {venv}"
installed = sorted(os.path.relpath(os.path.join(d, f), os.path.dirname(package))
                   for d, _, files in os.walk(package) if "__pycache__" not in d for f in files)
wheels = glob.glob(os.path.join(venv, "dist", "tricell-*.whl"))
assert len(wheels) == 1, wheels
in_wheel = sorted(n for n in zipfile.ZipFile(wheels[0]).namelist() if n.startswith("tricell/"))
assert installed == in_wheel, f"pip installed {installed}, the wheel holds {in_wheel}"
assert any(n.startswith("tricell/_tricell.") and n.endswith(".so") for n in in_wheel), in_wheel
assert version("tricell") == tricell.__version__, (version("tricell"), tricell.__version__)
print(f"install_in_venv: tricell {tricell.__version__}, {len(installed)} files in {package}, "
      f"the same in {os.path.basename(wheels[0])}")
PY
