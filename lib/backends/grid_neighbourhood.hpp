// The cell grid and stencil that the grid backends (dense, linked, hash) share: a CellGrid over
// the search frame and its Stencil (full or half, pruned by the exact closest approach where the
// search policy says that pays), with the stencil's rows and per-axis neighbour tables.
#pragma once

#include <array>
#include <cstddef>
#include <vector>

#include "backends/backend.hpp"
#include "tricell/grid.hpp"
#include "tricell/stencil.hpp"

namespace tricell::detail {

class GridNeighbourhood {
  public:
    /// `max_cells` caps the grid (the dense and linked backends); `tables` builds the per-axis
    /// neighbour tables (O(cells per axis) memory; the hash backend computes them on the fly).
    void build(const BinningInput& input, std::size_t max_cells, bool tables);

    const CellGrid& grid() const { return grid_; }
    const Stencil& stencil() const { return stencil_; }
    const std::vector<StencilRow>& rows() const { return stencil_.rows(); }
    int neighbour_cell(int axis, int t) const { return stencil_.neighbour_cell(axis, t); }
    int neighbour_shift(int axis, int t) const { return stencil_.neighbour_shift(axis, t); }
    /// Fractional volume of one cell (the product of the cell sizes).
    double cell_volume() const { return grid_.cell_size().prod(); }
    /// Cell coordinates of a flat cell index (c fastest).
    std::array<int, 3> coordinates(std::size_t cell) const {
        const std::array<int, 3>& n = grid_.dims();
        return {{int(cell / (std::size_t(n[2]) * std::size_t(n[1]))),
                 int((cell / std::size_t(n[2])) % std::size_t(n[1])),
                 int(cell % std::size_t(n[2]))}};
    }

  private:
    CellGrid grid_;
    Stencil stencil_;
};

} // namespace tricell::detail
