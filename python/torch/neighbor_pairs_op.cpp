// torch.ops.tricell.neighbor_pairs: tricell's neighbour search as a TorchScript custom op.
//
// The op takes N x 3 positions, a 3 x 3 cell with the lattice vectors as rows (float32 or
// float64, CPU, one dtype for both), three periodicity flags, a cutoff, full/half, whether to
// group the pairs by increasing i and the k nearest within the cutoff (max_neighbors,
// tie_tolerance, symmetric: NeighborOptions' fields), and returns the pairs (i, j, S) as int64
// tensors: i and j of N_pairs entries, S of N_pairs x 3, with D = x_j - x_i + S @ cell shorter
// than the cutoff. It runs tricell::compute_neighbors on detached float64 copies of the inputs,
// so it records nothing for autograd and its outputs are integers; tricell.torch computes D and
// d from them (the op pair_vectors), which is where gradients flow. Every argument is checked here,
// and a message names the argument and what it got; the library's own errors (a non-finite
// position, a singular cell, a pair limit) come through as RuntimeError with the library's message.
#include <cstdint>
#include <tuple>

#include <torch/library.h>
#include <torch/types.h>

#include <tricell/box.hpp>
#include <tricell/error.hpp>
#include <tricell/neighbor_list.hpp>

#include "op_arguments.hpp"
#include "output_tensor.hpp"

namespace {

using namespace tricell::torch_ops; // op_arguments.hpp

std::tuple<at::Tensor, at::Tensor, at::Tensor>
neighbor_pairs(const at::Tensor& positions, const at::Tensor& cell, const c10::List<bool>& periodic,
               double cutoff, bool full, bool grouped, int64_t max_neighbors, double tie_tolerance,
               bool symmetric) {
    const Structure structure = structure_of("neighbor_pairs", positions, cell, periodic);
    check_cutoff("neighbor_pairs", cutoff);
    tricell::NeighborOptions options;
    options.cutoff = cutoff;
    options.half = !full;
    options.grouped = grouped;
    set_nearest("neighbor_pairs", options, max_neighbors, tie_tolerance, symmetric);
    options.quantities.shifts = true;
    options.quantities.distances = false;
    options.quantities.vectors = false;

    // One list per thread, kept between calls: its buffers are reused, as a NeighborList's are.
    thread_local tricell::NeighborList list;
    try {
        tricell::compute_neighbors(structure.box(), structure.points(), options, list);
    } catch (const tricell::Error& error) {
        TORCH_CHECK(false, "neighbor_pairs: ", error.what());
    }

    const auto pairs = static_cast<std::int64_t>(list.size());
    at::Tensor i = output_tensor({pairs}, at::kLong);
    at::Tensor j = output_tensor({pairs}, at::kLong);
    at::Tensor shifts = output_tensor({pairs, 3}, at::kLong);
    std::int64_t* i_out = i.data_ptr<std::int64_t>();
    std::int64_t* j_out = j.data_ptr<std::int64_t>();
    std::int64_t* s_out = shifts.data_ptr<std::int64_t>();
    const auto& s_in = list.shifts();
    for (std::size_t k = 0; k < list.size(); ++k) {
        i_out[k] = list.i()[k];
        j_out[k] = list.j()[k];
        for (std::size_t axis = 0; axis < 3; ++axis) {
            s_out[3 * k + axis] = s_in[3 * k + axis];
        }
    }
    return {i, j, shifts};
}

} // namespace

TORCH_LIBRARY(tricell, m) {
    m.def("neighbor_pairs(Tensor positions, Tensor cell, bool[] periodic, float cutoff, "
          "bool full=True, bool grouped=False, int max_neighbors=0, float tie_tolerance=0., "
          "bool symmetric=False) -> (Tensor i, Tensor j, Tensor S)",
          &neighbor_pairs);
}
