#include "tricell/stencil.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

namespace tricell {

double closest_approach_sq(const Eigen::Matrix3d& h, const Eigen::Vector3d& lower,
                           const Eigen::Vector3d& upper) {
    return closest_approach_sq(h, h.transpose() * h, lower, upper);
}

// The active sets of the box constraints (each coordinate at its lower bound, its upper bound or
// free), vertices first, then edges, then faces: code = s_0 + 3 s_1 + 9 s_2 with s_k = 0 (lower),
// 1 (upper) or 2 (free).
constexpr std::array<int, 26> active_sets = [] {
    std::array<int, 26> sets{};
    int n = 0;
    for (int n_free = 0; n_free < 3; ++n_free) {
        for (int code = 0; code < 27; ++code) {
            const int free = (code % 3 == 2) + ((code / 3) % 3 == 2) + (code / 9 == 2);
            if (free == n_free) {
                sets[std::size_t(n++)] = code;
            }
        }
    }
    return sets;
}();

// |H u|^2 is convex, and its free minimum u = 0 lies outside the box, so its minimum over the box
// lies on a vertex, an edge or a face. Each active set has one stationary point (the free
// coordinates solve a 1x1 or 2x2 system in the Gram matrix G = H^T H). A feasible one at which the
// gradient G u points out of the box on every bound coordinate meets the Karush-Kuhn-Tucker
// conditions, which for a convex problem make it the minimum, so the enumeration stops there; the
// least feasible value is the answer when rounding hides the conditions at every point.
double closest_approach_sq(const Eigen::Matrix3d& h, const Eigen::Matrix3d& gram,
                           const Eigen::Vector3d& lower, const Eigen::Vector3d& upper) {
    // The origin inside the box: the cells touch or overlap.
    if ((lower.array() <= 0).all() && (upper.array() >= 0).all()) {
        return 0;
    }
    double best = std::numeric_limits<double>::infinity();
    for (const int code : active_sets) {
        const int state[3] = {code % 3, (code / 3) % 3, code / 9};
        Eigen::Vector3d u;
        int free_axes[3];
        int n_free = 0;
        for (int k = 0; k < 3; ++k) {
            if (state[k] == 2) {
                free_axes[n_free++] = k;
                u[k] = 0;
            } else {
                u[k] = state[k] == 0 ? lower[k] : upper[k];
            }
        }
        if (n_free > 0) {
            // Minimise over the free coordinates: G_FF u_F = -G_FX u_X (1x1 or 2x2).
            double rhs[2] = {0, 0};
            for (int a = 0; a < n_free; ++a) {
                for (int k = 0; k < 3; ++k) {
                    if (state[k] != 2) {
                        rhs[a] -= gram(free_axes[a], k) * u[k];
                    }
                }
            }
            if (n_free == 1) {
                u[free_axes[0]] = rhs[0] / gram(free_axes[0], free_axes[0]);
            } else {
                const double g00 = gram(free_axes[0], free_axes[0]);
                const double g01 = gram(free_axes[0], free_axes[1]);
                const double g11 = gram(free_axes[1], free_axes[1]);
                const double det = g00 * g11 - g01 * g01; // > 0: H is non-singular
                u[free_axes[0]] = (g11 * rhs[0] - g01 * rhs[1]) / det;
                u[free_axes[1]] = (g00 * rhs[1] - g01 * rhs[0]) / det;
            }
            bool feasible = true;
            for (int a = 0; a < n_free; ++a) {
                const int k = free_axes[a];
                feasible = feasible && u[k] >= lower[k] && u[k] <= upper[k];
            }
            if (!feasible) {
                continue;
            }
        }
        best = std::min(best, (h * u).squaredNorm());
        const Eigen::Vector3d gradient = gram * u; // half the gradient of |H u|^2
        bool minimum = true;
        for (int k = 0; k < 3; ++k) {
            minimum = minimum && !(state[k] == 0 && gradient[k] < 0) &&
                      !(state[k] == 1 && gradient[k] > 0);
        }
        if (minimum) {
            return best;
        }
    }
    return best;
}

bool box_within_radius(const Eigen::Matrix3d& h, const Eigen::Matrix3d& gram,
                       const Eigen::Vector3d& edges, const Eigen::Vector3d& lower,
                       const Eigen::Vector3d& upper, double radius) {
    if ((lower.array() <= 0).all() && (upper.array() >= 0).all()) {
        return true; // the origin is in the box (even when radius^2 underflows to 0)
    }
    const double centre = (h * (0.5 * (lower + upper))).norm();
    if (centre < radius) {
        return true;
    }
    const double spread = 0.5 * edges.dot(upper - lower);
    // A relative margin far above the rounding of the two sums keeps the bound a bound.
    if (centre - spread > radius + 1e-12 * (centre + spread)) {
        return false;
    }
    return closest_approach_sq(h, gram, lower, upper) < radius * radius;
}

namespace {

bool lexicographically_positive(const CellOffset& d) {
    if (d[0] != 0) {
        return d[0] > 0;
    }
    if (d[1] != 0) {
        return d[1] > 0;
    }
    return d[2] > 0;
}

// Offsets within the reach whose cells can hold a pair closer than the radius. Cells of
// fractional size f along an axis: offset delta covers fractional differences in
// ((delta - 1) f, (delta + 1) f).
std::vector<CellOffset> kept_offsets(const CellGrid& grid, const Box& box, double radius, bool half,
                                     bool exact) {
    const std::array<int, 3>& m = grid.reach();
    const Eigen::Vector3d& f = grid.cell_size();
    const Eigen::Vector3d& w = box.perpendicular_widths();
    const Eigen::Matrix3d gram = box.matrix().transpose() * box.matrix();
    const Eigen::Vector3d edges = box.matrix().colwise().norm().transpose();
    std::vector<CellOffset> kept;
    if (half) {
        kept.push_back({{0, 0, 0}});
    }
    for (int da = -m[0]; da <= m[0]; ++da) {
        for (int db = -m[1]; db <= m[1]; ++db) {
            for (int dc = -m[2]; dc <= m[2]; ++dc) {
                const CellOffset d{{da, db, dc}};
                if (half && !lexicographically_positive(d)) {
                    continue;
                }
                Eigen::Vector3d lower, upper;
                double slab_gap = 0; // cheap lower bound: the gap across one pair of faces
                for (int k = 0; k < 3; ++k) {
                    lower[k] = (d[k] - 1) * f[k];
                    upper[k] = (d[k] + 1) * f[k];
                    const double gap = std::max({lower[k], -upper[k], 0.0}) * w[k];
                    slab_gap = std::max(slab_gap, gap);
                }
                if (slab_gap >= radius) {
                    continue;
                }
                if (exact && !box_within_radius(box.matrix(), gram, edges, lower, upper, radius)) {
                    continue;
                }
                kept.push_back(d);
            }
        }
    }
    return kept;
}

} // namespace

Stencil Stencil::make(const CellGrid& grid, const Box& box, double search_radius, bool half,
                      bool exact, bool tables) {
    Stencil s;
    s.offsets_ = kept_offsets(grid, box, search_radius, half, exact);
    s.half_ = half;
    s.reach_ = grid.reach();
    // Rows through a table indexed by (da, db), so that wide stencils (cutoffs of many boxes)
    // stay linear.
    const int ma = s.reach_[0], mb = s.reach_[1];
    const std::size_t width = std::size_t(2 * mb + 1);
    std::vector<int> row_of(std::size_t(2 * ma + 1) * width, -1);
    for (const CellOffset& d : s.offsets_) {
        int& row = row_of[std::size_t(d[0] + ma) * width + std::size_t(d[1] + mb)];
        if (row < 0) {
            row = int(s.rows_.size());
            s.rows_.push_back(StencilRow{d[0], d[1], d[2], d[2]});
        } else {
            StencilRow& r = s.rows_[std::size_t(row)];
            r.dc_lo = std::min(r.dc_lo, d[2]);
            r.dc_hi = std::max(r.dc_hi, d[2]);
        }
    }
    if (!tables) {
        return s;
    }
    for (int k = 0; k < 3; ++k) {
        const int count = grid.dims()[std::size_t(k)];
        const int reach = s.reach_[std::size_t(k)];
        s.neighbour_cell_[k].resize(std::size_t(count + 2 * reach));
        s.neighbour_shift_[k].resize(std::size_t(count + 2 * reach));
        for (int t = -reach; t < count + reach; ++t) {
            const std::size_t slot = std::size_t(t + reach);
            if (box.periodic(k)) {
                s.neighbour_cell_[k][slot] = floor_mod(t, count);
                s.neighbour_shift_[k][slot] = floor_div(t, count);
            } else {
                s.neighbour_cell_[k][slot] = (t >= 0 && t < count) ? t : -1;
                s.neighbour_shift_[k][slot] = 0;
            }
        }
    }
    return s;
}

Stencil Stencil::full(const CellGrid& grid, const Box& box, double search_radius, bool exact,
                      bool tables) {
    return make(grid, box, search_radius, false, exact, tables);
}

Stencil Stencil::half(const CellGrid& grid, const Box& box, double search_radius, bool exact,
                      bool tables) {
    return make(grid, box, search_radius, true, exact, tables);
}

} // namespace tricell
