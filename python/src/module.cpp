// The native module tricell._tricell: registers the bindings and translates tricell's
// exceptions. A malformed or unreadable file (tricell::ParseError) becomes OSError, any other
// bad value (InvalidArgument, GeometryError) ValueError, each with the C++ message unchanged.
#include <pybind11/pybind11.h>

#include <tricell/error.hpp>

namespace tricell::python {

namespace py = pybind11;

void bind_neighbors(py::module_& m);
void bind_read(py::module_& m);
void bind_analysis(py::module_& m);

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
        } catch (const tricell::Error& e) {
            PyErr_SetString(PyExc_ValueError, e.what());
        }
    });
    tricell::python::bind_neighbors(m);
    tricell::python::bind_read(m);
    tricell::python::bind_analysis(m);
}
