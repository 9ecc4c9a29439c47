// tricell.DisplacementTracker: the library's rebuild rule (tricell::DisplacementTracker) for
// Python lists that keep their own candidates, such as the ASE drop-in classes with per-atom
// cutoffs (tricell/_ase_classes.py). The rule and its proof live in
// include/tricell/displacement.hpp; this file only converts arrays.
#include <cmath>
#include <string>

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <tricell/displacement.hpp>

#include "arguments.hpp"

namespace tricell::python {

namespace {

class PyDisplacementTracker {
  public:
    PyDisplacementTracker(double skin, double cutoff) : skin_(skin), cutoff_(cutoff) {
        check_margin(skin, "skin");
        check_margin(cutoff, "cutoff");
    }

    void record(const py::handle& points, const py::handle& box, const py::handle& periodic) {
        const DoubleArray x = points_array(points);
        tracker_.record(box_from_rows(box, periodic), view(x));
    }

    bool needs_rebuild(const py::handle& points, const py::handle& box,
                       const py::handle& periodic) const {
        const DoubleArray x = points_array(points);
        return tracker_.needs_rebuild(box_from_rows(box, periodic), view(x), skin_, cutoff_);
    }

    py::object jumps(const py::handle& points, const py::handle& box,
                     const py::handle& periodic) const {
        const DoubleArray x = points_array(points);
        const Box b = box_from_rows(box, periodic);
        py::array_t<std::int32_t> out({py::ssize_t(x.shape(0)), py::ssize_t(3)});
        if (!tracker_.jumps_since_record(b, view(x), skin_, cutoff_, out.mutable_data())) {
            return py::none();
        }
        return std::move(out);
    }

    double budget(const py::handle& box, const py::handle& periodic) const {
        return tracker_.budget(box_from_rows(box, periodic), skin_, cutoff_);
    }

    double max_displacement(const py::handle& points, const py::handle& box,
                            const py::handle& periodic) const {
        const DoubleArray x = points_array(points);
        return tracker_.max_displacement(box_from_rows(box, periodic), view(x));
    }

    void reset() { tracker_.reset(); }
    bool recorded() const { return tracker_.recorded(); }
    double skin() const { return skin_; }
    double cutoff() const { return cutoff_; }

  private:
    static void check_margin(double value, const char* name) {
        if (!std::isfinite(value) || !(value >= 0)) {
            throw py::value_error(std::string(name) + " must be finite and >= 0 (got " +
                                  std::to_string(value) + ")");
        }
    }

    static PointsView view(const DoubleArray& x) {
        return PointsView(x.data(), static_cast<std::size_t>(x.shape(0)));
    }

    DisplacementTracker tracker_;
    double skin_;
    double cutoff_;
};

} // namespace

void bind_displacement(py::module_& m) {
    py::class_<PyDisplacementTracker>(m, "DisplacementTracker", R"doc(
The library's rebuild rule for a list of candidate pairs built at cutoff + skin.

DisplacementTracker(skin, cutoff): skin is the list's margin beyond the cutoff of every pair,
cutoff the largest cutoff of a pair (both finite, >= 0). After record() of the build's points,
needs_rebuild() is true when the candidates may miss a pair within its cutoff: the atom count
or periodicity changed, or some atom moved (minimum image, in the build's frame) by more than
budget() = (skin - eps * cutoff) / 2, eps the box's strain since the build (skin / 2 for an
unchanged box). The bound is safe: a pair within its cutoff now was within cutoff + skin at
the build.
Points are N x 3 Cartesian, the box 3 x 3 with lattice vectors as rows, periodic one bool or
three.)doc")
        .def(py::init<double, double>(), py::arg("skin"), py::arg("cutoff"))
        .def("record", &PyDisplacementTracker::record, py::arg("points"), py::arg("box"),
             py::arg("periodic") = true, "Makes these points and box the build.")
        .def("needs_rebuild", &PyDisplacementTracker::needs_rebuild, py::arg("points"),
             py::arg("box"), py::arg("periodic") = true,
             "Whether the candidates of the build may miss a pair now (True before record()).")
        .def("jumps", &PyDisplacementTracker::jumps, py::arg("points"), py::arg("box"),
             py::arg("periodic") = true, R"doc(
None when needs_rebuild(); otherwise the lattice jumps k (int32, N x 3) of the atoms since the
build, relative to the points as recorded: a pair (i, j, S) of the build is now (i, j,
S + k[j] - k[i]).)doc")
        .def("budget", &PyDisplacementTracker::budget, py::arg("box"), py::arg("periodic") = true,
             "How far each atom may move since the build in this box (negative: rebuild).")
        .def("max_displacement", &PyDisplacementTracker::max_displacement, py::arg("points"),
             py::arg("box"), py::arg("periodic") = true,
             "Largest displacement of an atom since the build (inf without a compatible build).")
        .def("reset", &PyDisplacementTracker::reset, "Forgets the build.")
        .def_property_readonly("recorded", &PyDisplacementTracker::recorded,
                               "Whether record() has made a build.")
        .def_property_readonly("skin", &PyDisplacementTracker::skin,
                               "The list's margin beyond every pair's cutoff.")
        .def_property_readonly("cutoff", &PyDisplacementTracker::cutoff,
                               "The largest cutoff of a pair.");
}

} // namespace tricell::python
