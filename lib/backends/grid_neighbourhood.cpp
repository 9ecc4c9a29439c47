#include "backends/grid_neighbourhood.hpp"

#include "search/policy.hpp"

#include <algorithm>

namespace tricell::detail {

void GridNeighbourhood::build(const BinningInput& input, std::size_t max_cells, bool tables) {
    GridOptions grid_options;
    grid_options.search_radius = input.search_radius;
    grid_options.cells_per_cutoff = input.options.cells_per_cutoff;
    grid_options.max_cells = max_cells;
    grid_ = CellGrid(input.frame, grid_options, input.lower, input.upper);

    const bool exact_pruning =
        exact_stencil_pruning(double(input.fractional.size()),
                              double(grid_.dims()[0]) * grid_.dims()[1] * grid_.dims()[2]);
    stencil_ = input.options.half
                   ? Stencil::half(grid_, input.frame, input.search_radius, exact_pruning)
                   : Stencil::full(grid_, input.frame, input.search_radius, exact_pruning);
    // Rows: for each (da, db), the hull of its dc (a superset of the kept offsets is always
    // correct; in practice the kept dc already form an interval), found through a table indexed
    // by (da, db) so that wide stencils (cutoffs of many boxes) stay linear.
    rows_.clear();
    const int ma = grid_.reach()[0], mb = grid_.reach()[1];
    const std::size_t width = std::size_t(2 * mb + 1);
    std::vector<int> row_of(std::size_t(2 * ma + 1) * width, -1);
    for (const CellOffset& d : stencil_.offsets()) {
        int& row = row_of[std::size_t(d[0] + ma) * width + std::size_t(d[1] + mb)];
        if (row < 0) {
            row = int(rows_.size());
            rows_.push_back(StencilRow{d[0], d[1], d[2], d[2]});
        } else {
            rows_[std::size_t(row)].dc_lo = std::min(rows_[std::size_t(row)].dc_lo, d[2]);
            rows_[std::size_t(row)].dc_hi = std::max(rows_[std::size_t(row)].dc_hi, d[2]);
        }
    }
    for (int k = 0; k < 3; ++k) {
        neighbour_cell_[k].clear();
        neighbour_shift_[k].clear();
        if (!tables) {
            continue;
        }
        const int count = grid_.dims()[std::size_t(k)];
        const int reach = grid_.reach()[std::size_t(k)];
        neighbour_cell_[k].resize(std::size_t(count + 2 * reach));
        neighbour_shift_[k].resize(std::size_t(count + 2 * reach));
        for (int t = -reach; t < count + reach; ++t) {
            const std::size_t slot = std::size_t(t + reach);
            if (input.frame.periodic(k)) {
                neighbour_cell_[k][slot] = floor_mod(t, count);
                neighbour_shift_[k][slot] = floor_div(t, count);
            } else {
                neighbour_cell_[k][slot] = (t >= 0 && t < count) ? t : -1;
                neighbour_shift_[k][slot] = 0;
            }
        }
    }
}

} // namespace tricell::detail
