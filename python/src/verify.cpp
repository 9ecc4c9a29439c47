// tricell.verify: any code's neighbour list (numpy arrays i, j, S and optionally d, D, e.g.
// from ASE's neighbor_list("ijSdD", ...)) checked by tricell::verify, and its report as
// tricell.VerifyReport. The arrays follow the argument rules of arguments.hpp; the search for the
// reference runs without the GIL.
#include <cstdint>
#include <string>
#include <vector>

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <tricell/neighbor_list.hpp>
#include <tricell/verify.hpp>

#include "arguments.hpp"

namespace tricell::python {

namespace {

VerifyReport verify_arrays(const py::handle& points, const py::handle& box, const py::handle& i,
                           const py::handle& j, const py::handle& shifts,
                           const py::handle& distances, const py::handle& vectors,
                           const py::object& cutoff, const py::handle& radii,
                           const py::handle& species, bool half, const py::handle& periodic,
                           int threads, std::size_t max_pairs, const py::object& max_bytes) {
    const DoubleArray x = points_array(points);
    const Box search_box = box_from_rows(box, periodic);
    const auto n = static_cast<std::size_t>(x.shape(0));
    NeighborOptions options;
    set_cutoff(cutoff, options);
    if (cutoff.is_none() == radii.is_none()) {
        throw py::value_error(radii.is_none() ? "verify needs cutoff= (a number or a dict of "
                                                "species pairs) or radii="
                                              : "give cutoff= or radii=, not both");
    }
    if (options.species_cutoffs.empty() != species.is_none()) {
        throw py::value_error(species.is_none()
                                  ? "species= is needed with a cutoff dict of species pairs"
                                  : "species= is only for a cutoff dict of species pairs");
    }
    if (!radii.is_none()) {
        const DoubleArray r = per_atom_array(radii, n, "radii");
        options.radii.assign(r.data(), r.data() + n);
    }
    if (!species.is_none()) {
        options.species = per_atom_species(species, n);
    }
    options.half = half;
    options.threads = threads;
    options.max_pairs = max_pairs;
    options.max_bytes = max_bytes_argument(max_bytes);

    const std::vector<std::int64_t> first = index_array(i, "i", -1, 1, nullptr);
    const auto rows = static_cast<py::ssize_t>(first.size());
    const std::vector<std::int64_t> second = index_array(j, "j", rows, 1, "i");
    std::vector<std::int64_t> s;
    if (!shifts.is_none()) {
        s = index_array(shifts, "S", rows, 3, "i");
    }
    DoubleArray d, v;
    if (!distances.is_none()) {
        d = pair_value_array(distances, "d", rows, 1, "i");
    }
    if (!vectors.is_none()) {
        v = pair_value_array(vectors, "D", rows, 3, "i");
    }
    const PairArrays arrays{first.size(),
                            first.data(),
                            second.data(),
                            shifts.is_none() ? nullptr : s.data(),
                            distances.is_none() ? nullptr : d.data(),
                            vectors.is_none() ? nullptr : v.data()};
    if (arrays.shifts == nullptr && search_box.periodicity().any() && arrays.size > 0) {
        throw py::value_error("S= is needed: the box is periodic, and a pair is (i, j, S)");
    }
    py::gil_scoped_release release;
    return verify(search_box, PointsView(x.data(), n), options, arrays);
}

} // namespace

void bind_verify(py::module_& m) {
    py::class_<VerifyReport>(m, "VerifyReport",
                             "The verdict of tricell.verify: ok, the counts of each kind of "
                             "difference, and message (\"ok: ...\" or the first difference in "
                             "words). True when ok.")
        .def_readonly("ok", &VerifyReport::ok, "True when the list is right.")
        .def_readonly("entries", &VerifyReport::entries, "Entries of the list examined.")
        .def_readonly("expected", &VerifyReport::expected, "Pairs the reference found.")
        .def_readonly("matched", &VerifyReport::matched, "Entries that matched a reference pair.")
        .def_readonly("near_cutoff", &VerifyReport::near_cutoff,
                      "Pairs within rounding of their cutoff, accepted either way.")
        .def_readonly("missing", &VerifyReport::missing, "Reference pairs the list lacks.")
        .def_readonly("extra", &VerifyReport::extra, "Listed pairs that are not pairs.")
        .def_readonly("duplicates", &VerifyReport::duplicates,
                      "Entries repeating a pair (in a half list: in either orientation).")
        .def_readonly("rule_breaks", &VerifyReport::rule_breaks,
                      "Entries with an index out of range, (i, i, 0) or a shift along an open "
                      "axis.")
        .def_readonly("wrong_values", &VerifyReport::wrong_values,
                      "Entries whose d or D differs from the one of the positions.")
        .def_readonly("reference", &VerifyReport::reference,
                      "The independent method: \"brute force\", \"the dense backend\" or \"the "
                      "hash backend\".")
        .def_readonly("message", &VerifyReport::message,
                      "\"ok: ...\" or the first difference in words.")
        .def("__bool__", [](const VerifyReport& r) { return r.ok; })
        .def("__repr__", [](const VerifyReport& r) {
            return std::string("<tricell.VerifyReport ") + (r.ok ? "" : "FAILED: ") + r.message +
                   ">";
        });
    m.def("verify", &verify_arrays, py::arg("points"), py::arg("box"), py::arg("i"), py::arg("j"),
          py::arg("S") = py::none(), py::arg("d") = py::none(), py::arg("D") = py::none(),
          py::kw_only(), py::arg("cutoff") = py::none(), py::arg("radii") = py::none(),
          py::arg("species") = py::none(), py::arg("half") = false, py::arg("periodic") = true,
          py::arg("threads") = 1, py::arg("max_pairs") = NeighborOptions().max_pairs,
          py::arg("max_bytes") = py::none(),
          "Checks the neighbour list (i, j, S) of points in box (lattice vectors as rows; "
          "periodic: one bool or three), from any code (ASE's neighbor_list(\"ijSdD\", ...) "
          "arrays, for instance), against an independent search: brute force while N^2 times "
          "the images per pair stays within 2^26 distance tests, else a backend other than the "
          "automatic choice. cutoff is a number or a dict {(species a, species b): cutoff} "
          "(then species= is needed), or radii= gives per-atom radii (a pair counts when "
          "d < radii[i] + radii[j]). A full list (half=False) must hold both orientations of "
          "every pair with d < cutoff, a half list either orientation of each pair exactly "
          "once; no (i, i, 0), S = 0 along open axes, d = |D| and D = points[j] - points[i] + "
          "S @ box when given (pairs within rounding of their cutoff may be in or out). S may be "
          "None only when no axis is periodic. Returns a VerifyReport (true when ok) whose "
          "message names the first difference; bad arguments raise TypeError or ValueError.");
}

} // namespace tricell::python
