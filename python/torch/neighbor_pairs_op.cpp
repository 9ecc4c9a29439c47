// torch.ops.tricell.neighbor_pairs: tricell's neighbour search as a TorchScript custom op.
//
// The op takes N x 3 positions, a 3 x 3 cell with the lattice vectors as rows (float32 or
// float64, CPU, one dtype for both), three periodicity flags, a cutoff and full/half, and
// returns the pairs (i, j, S) as int64 tensors: i and j of N_pairs entries, S of N_pairs x 3,
// with D = x_j - x_i + S @ cell shorter than the cutoff. It runs tricell::compute_neighbors on
// detached float64 copies of the inputs, so it records nothing for autograd and its outputs
// are integers; tricell.torch computes D and d from them with ordinary torch ops, which is
// where gradients flow. Every argument is checked here, and a message names the argument and
// what it got; the library's own errors (a non-finite position, a singular cell, a pair limit)
// come through as RuntimeError with the library's message.
#include <cmath>
#include <cstdint>
#include <sstream>
#include <string>
#include <tuple>

#include <torch/library.h>
#include <torch/types.h>

#include <tricell/box.hpp>
#include <tricell/error.hpp>
#include <tricell/neighbor_list.hpp>

namespace {

std::string shape_of(const at::Tensor& tensor) {
    std::ostringstream text;
    text << tensor.sizes();
    return text.str();
}

// A float32 or float64 tensor on the CPU; `name` is the argument in messages.
void check_real_cpu(const at::Tensor& tensor, const char* name) {
    TORCH_CHECK(tensor.scalar_type() == at::kFloat || tensor.scalar_type() == at::kDouble,
                "neighbor_pairs: ", name, " must be float32 or float64 (got ", tensor.scalar_type(),
                ")");
    TORCH_CHECK(tensor.device().is_cpu(), "neighbor_pairs: ", name,
                " must be on the CPU (got device ", tensor.device(), ")");
}

void check_arguments(const at::Tensor& positions, const at::Tensor& cell,
                     const c10::List<bool>& periodic, double cutoff) {
    TORCH_CHECK(positions.dim() == 2 && positions.size(1) == 3,
                "neighbor_pairs: positions must be an N x 3 tensor (got shape ",
                shape_of(positions), ")");
    TORCH_CHECK(cell.dim() == 2 && cell.size(0) == 3 && cell.size(1) == 3,
                "neighbor_pairs: cell must be a 3 x 3 tensor with the lattice vectors as rows "
                "(got shape ",
                shape_of(cell), ")");
    check_real_cpu(positions, "positions");
    check_real_cpu(cell, "cell");
    TORCH_CHECK(cell.scalar_type() == positions.scalar_type(),
                "neighbor_pairs: cell must have the dtype of positions (got ", cell.scalar_type(),
                " for cell and ", positions.scalar_type(), " for positions)");
    TORCH_CHECK(periodic.size() == 3, "neighbor_pairs: periodic must be three bools (got ",
                periodic.size(), ")");
    TORCH_CHECK(std::isfinite(cutoff) && cutoff > 0,
                "neighbor_pairs: cutoff must be finite and > 0 (got ", cutoff, ")");
}

std::tuple<at::Tensor, at::Tensor, at::Tensor> neighbor_pairs(const at::Tensor& positions,
                                                              const at::Tensor& cell,
                                                              const c10::List<bool>& periodic,
                                                              double cutoff, bool full) {
    check_arguments(positions, cell, periodic, cutoff);
    const at::Tensor x = positions.detach().to(at::kDouble).contiguous();
    const at::Tensor h = cell.detach().to(at::kDouble).contiguous();

    Eigen::Matrix3d rows;
    const double* h_data = h.data_ptr<double>();
    for (int r = 0; r < 3; ++r) {
        for (int c = 0; c < 3; ++c) {
            rows(r, c) = h_data[3 * r + c];
        }
    }
    tricell::Periodicity pbc;
    for (std::size_t axis = 0; axis < 3; ++axis) {
        pbc.axes[axis] = periodic[axis];
    }
    tricell::NeighborOptions options;
    options.cutoff = cutoff;
    options.half = !full;
    options.quantities.shifts = true;
    options.quantities.distances = false;
    options.quantities.vectors = false;

    tricell::NeighborList list;
    try {
        const auto n = static_cast<std::size_t>(x.size(0));
        const tricell::PointsView points(n == 0 ? nullptr : x.data_ptr<double>(), n);
        tricell::compute_neighbors(tricell::Box::from_rows(rows, pbc), points, options, list);
    } catch (const tricell::Error& error) {
        TORCH_CHECK(false, "neighbor_pairs: ", error.what());
    }

    const auto pairs = static_cast<std::int64_t>(list.size());
    const auto as_long = at::TensorOptions().dtype(at::kLong);
    at::Tensor i = at::empty({pairs}, as_long);
    at::Tensor j = at::empty({pairs}, as_long);
    at::Tensor shifts = at::empty({pairs, 3}, as_long);
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
          "bool full=True) -> (Tensor i, Tensor j, Tensor S)",
          &neighbor_pairs);
}
