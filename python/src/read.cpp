// tricell.read(path): a structure file (CIF, POSCAR, extended XYZ) through tricell::io.
//
// Returns the plain pieces the Python side wraps in tricell.Structure: lattice vectors as rows
// (3 x 3), Cartesian positions (N x 3), element symbols, periodicity (three bools),
// occupancies and labels. What each format means is documented in tricell/io/structure.hpp;
// nothing is reinterpreted here. Without tricell::io in the build, read() raises OSError.
#include <string>
#include <vector>

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#ifdef TRICELL_PYTHON_HAS_IO
#include <tricell/io/structure.hpp>
#endif

namespace tricell::python {

namespace py = pybind11;

namespace {

py::tuple read(const std::string& path, const std::string& format) {
#ifdef TRICELL_PYTHON_HAS_IO
    io::ReadOptions options;
    if (!format.empty()) {
        options.format = io::parse_format(format);
    }
    io::Structure s;
    {
        py::gil_scoped_release release;
        s = io::read_structure(path, options);
    }
    py::array_t<double> cell(std::vector<py::ssize_t>{3, 3});
    auto c = cell.mutable_unchecked<2>();
    for (int r = 0; r < 3; ++r) {
        for (int k = 0; k < 3; ++k) {
            c(r, k) = s.box.matrix()(k, r); // row r = lattice vector r = column r of H
        }
    }
    const auto n = static_cast<py::ssize_t>(s.size());
    py::array_t<double> positions(std::vector<py::ssize_t>{n, 3});
    auto p = positions.mutable_unchecked<2>();
    for (py::ssize_t a = 0; a < n; ++a) {
        for (int k = 0; k < 3; ++k) {
            p(a, k) = s.positions[static_cast<std::size_t>(a)][k];
        }
    }
    py::array_t<double> occupancies(n);
    std::copy(s.occupancies.begin(), s.occupancies.end(), occupancies.mutable_data());
    const auto& axes = s.box.periodicity().axes;
    return py::make_tuple(cell, positions, s.species, py::make_tuple(axes[0], axes[1], axes[2]),
                          occupancies, s.labels);
#else
    (void)format;
    const std::string message =
        path + ": cannot read files, this tricell module was built without tricell::io";
    PyErr_SetString(PyExc_OSError, message.c_str());
    throw py::error_already_set();
#endif
}

} // namespace

void bind_read(py::module_& m) {
    m.def("_read", &read, py::arg("path"), py::arg("format") = "",
          "The fields of tricell.Structure as a tuple; tricell.read is the public call.");
}

} // namespace tricell::python
