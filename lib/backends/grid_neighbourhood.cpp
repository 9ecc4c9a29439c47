#include "backends/grid_neighbourhood.hpp"

namespace tricell::detail {

void GridNeighbourhood::build(const BinningInput& input, std::size_t max_cells, bool tables) {
    GridOptions grid_options;
    grid_options.search_radius = input.search_radius;
    grid_options.cells_per_cutoff = input.plan.cells_per_cutoff;
    grid_options.max_cells = max_cells;
    grid_ = CellGrid(input.frame, grid_options, input.lower, input.upper);

    const bool exact_pruning =
        input.plan.exact_pruning(double(grid_.dims()[0]) * grid_.dims()[1] * grid_.dims()[2]);
    stencil_ = input.plan.half_stencil(input.options)
                   ? Stencil::half(grid_, input.frame, input.search_radius, exact_pruning, tables)
                   : Stencil::full(grid_, input.frame, input.search_radius, exact_pruning, tables);
}

} // namespace tricell::detail
