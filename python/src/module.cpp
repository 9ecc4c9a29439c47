// The native module tricell._tricell: registers the bindings and translates tricell's
// exceptions. A malformed or unreadable file (tricell::ParseError) becomes OSError, any other
// bad value (InvalidArgument, GeometryError) ValueError, each with the C++ message unchanged,
// except that a refused pair or memory limit (PairLimitError) names the keyword argument
// max_pairs or max_bytes.
#include <string>
#include <vector>

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <tricell/error.hpp>
#include <tricell/neighbor_list.hpp>

#include "arguments.hpp"

namespace tricell::python {

namespace py = pybind11;

void bind_neighbors(py::module_& m);
void bind_displacement(py::module_& m);
void bind_read(py::module_& m);
void bind_analysis(py::module_& m);
void bind_verify(py::module_& m);
void bind_shells(py::module_& m);

} // namespace tricell::python

PYBIND11_MODULE(_tricell, m) {
    namespace py = pybind11;
    m.doc() = "tricell: periodic neighbour search in triclinic boxes (native part)";
    py::register_exception_translator([](std::exception_ptr p) {
        try {
            if (p) {
                std::rethrow_exception(p);
            }
        } catch (const tricell::ParseError& e) {
            PyErr_SetString(PyExc_OSError, e.what());
        } catch (const tricell::PairLimitError& e) {
            // The limit as a Python caller sets it: the keyword argument max_pairs or max_bytes.
            const std::string keyword =
                e.which() == tricell::PairLimitError::Limit::bytes ? "max_bytes" : "max_pairs";
            const std::string text = e.message_for(keyword + " = " + e.limit_text(), keyword);
            PyErr_SetString(PyExc_ValueError, text.c_str());
        } catch (const tricell::Error& e) {
            PyErr_SetString(PyExc_ValueError, e.what());
        }
    });
    m.attr("__version__") = TRICELL_PYTHON_VERSION;
    m.def(
        "backends",
        [] {
            std::vector<std::string> names;
            for (const tricell::SearchBackend backend : tricell::search_backends()) {
                names.push_back(tricell::backend_name(backend));
            }
            return names;
        },
        "The names backend= takes, \"auto\" first, from the library's table of backends.");
    m.def("_as_array", &tricell::python::checked_array, py::arg("value"), py::arg("name"),
          py::arg("rule"),
          "value converted by the rules every array argument of this module follows, its "
          "TypeError or ValueError naming name: rule \"points\" (N x 3 float64), \"box\" "
          "(3 x 3 float64), \"real\" (float64, any shape), \"species\" (1-D int32) or "
          "\"periodic\" (3 bools). For the drop-ins, which name their own arguments.");
    m.def(
        "_completed_box",
        [](const py::handle& box, const py::handle& periodic) {
            const Eigen::Matrix3d rows =
                tricell::python::box_from_rows(box, periodic).matrix().transpose();
            py::array_t<double> out({3, 3});
            for (int r = 0; r < 3; ++r) {
                for (int c = 0; c < 3; ++c) {
                    out.mutable_at(r, c) = rows(r, c);
                }
            }
            return out;
        },
        py::arg("box"), py::arg("periodic"),
        "The box the library searches in, rows as lattice vectors: box with the vectors of open "
        "axes completed where they cannot serve (a zero one, or open vectors that do not span "
        "with the others, by unit vectors orthogonal to the others). For the drop-ins, which hand "
        "the box to ASE's own "
        "geometry.");
    tricell::python::bind_neighbors(m);
    tricell::python::bind_displacement(m);
    tricell::python::bind_read(m);
    tricell::python::bind_analysis(m);
    tricell::python::bind_verify(m);
    tricell::python::bind_shells(m);
}
