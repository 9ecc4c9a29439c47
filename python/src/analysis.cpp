// tricell.Rdf and tricell.nearest_neighbors: the analysis of tricell::core (include/tricell/
// analysis/) behind numpy. Inputs go through the shared argument checks (arguments.hpp), results
// come back as fresh numpy arrays; the GIL is released while a frame is histogrammed or the
// neighbours are searched.
#include <string>
#include <vector>

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <tricell/analysis/nearest.hpp>
#include <tricell/analysis/rdf.hpp>

#include "arguments.hpp"

namespace tricell::python {

namespace {

py::array_t<double> to_numpy(const std::vector<double>& values) {
    return py::array_t<double>(py::ssize_t(values.size()), values.data());
}

py::tuple curve_tuple(const RdfCurve& curve) {
    return py::make_tuple(to_numpy(curve.r), to_numpy(curve.g), to_numpy(curve.n));
}

Rdf make_rdf(double rmax, std::size_t bins, int threads, const std::string& backend) {
    RdfOptions options;
    options.rmax = rmax;
    options.bins = bins;
    options.threads = threads;
    options.backend = parse_backend(backend);
    return Rdf(options);
}

void add_frame(Rdf& rdf, const py::handle& points, const py::handle& box,
               const py::handle& periodic, const py::handle& species) {
    const DoubleArray x = points_array(points);
    const Box frame_box = box_from_rows(box, periodic);
    const auto n = static_cast<std::size_t>(x.shape(0));
    const std::vector<std::int32_t> kinds =
        species.is_none() ? std::vector<std::int32_t>{} : per_atom_species(species, n);
    py::gil_scoped_release release;
    rdf.add_frame(frame_box, PointsView(x.data(), n), kinds);
}

py::tuple nearest(const py::handle& points, const py::handle& box, const py::handle& periodic,
                  std::size_t k, int threads, const std::string& backend) {
    const DoubleArray x = points_array(points);
    const Box search_box = box_from_rows(box, periodic);
    const auto n = static_cast<std::size_t>(x.shape(0));
    const NearestOptions options{threads, parse_backend(backend)};
    NearestNeighbors result;
    {
        py::gil_scoped_release release;
        result = nearest_neighbors(search_box, PointsView(x.data(), n), k, options);
    }
    const auto rows = py::ssize_t(n);
    const auto cols = py::ssize_t(k);
    py::array_t<std::uint32_t> j({rows, cols}, result.j.data());
    py::array_t<std::int32_t> shifts({rows, cols, py::ssize_t(3)}, result.shifts.data());
    py::array_t<double> d({rows, cols}, result.distances.data());
    return py::make_tuple(j, shifts, d);
}

} // namespace

void bind_analysis(py::module_& m) {
    py::class_<Rdf>(m, "Rdf", R"doc(
Radial distribution function g(r) over every periodic image (rmax may exceed the cell),
accumulated frame by frame: bins of width rmax / bins over [0, rmax), exact shell volumes,
total g normalised with N * N / V (ASE's get_rdf, freud's exact mode), partial g_AB with
N_A * N_B / V (ASE's elements= normalises with N_A * N / V: its value is ours times N_B / N),
and the running coordination number n(r) at each bin's upper edge. Every axis must be
periodic. Curves are plain averages over the frames, which may differ in cell and atom count; a
partial averages over the frames that hold both species.)doc")
        .def(py::init(&make_rdf), py::arg("rmax"), py::arg("bins"), py::arg("threads") = 1,
             py::arg("backend") = "auto")
        .def("add_frame", &add_frame, py::arg("points"), py::arg("box"), py::arg("periodic") = true,
             py::arg("species") = py::none(),
             R"doc(
Adds one frame: N x 3 Cartesian points, a 3 x 3 box with the lattice vectors as rows, and
optionally N non-negative integer species (atomic numbers, say). A refused frame changes
nothing.)doc")
        .def_property_readonly("frames", &Rdf::frames, "The number of frames added so far.")
        .def_property_readonly(
            "edges", [](const Rdf& rdf) { return to_numpy(rdf.edges()); },
            "The bins + 1 bin edges, 0 to rmax.")
        .def_property_readonly("species", &Rdf::species,
                               "The species seen in the frames, ascending.")
        .def(
            "total", [](const Rdf& rdf) { return curve_tuple(rdf.total()); },
            "(r, g, n): bin centres, g(r) and n(r) averaged over the frames.")
        .def(
            "partial",
            [](const Rdf& rdf, std::int32_t a, std::int32_t b) {
                return curve_tuple(rdf.partial(a, b));
            },
            py::arg("a"), py::arg("b"),
            "(r, g_AB, n_AB): n_AB is the mean number of B neighbours of an A atom within r.");

    m.def("nearest_neighbors", &nearest, py::arg("points"), py::arg("box"),
          py::arg("periodic") = true, py::arg("k") = 1, py::arg("threads") = 1,
          py::arg("backend") = "auto", R"doc(
The k nearest neighbours (j, S) of every atom over periodic images (k may exceed N): returns
j (uint32, N x k), S (int32, N x k x 3) and d (float64, N x k), nearest first, ties broken by
j then S.)doc");
}

} // namespace tricell::python
