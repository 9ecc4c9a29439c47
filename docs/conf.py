"""Sphinx configuration of tricell's documentation site (built by the `docs` target of CMake).

The source directory is the repository root, so the pages of docs/ keep the relative links
they have on GitHub, also those to benchmarks/README.md and tests/fuzz/; `include_patterns`
names the pages. CMake passes what the build made through the environment: the Doxygen XML of
the headers (TRICELL_DOXYGEN_XML), the built Python package (PYTHONPATH) and the `tricell`
command (TRICELL_CLI).
"""
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "_ext"))

project = "tricell"
author = "the tricell authors"
copyright = "the tricell authors"
release = version = os.environ.get("TRICELL_VERSION", "")

extensions = [
    "myst_parser",
    "breathe",
    "sphinx.ext.autodoc",
    "tricell_docs",
]

root_doc = "docs/index"
source_suffix = {".md": "markdown"}
include_patterns = [
    "docs/**.md",
    "benchmarks/README.md",
    "examples/mpi_md/README.md",
    "tests/fuzz/README.md",
    "tests/fuzz/RESULTS.md",
]
exclude_patterns = [".git", "build*"]

# Markdown: anchors for the headings of every level the pages link to (`cpp.md#verlet-lists`).
myst_heading_anchors = 4
myst_enable_extensions = ["dollarmath"]

# The C++ and C API, from Doxygen's XML of include/.
breathe_projects = {"tricell": os.environ.get("TRICELL_DOXYGEN_XML", "")}
breathe_default_project = "tricell"
breathe_domain_by_extension = {"h": "c", "hpp": "cpp"}

# The Python API, from the docstrings of the built package.
autodoc_member_order = "bysource"
autodoc_typehints = "signature"

# Every reference must resolve (-n), except to the types of other libraries, which this site
# does not document.
nitpicky = True
nitpick_ignore_regex = [
    # The namespaces are scopes, not documented entities; Shift is Eigen's Vector3i. Private
    # names Doxygen does not extract appear in initialisers and base classes.
    (r"cpp:identifier", r"tricell(::(io|mpi))?|Shift::Zero|default_neighbors|detail(::.*)?"),
    (r"cpp:identifier", r"Eigen(::.*)?|MPI_Comm"),
    (r"c:identifier", r"u?int32_t|size_t"),
    (r"py:class", r"numpy\.ndarray|torch\.Tensor"),
]

# The root of the site sends a browser on to the landing page, docs/index.html.
html_extra_path = ["site-root"]
html_theme = "sphinx_rtd_theme"
html_title = "tricell"
html_favicon = "_static/tricell.svg"
html_show_sourcelink = False
html_theme_options = {"navigation_depth": 3}
