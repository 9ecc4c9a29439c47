// tricell.neighbor_shells: the lists of several cutoffs from one search (include/tricell/
// analysis/shells.hpp) behind numpy. The pairs come ordered by shell, so the list at cutoffs[k]
// is the prefix [0, offsets[k + 1]) of every column; the columns are views of the result (or
// copies), as NeighborList.compute gives them. tricell.neighbor_lists builds the requests of
// machine-learning models (a cutoff and full or half each) on it.
#include <memory>
#include <string>
#include <vector>

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <tricell/analysis/shells.hpp>

#include "arguments.hpp"
#include "columns.hpp"

namespace tricell::python {

namespace {

py::tuple neighbor_shells(const py::handle& points, const py::handle& box,
                          const py::handle& periodic, const std::vector<double>& cutoffs,
                          const std::string& quantities, bool full, int threads, bool copy) {
    const DoubleArray x = points_array(points);
    const Box search_box = box_from_rows(box, periodic);
    const QuantitySpec spec = parse_quantities(quantities);
    if (spec.offsets) {
        throw py::value_error("quantity 'o' (per-atom offsets) does not apply to lists ordered by "
                              "shell (quantities='" +
                              quantities + "')");
    }
    NeighborOptions options;
    options.half = !full;
    options.threads = threads;
    options.quantities = spec.stored;
    const auto n = static_cast<std::size_t>(x.shape(0));
    auto shells = std::make_shared<ShellNeighborList>();
    {
        py::gil_scoped_release release;
        *shells = compute_neighbors(search_box, PointsView(x.data(), n), cutoffs, options);
    }
    py::array_t<std::int64_t> offsets(static_cast<py::ssize_t>(shells->offsets.size()));
    for (std::size_t k = 0; k < shells->offsets.size(); ++k) {
        offsets.mutable_data()[k] = static_cast<std::int64_t>(shells->offsets[k]);
    }
    // Views hold the whole result through an aliasing pointer to its list.
    const std::shared_ptr<const NeighborList> list(shells, &shells->pairs);
    py::object columns = pair_columns(shells->pairs, spec, copy ? nullptr : list);
    py::tuple out(1 + spec.columns.size());
    out[0] = offsets;
    for (std::size_t k = 0; k < spec.columns.size(); ++k) {
        out[k + 1] = spec.columns.size() == 1 ? columns : py::object(columns.cast<py::tuple>()[k]);
    }
    return out;
}

} // namespace

void bind_shells(py::module_& m) {
    m.def("neighbor_shells", &neighbor_shells, py::arg("points"), py::arg("box"),
          py::arg("periodic"), py::arg("cutoffs"), py::arg("quantities") = "ijSd",
          py::arg("full") = true, py::arg("threads") = 1, py::arg("copy") = true, R"doc(
The lists at several cutoffs (finite, > 0, strictly increasing) from one search at the
largest, for N x 3 points and a 3 x 3 box (rows are lattice vectors). Returns (offsets,
*columns): the pairs ordered by shell, offsets (int64, len(cutoffs) + 1) such that the list at
cutoffs[k] is the prefix [:offsets[k + 1]] of every column, holding exactly the pairs, d and D
of NeighborList(cutoffs[k], full).compute() (in the order of the shells, each in the search's
order). The letters are those of compute() but 'o'; copy=False returns views.)doc");
}

} // namespace tricell::python
