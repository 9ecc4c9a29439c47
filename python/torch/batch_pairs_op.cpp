// torch.ops.tricell.batch_pairs: the neighbour lists of a batch of structures in one call, as a
// TorchScript custom op, in the concatenated layout of machine-learning codes.
//
// The op takes the positions of all structures one after the other (N x 3), one cell per
// structure (B x 3 x 3, lattice vectors as rows; float32 or float64 like the positions, CPU), the
// periodicity of each (B x 3 bools) and the pointer array batch_ptr (B + 1 integers: structure s
// owns rows batch_ptr[s]:batch_ptr[s + 1]), and returns the pairs (i, j, S) of every structure
// as int64 tensors, i and j indexing the concatenated positions, with the per-structure pair
// offsets (B + 1): structure s owns pairs offsets[s]:offsets[s + 1]. It is one call of
// tricell::compute_neighbors_batch (threads across structures) on detached float64 copies of
// the inputs, so each structure gets exactly the pairs of neighbor_pairs on it alone and no pair
// joins two structures; max_neighbors, tie_tolerance and symmetric select the k nearest within
// the cutoff of every structure's centres, as in neighbor_pairs. Like neighbor_pairs it records
// nothing for autograd: tricell.torch computes D and d from the pairs (the op pair_vectors).
// With `shells` (cutoffs, increasing,
// none above the cutoff) the op also gives each pair's shell: the index of the first of them
// above its distance d (len(shells) for d >= the last), by the search's own test d < r, so the
// pairs a search at shells[k] stores are those of shell <= k. Messages name the argument and
// the structure ("batch_pairs: structure 17, cells[17]: ...").
#include <cstdint>
#include <string>
#include <tuple>
#include <vector>

#include <torch/library.h>
#include <torch/types.h>

#include <tricell/batch.hpp>
#include <tricell/error.hpp>

#include "batch_layout.hpp" // python/src: the pointer array's rule, shared with the numpy front
#include "op_arguments.hpp"
#include "output_tensor.hpp"

namespace {

using namespace tricell::torch_ops; // op_arguments.hpp

constexpr const char* op = "batch_pairs";

// batch_ptr as int64 values, checked (one rule with the numpy front: batch_layout.hpp).
std::vector<std::int64_t> pointer_array(const at::Tensor& batch_ptr, std::size_t points) {
    TORCH_CHECK(batch_ptr.dim() == 1, op,
                ": batch_ptr must be a 1-D tensor of B + 1 integers (got "
                "shape ",
                shape_of(batch_ptr), ")");
    TORCH_CHECK(!batch_ptr.is_floating_point() && !batch_ptr.is_complex() &&
                    batch_ptr.scalar_type() != at::kBool,
                op, ": batch_ptr must hold integers (got ", batch_ptr.scalar_type(), ")");
    const at::Tensor ptr = batch_ptr.to(at::kCPU).to(at::kLong).contiguous();
    std::vector<std::int64_t> out(ptr.data_ptr<std::int64_t>(),
                                  ptr.data_ptr<std::int64_t>() + ptr.numel());
    const std::string problem =
        tricell::python::batch_pointer_problem(out.data(), out.size(), points, "batch_ptr");
    TORCH_CHECK(problem.empty(), op, ": ", problem);
    return out;
}

std::tuple<at::Tensor, at::Tensor, at::Tensor, at::Tensor, at::Tensor>
batch_pairs(const at::Tensor& positions, const at::Tensor& cells, const at::Tensor& pbc,
            const at::Tensor& batch_ptr, double cutoff, bool full, int64_t threads,
            const c10::List<double>& shells, int64_t max_neighbors, double tie_tolerance,
            bool symmetric) {
    check_positions_and_cell(op, positions, cells, "cells");
    check_cutoff(op, cutoff);
    const std::vector<std::int64_t> ptr = pointer_array(batch_ptr, std::size_t(positions.size(0)));
    const auto count = static_cast<std::int64_t>(ptr.size() - 1);
    TORCH_CHECK(
        cells.dim() == 3 && cells.size(0) == count && cells.size(1) == 3 && cells.size(2) == 3, op,
        ": cells must be a B x 3 x 3 tensor, one cell per structure of batch_ptr, "
        "the lattice vectors as rows (B = ",
        count, "; got shape ", shape_of(cells), ")");
    TORCH_CHECK(pbc.scalar_type() == at::kBool && pbc.dim() == 2 && pbc.size(0) == count &&
                    pbc.size(1) == 3,
                op, ": pbc must be a B x 3 bool tensor, one row per structure of batch_ptr (B = ",
                count, "; got ", pbc.scalar_type(), " of shape ", shape_of(pbc), ")");
    TORCH_CHECK(threads >= 0, op, ": threads must be >= 0 (0: every core; got ", threads, ")");
    const std::vector<double> radii(shells.begin(), shells.end());
    for (std::size_t k = 0; k < radii.size(); ++k) {
        TORCH_CHECK(radii[k] > 0 && radii[k] <= cutoff && (k == 0 || radii[k] > radii[k - 1]), op,
                    ": shells[", k, "] = ", radii[k],
                    " must be > 0, exceed the one before and be at most the cutoff, ", cutoff);
    }

    const at::Tensor x = positions.detach().to(at::kDouble).contiguous();
    const at::Tensor h = cells.detach().to(at::kDouble).contiguous();
    const at::Tensor flags = pbc.to(at::kCPU).contiguous();
    const bool* flag = flags.data_ptr<bool>();
    const double* x_data = x.numel() == 0 ? nullptr : x.data_ptr<double>();
    std::vector<tricell::BatchStructure> structures;
    structures.reserve(std::size_t(count));
    for (std::int64_t s = 0; s < count; ++s) {
        tricell::Periodicity periodic;
        for (std::size_t axis = 0; axis < 3; ++axis) {
            periodic.axes[axis] = flag[3 * s + std::int64_t(axis)];
        }
        const tricell::PointsView points(
            x_data == nullptr ? nullptr : x_data + 3 * ptr[std::size_t(s)],
            std::size_t(ptr[std::size_t(s) + 1] - ptr[std::size_t(s)]));
        if (tricell::python::same_cell_as_previous(h.data_ptr<double>(), std::size_t(s)) &&
            periodic == structures.back().box.periodicity()) {
            structures.push_back(tricell::BatchStructure{structures.back().box, points});
            continue;
        }
        try {
            structures.push_back(tricell::BatchStructure{
                box_from_rows(h.data_ptr<double>() + 9 * s, periodic), points});
        } catch (const tricell::Error& error) {
            TORCH_CHECK(false, op, ": structure ", s, ", cells[", s, "]: ", error.what());
        }
    }

    tricell::NeighborOptions options;
    options.cutoff = cutoff;
    options.half = !full;
    options.threads = int(threads);
    set_nearest(op, options, max_neighbors, tie_tolerance, symmetric);
    TORCH_CHECK(max_neighbors == 0 || radii.empty(), op,
                ": shells and max_neighbors cannot be asked together (shells split a whole "
                "list by distance)");
    options.quantities.shifts = true;
    options.quantities.distances = !radii.empty();
    options.quantities.vectors = false;
    // One list per thread, kept between calls: its buffers are reused, as a NeighborList's are.
    thread_local tricell::BatchList list;
    try {
        tricell::compute_neighbors_batch(structures, options, list, tricell::BatchIndices::global);
    } catch (const tricell::Error& error) {
        TORCH_CHECK(
            false, op, ": ",
            tricell::python::with_rows_of(error.what(), ptr.data(), ptr.size(), "positions"));
    }

    const auto pairs = static_cast<std::int64_t>(list.size());
    at::Tensor i = output_tensor({pairs}, at::kLong);
    at::Tensor j = output_tensor({pairs}, at::kLong);
    at::Tensor shifts = output_tensor({pairs, 3}, at::kLong);
    at::Tensor offsets = output_tensor({count + 1}, at::kLong);
    std::int64_t* i_out = i.data_ptr<std::int64_t>();
    std::int64_t* j_out = j.data_ptr<std::int64_t>();
    std::int64_t* s_out = shifts.data_ptr<std::int64_t>();
    const auto& pair_offsets = list.pair_offsets();
    const auto& s_in = list.shifts();
    for (std::int64_t s = 0; s <= count; ++s) {
        offsets.data_ptr<std::int64_t>()[s] = std::int64_t(pair_offsets[std::size_t(s)]);
    }
    const std::uint32_t* i_in = list.i().data(); // global: rows of the positions
    const std::uint32_t* j_in = list.j().data();
    for (std::size_t k = 0; k < list.size(); ++k) {
        i_out[k] = i_in[k];
        j_out[k] = j_in[k];
    }
    for (std::size_t k = 0; k < 3 * list.size(); ++k) {
        s_out[k] = s_in[k];
    }
    at::Tensor shell = output_tensor({radii.empty() ? 0 : pairs}, at::kLong);
    if (!radii.empty()) {
        std::int64_t* shell_out = shell.data_ptr<std::int64_t>();
        for (std::size_t k = 0; k < list.size(); ++k) {
            std::int64_t first_above = 0;
            while (first_above < std::int64_t(radii.size()) &&
                   !(list.distances()[k] < radii[std::size_t(first_above)])) {
                ++first_above;
            }
            shell_out[k] = first_above;
        }
    }
    return {i, j, shifts, offsets, shell};
}

} // namespace

TORCH_LIBRARY_FRAGMENT(tricell, m) {
    m.def("batch_pairs(Tensor positions, Tensor cells, Tensor pbc, Tensor batch_ptr, float cutoff, "
          "bool full=True, int threads=1, float[] shells=[], int max_neighbors=0, "
          "float tie_tolerance=0., bool symmetric=False) -> (Tensor i, Tensor j, Tensor S, "
          "Tensor offsets, Tensor shell)",
          &batch_pairs);
}
