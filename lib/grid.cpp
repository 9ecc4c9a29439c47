#include "tricell/grid.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "tricell/error.hpp"

namespace tricell {

void GridOptions::validate() const {
    if (!(std::isfinite(search_radius) && search_radius > 0)) {
        detail::fail<InvalidArgument>("search radius must be > 0 (got ", search_radius, ")");
    }
    if (!(std::isfinite(cells_per_cutoff) && cells_per_cutoff >= 1)) {
        detail::fail<InvalidArgument>("cells per cutoff must be >= 1 (got ", cells_per_cutoff, ")");
    }
    if (max_cells < 1) {
        detail::fail<InvalidArgument>("max_cells must be >= 1 (got ", max_cells, ")");
    }
}

namespace {

// Most cells along one axis, whatever max_cells allows: keeps coordinates in an int and the
// flat index of three axes (2^60) in 64 bits.
constexpr double max_cells_per_axis = double(1 << 20);

// x * y / z for x, y, z >= 0, without the intermediate overflow or underflow of x * y: the
// mantissas and the exponents are combined apart, so the result is inf or 0 only when the true
// value is. An open axis spanning 1e308 in fractional units, a few units wide, with a cutoff
// near 1e308 asks for a few cells, not for the 2^20 of an overflowed thickness (whose stencil
// would reach all of them).
double scaled_ratio(double x, double y, double z) {
    int ex = 0, ey = 0, ez = 0;
    const double mx = std::frexp(x, &ex), my = std::frexp(y, &ey), mz = std::frexp(z, &ez);
    return std::ldexp(mx * my / mz, ex + ey - ez);
}

// Cells that fit along an axis of fractional span `span` and perpendicular width `width` with
// target size h, at most `limit` (so that cell counts stay representable).
int cells_along(double span, double width, double h, double limit) {
    double wanted = span * width / h;
    if (std::isinf(wanted) && std::isfinite(span)) {
        wanted = scaled_ratio(span, width, h);
    }
    const double n = std::floor(wanted); // NaN for 0 / 0 (a flat axis, h underflowed)
    return !(n >= 1) ? 1 : static_cast<int>(std::min({n, limit, max_cells_per_axis}));
}

} // namespace

CellGrid::CellGrid(const Box& box, const GridOptions& options, const Eigen::Vector3d& lower,
                   const Eigen::Vector3d& upper)
    : pbc_(box.periodicity()) {
    options.validate();
    const Eigen::Vector3d& widths = box.perpendicular_widths();
    // The fractional span of the region the grid covers along each axis.
    Eigen::Vector3d span;
    for (int axis = 0; axis < 3; ++axis) {
        if (pbc_[axis]) {
            origin_[axis] = 0;
            span[axis] = 1;
        } else {
            origin_[axis] = lower[axis];
            span[axis] = std::max(upper[axis] - lower[axis], 0.0);
        }
    }

    const double max_cells = static_cast<double>(options.max_cells);
    double h = options.search_radius / options.cells_per_cutoff;
    for (;;) {
        for (int axis = 0; axis < 3; ++axis) {
            dims_[axis] = cells_along(span[axis], widths[axis], h, max_cells);
        }
        if (double(dims_[0]) * double(dims_[1]) * double(dims_[2]) <= max_cells) {
            break;
        }
        capped_ = true;
        // Grow by 10%, and by at least one ulp (1.1 h rounds back to h for the smallest
        // denormal sizes).
        h = std::max(h * 1.1, std::nextafter(h, std::numeric_limits<double>::infinity()));
    }

    for (int axis = 0; axis < 3; ++axis) {
        // A span so small (denormal) that the inverse cell size overflows counts as a plane: an
        // atom at the origin was at 0 * inf = NaN cells (search fuzzer).
        if (span[axis] > 0 && std::isfinite(dims_[axis] / span[axis])) {
            cell_size_[axis] = span[axis] / dims_[axis];
        } else {
            cell_size_[axis] = 1; // all positions share one plane: any size, every atom in cell 0
        }
        inverse_size_[axis] = 1.0 / cell_size_[axis];
        // A pair within the radius is at most r / (w * cell_size) cell layers apart, at least
        // one (the cells' real thickness can overflow to inf, and r / inf is 0).
        const double layers =
            std::max(options.search_radius / (widths[axis] * cell_size_[axis]), 1.0);
        if (!pbc_[axis]) {
            // No images: the grid's end is the end.
            reach_[axis] =
                layers < dims_[axis] - 1 ? static_cast<int>(std::ceil(layers)) : dims_[axis] - 1;
            continue;
        }
        if (!(layers < 1e6)) {
            detail::fail<InvalidArgument>("search radius ", options.search_radius,
                                          " spans more than a million cells along axis ", axis,
                                          " (perpendicular width ", widths[axis], ")");
        }
        const int reach = static_cast<int>(std::ceil(layers));
        reach_[axis] = reach;
    }
}

} // namespace tricell
