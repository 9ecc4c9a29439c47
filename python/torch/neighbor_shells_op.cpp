// torch.ops.tricell.neighbor_shells: the pairs of several cutoffs from one search, as a
// TorchScript custom op (tricell::compute_neighbors with a list of cutoffs,
// include/tricell/analysis/shells.hpp).
//
// The op takes what neighbor_pairs takes, with strictly increasing cutoffs instead of one, and
// returns the pairs (i, j, S) of the largest ordered by shell with the shell offsets
// (len(cutoffs) + 1, int64): the pairs within cutoffs[k] are the prefix [0, offsets[k + 1]),
// exactly those neighbor_pairs gives at cutoffs[k]. Like neighbor_pairs it records nothing for
// autograd; tricell.torch computes D and d from the pairs.
#include <cstdint>
#include <tuple>
#include <vector>

#include <torch/library.h>
#include <torch/types.h>

#include <tricell/analysis/shells.hpp>
#include <tricell/error.hpp>

#include "op_arguments.hpp"
#include "output_tensor.hpp"

namespace {

using namespace tricell::torch_ops; // op_arguments.hpp

constexpr const char* op = "neighbor_shells";

std::tuple<at::Tensor, at::Tensor, at::Tensor, at::Tensor>
neighbor_shells(const at::Tensor& positions, const at::Tensor& cell,
                const c10::List<bool>& periodic, const c10::List<double>& cutoffs, bool full) {
    const Structure structure = structure_of(op, positions, cell, periodic);
    tricell::NeighborOptions options;
    options.half = !full;
    options.quantities.shifts = true;
    options.quantities.distances = false;
    options.quantities.vectors = false;
    const std::vector<double> radii(cutoffs.begin(), cutoffs.end());
    tricell::ShellNeighborList shells;
    try {
        shells = tricell::compute_neighbors(structure.box(), structure.points(), radii, options);
    } catch (const tricell::Error& error) {
        TORCH_CHECK(false, op, ": ", error.what());
    }
    const tricell::NeighborList& list = shells.pairs;
    const auto pairs = static_cast<std::int64_t>(list.size());
    at::Tensor i = output_tensor({pairs}, at::kLong);
    at::Tensor j = output_tensor({pairs}, at::kLong);
    at::Tensor shifts = output_tensor({pairs, 3}, at::kLong);
    at::Tensor offsets = output_tensor({std::int64_t(shells.offsets.size())}, at::kLong);
    for (std::size_t k = 0; k < list.size(); ++k) {
        i.data_ptr<std::int64_t>()[k] = list.i()[k];
        j.data_ptr<std::int64_t>()[k] = list.j()[k];
    }
    for (std::size_t k = 0; k < 3 * list.size(); ++k) {
        shifts.data_ptr<std::int64_t>()[k] = list.shifts()[k];
    }
    for (std::size_t k = 0; k < shells.offsets.size(); ++k) {
        offsets.data_ptr<std::int64_t>()[k] = std::int64_t(shells.offsets[k]);
    }
    return {i, j, shifts, offsets};
}

} // namespace

TORCH_LIBRARY_FRAGMENT(tricell, m) {
    m.def("neighbor_shells(Tensor positions, Tensor cell, bool[] periodic, float[] cutoffs, "
          "bool full=True) -> (Tensor i, Tensor j, Tensor S, Tensor offsets)",
          &neighbor_shells);
}
