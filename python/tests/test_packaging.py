"""The build requirements of the Python package: pyproject.toml's static ones, and the in-tree
backend's CMake, asked for only when no CMake of at least CMakeLists.txt's minimum is on PATH
(python/tests/wheel_from_sdist.sh builds the sdist and the wheel themselves)."""
import os
import re
import sys

import pytest

from conftest import SOURCE_DIR

tomllib = pytest.importorskip("tomllib")  # Python 3.11


@pytest.fixture
def backend(monkeypatch):
    monkeypatch.chdir(SOURCE_DIR)  # where a build runs the backend
    monkeypatch.syspath_prepend(os.path.join(SOURCE_DIR, "python", "build_backend"))
    sys.modules.pop("tricell_build_backend", None)
    import tricell_build_backend

    return tricell_build_backend


def minimum_cmake():
    text = open(os.path.join(SOURCE_DIR, "CMakeLists.txt")).read()
    return re.search(r"cmake_minimum_required\(VERSION ([0-9.]+)\)", text).group(1)


def test_pyproject_declares_the_backend_and_its_requirements():
    with open(os.path.join(SOURCE_DIR, "pyproject.toml"), "rb") as f:
        pyproject = tomllib.load(f)
    system = pyproject["build-system"]
    assert system["build-backend"] == "tricell_build_backend"
    assert system["backend-path"] == ["python/build_backend"]
    assert any(r.startswith("setuptools") for r in system["requires"]), system
    assert any(r.startswith("pybind11") for r in system["requires"]), system
    project = pyproject["project"]
    assert project["license"] == {"text": "BSD-3-Clause"}
    assert any(r.startswith("numpy") for r in project["dependencies"]), project


def fake_cmake(directory, version):
    path = directory / "cmake"
    path.write_text(f"#!/bin/sh\necho 'cmake version {version}'\n")
    path.chmod(0o755)
    return str(directory)


@pytest.mark.parametrize("hook", ["get_requires_for_build_wheel",
                                  "get_requires_for_build_editable"])
def test_cmake_is_a_requirement_only_without_a_recent_enough_cmake(backend, hook, monkeypatch,
                                                                   tmp_path):
    requirement = f"cmake>={minimum_cmake()}"
    # setuptools runs setup.py (egg_info) to answer: its build directory goes to tmp_path.
    monkeypatch.setenv("TRICELL_PIP_BUILD_DIR", str(tmp_path / "build"))
    for version, needed in [("3.99.1", False), ("3.10.2", True), (None, True)]:
        bin_dir = tmp_path / f"bin-{version}"  # a cmake of that version, or none at all
        bin_dir.mkdir()
        monkeypatch.setenv("PATH", fake_cmake(bin_dir, version) if version else str(bin_dir))
        requires = getattr(backend, hook)()
        assert (requirement in requires) == needed, (version, requires)
    assert backend.get_requires_for_build_sdist() == []  # an sdist builds nothing
