"""Builds the Python package with CMake, for pip and python3 -m build (see pyproject.toml).

setuptools knows one extension, tricell._tricell; building it configures this repository with
CMake for the running interpreter (only the library, tricell::io and the Python module, plus the
PyTorch op when PyTorch is found), builds it, and installs CMake's `python` component into
setuptools' build directory. So the files of the package are the ones python/CMakeLists.txt
lists, whichever way it is installed, and the version is CMake's project version.

pybind11 comes from the pybind11 Python package when it is importable (a build requirement,
so an isolated build has it), else from CMake's own search. $CMAKE_ARGS adds configure options,
as for scikit-build: CMAKE_ARGS=-DTRICELL_BUILD_IO=OFF builds without gemmi and spglib (and so
without tricell.read). The build directory is build-pip/ in the source tree, or
$TRICELL_PIP_BUILD_DIR; a second build there is incremental. $CMAKE_BUILD_PARALLEL_LEVEL sets
the parallel jobs (default: every core).
"""
import os
import re
import shlex
import shutil
import subprocess
import sys
from pathlib import Path

from setuptools import Extension, setup
from setuptools.command.build_ext import build_ext

ROOT = Path(__file__).resolve().parent
BUILD_BASE = Path(os.environ.get("TRICELL_PIP_BUILD_DIR", ROOT / "build-pip")).resolve()


def pybind11_options():
    try:
        import pybind11
    except ImportError:
        return []
    return [f"-Dpybind11_DIR={pybind11.get_cmake_dir()}"]


def cmake_project_version():
    text = (ROOT / "CMakeLists.txt").read_text()
    match = re.search(r"project\(\s*tricell\s+VERSION\s+([0-9][0-9.]*)", text)
    if not match:
        raise RuntimeError(f"no 'project(tricell VERSION x.y.z' in {ROOT / 'CMakeLists.txt'}")
    return match.group(1)


class CMakeBuild(build_ext):
    def build_extension(self, ext):
        # The package directory: where setuptools expects tricell/_tricell<suffix>.
        package_parent = Path(self.get_ext_fullpath(ext.name)).resolve().parent.parent
        # Only what CMake installs now: no file left over from an earlier build.
        shutil.rmtree(package_parent / "tricell", ignore_errors=True)
        cmake_dir = BUILD_BASE / "cmake"
        os.environ.setdefault("CMAKE_BUILD_PARALLEL_LEVEL", str(os.cpu_count() or 1))
        subprocess.run(["cmake", "-S", str(ROOT), "-B", str(cmake_dir),
                        "-DCMAKE_BUILD_TYPE=Release",
                        f"-DPython3_EXECUTABLE={sys.executable}",
                        f"-DTRICELL_PYTHON_INSTALL_DIR={package_parent}",
                        "-DTRICELL_BUILD_PYTHON=ON", "-DTRICELL_BUILD_IO=ON", "-DBUILD_SHARED_LIBS=OFF",
                        "-DTRICELL_BUILD_TESTS=OFF", "-DTRICELL_BUILD_EXAMPLES=OFF",
                        "-DTRICELL_BUILD_CLI=OFF",
                        "-DTRICELL_BUILD_BENCHMARKS=OFF", "-DTRICELL_BUILD_MPI=OFF",
                        "-DTRICELL_BUILD_FORTRAN=OFF", "-DTRICELL_INSTALL=OFF",
                        *pybind11_options(), *shlex.split(os.environ.get("CMAKE_ARGS", ""))],
                       check=True)
        subprocess.run(["cmake", "--build", str(cmake_dir)], check=True)
        subprocess.run(["cmake", "--install", str(cmake_dir), "--component", "python"],
                       check=True)


BUILD_BASE.mkdir(parents=True, exist_ok=True)
# setuptools adds the files listed in an existing egg-info's SOURCES.txt to the sdist: a file
# since dropped from MANIFEST.in would stay. Each run starts without that list.
(BUILD_BASE / "tricell.egg-info" / "SOURCES.txt").unlink(missing_ok=True)
setup(
    version=cmake_project_version(),
    packages=[],
    ext_modules=[Extension("tricell._tricell", sources=[])],
    cmdclass={"build_ext": CMakeBuild},
    options={"build": {"build_base": str(BUILD_BASE)},
             "egg_info": {"egg_base": str(BUILD_BASE)}},
    zip_safe=False,
)
