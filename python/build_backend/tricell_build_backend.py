"""The build backend of the Python package: setuptools' own (setuptools.build_meta), which runs
setup.py and so CMake, plus one build requirement decided at build time.

CMake is a build requirement, as the PyPI package `cmake`, only when no CMake of at least the
version CMakeLists.txt asks for (cmake_minimum_required) is on PATH: an isolated build
(`pip install .`, `python -m build`) then fetches it from the index, and a machine with its
own CMake (Debian's, say) builds with that one and needs no download. scikit-build-core
decides the same way. Everything else comes from setuptools.build_meta unchanged; the static
requirements (setuptools, pybind11) are in pyproject.toml.
"""
import re
import shutil
import subprocess
from pathlib import Path

from setuptools import build_meta as _setuptools
from setuptools.build_meta import *  # noqa: F401,F403 (the hooks this module does not change)


def _version(text):
    return tuple(int(part) for part in text.split("."))


def _cmake_requirements():
    """["cmake>=X.Y"] when no cmake >= X.Y (CMakeLists.txt's minimum) is on PATH, else []."""
    text = Path("CMakeLists.txt").read_text()
    match = re.search(r"cmake_minimum_required\(\s*VERSION\s+([0-9]+(?:\.[0-9]+)*)", text)
    if not match:
        raise RuntimeError("no 'cmake_minimum_required(VERSION x.y)' in CMakeLists.txt")
    minimum = match.group(1)
    cmake = shutil.which("cmake")
    if cmake:
        try:
            output = subprocess.run([cmake, "--version"], capture_output=True, text=True,
                                    check=True).stdout
        except (OSError, subprocess.CalledProcessError):
            output = ""
        found = re.search(r"cmake version ([0-9]+(?:\.[0-9]+)*)", output)
        if found and _version(found.group(1)) >= _version(minimum):
            return []
    return [f"cmake>={minimum}"]


def get_requires_for_build_wheel(config_settings=None):
    return _setuptools.get_requires_for_build_wheel(config_settings) + _cmake_requirements()


def get_requires_for_build_editable(config_settings=None):
    return _setuptools.get_requires_for_build_editable(config_settings) + _cmake_requirements()
