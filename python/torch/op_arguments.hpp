// What every op of the PyTorch op library checks of its tensors, with messages naming the op,
// the argument and what it got ("neighbor_pairs: positions must be float32 or float64 (got
// Long)"), and how it hands tricell's arrays over.
#pragma once

#include <cstdint>
#include <sstream>
#include <string>

#include <torch/types.h>

#include <tricell/box.hpp>
#include <tricell/neighbor_list.hpp>

namespace tricell::torch_ops {

inline std::string shape_of(const at::Tensor& tensor) {
    std::ostringstream text;
    text << tensor.sizes();
    return text.str();
}

/// A float32 or float64 tensor on the CPU.
inline void check_real_cpu(const char* op, const at::Tensor& tensor, const char* name) {
    TORCH_CHECK(tensor.scalar_type() == at::kFloat || tensor.scalar_type() == at::kDouble, op, ": ",
                name, " must be float32 or float64 (got ", tensor.scalar_type(), ")");
    TORCH_CHECK(tensor.device().is_cpu(), op, ": ", name, " must be on the CPU (got device ",
                tensor.device(), ")");
}

/// N x 3 positions and a cell of the same real dtype on the CPU (the cell's shape is the caller's
/// to check).
inline void check_positions_and_cell(const char* op, const at::Tensor& positions,
                                     const at::Tensor& cell, const char* cell_name) {
    TORCH_CHECK(positions.dim() == 2 && positions.size(1) == 3, op,
                ": positions must be an N x 3 tensor (got shape ", shape_of(positions), ")");
    check_real_cpu(op, positions, "positions");
    check_real_cpu(op, cell, cell_name);
    TORCH_CHECK(cell.scalar_type() == positions.scalar_type(), op, ": ", cell_name,
                " must have the dtype of positions (got ", cell.scalar_type(), " for ", cell_name,
                " and ", positions.scalar_type(), " for positions)");
}

inline void check_cutoff(const char* op, double cutoff) {
    TORCH_CHECK(std::isfinite(cutoff) && cutoff > 0, op, ": cutoff must be finite and > 0 (got ",
                cutoff, ")");
}

/// The k nearest within the cutoff: at most max_neighbors pairs per centre (0: no limit), with
/// tie_tolerance and symmetric as NeighborOptions has them; the rules that name the op's own
/// arguments are checked here, the rest by the library.
inline void set_nearest(const char* op, NeighborOptions& options, std::int64_t max_neighbors,
                        double tie_tolerance, bool symmetric) {
    TORCH_CHECK(max_neighbors >= 0, op, ": max_neighbors must be >= 0 (0: no limit; got ",
                max_neighbors, ")");
    TORCH_CHECK(max_neighbors == 0 || !options.half, op,
                ": max_neighbors keeps the nearest pairs of each centre of a full list: full "
                "must be True");
    options.max_neighbors = std::size_t(max_neighbors);
    options.tie_tolerance = tie_tolerance;
    options.symmetric = symmetric;
}

/// The 3 x 3 matrix at `rows` (row-major: the lattice vectors as rows) as a Box.
inline Box box_from_rows(const double* rows, const Periodicity& pbc) {
    Eigen::Matrix3d m;
    for (int r = 0; r < 3; ++r) {
        for (int c = 0; c < 3; ++c) {
            m(r, c) = rows[3 * r + c];
        }
    }
    return Box::from_rows(m, pbc);
}

/// One structure's arguments, checked, as the library takes them: `x` (N x 3) and `h` (3 x 3,
/// the lattice vectors as rows) are detached float64 copies of the positions and the cell.
struct Structure {
    at::Tensor x;
    at::Tensor h;
    Periodicity pbc;

    Box box() const { return box_from_rows(h.data_ptr<double>(), pbc); }
    PointsView points() const {
        const auto n = static_cast<std::size_t>(x.size(0));
        return PointsView(n == 0 ? nullptr : x.data_ptr<double>(), n);
    }
};

/// N x 3 positions, a 3 x 3 cell of their dtype on the CPU and three periodicity flags.
inline Structure structure_of(const char* op, const at::Tensor& positions, const at::Tensor& cell,
                              const c10::List<bool>& periodic) {
    check_positions_and_cell(op, positions, cell, "cell");
    TORCH_CHECK(cell.dim() == 2 && cell.size(0) == 3 && cell.size(1) == 3, op,
                ": cell must be a 3 x 3 tensor with the lattice vectors as rows (got shape ",
                shape_of(cell), ")");
    TORCH_CHECK(periodic.size() == 3, op, ": periodic must be three bools (got ", periodic.size(),
                ")");
    Structure s;
    s.x = positions.detach().to(at::kDouble).contiguous();
    s.h = cell.detach().to(at::kDouble).contiguous();
    for (std::size_t axis = 0; axis < 3; ++axis) {
        s.pbc.axes[axis] = periodic[axis];
    }
    return s;
}

} // namespace tricell::torch_ops
