// The cell grid and stencil that the grid backends (dense, linked, hash) share: a CellGrid over
// the search frame, its Stencil (full or half, pruned by the exact closest approach where that
// pays), the stencil's rows (for each (da, db), the range of dc it keeps) and, per axis, the
// table that turns a cell coordinate plus an offset into the neighbour cell and its image shift.
#pragma once

#include <array>
#include <cstddef>
#include <vector>

#include "backends/backend.hpp"
#include "tricell/grid.hpp"
#include "tricell/stencil.hpp"

namespace tricell::detail {

/// A row of the stencil: offsets (da, db, dc) for dc in [dc_lo, dc_hi]. In a layout where c
/// varies fastest the cells of one row are consecutive, so a row is scanned as at most a few
/// contiguous atom ranges instead of one range per offset.
struct StencilRow {
    int da, db, dc_lo, dc_hi;
};

class GridNeighbourhood {
  public:
    /// `max_cells` caps the grid (the dense and linked backends); `tables` builds the per-axis
    /// neighbour tables (O(cells per axis) memory; the hash backend computes them on the fly).
    void build(const BinningInput& input, std::size_t max_cells, bool tables);

    const CellGrid& grid() const { return grid_; }
    const Stencil& stencil() const { return stencil_; }
    const std::vector<StencilRow>& rows() const { return rows_; }
    /// Neighbour cell along `axis` of coordinate t = c + delta in [-reach, n + reach): -1 beyond
    /// the end of an open axis.
    int neighbour_cell(int axis, int t) const {
        return neighbour_cell_[axis][std::size_t(t + grid_.reach()[std::size_t(axis)])];
    }
    int neighbour_shift(int axis, int t) const {
        return neighbour_shift_[axis][std::size_t(t + grid_.reach()[std::size_t(axis)])];
    }
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
    std::vector<StencilRow> rows_;
    std::vector<int> neighbour_cell_[3];
    std::vector<int> neighbour_shift_[3];
};

} // namespace tricell::detail
