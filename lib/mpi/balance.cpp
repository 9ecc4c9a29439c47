// Moment-balanced boundaries and the rank-work estimate (balance.hpp holds the model).
#include "tricell/mpi/balance.hpp"

#include <algorithm>
#include <array>
#include <cmath>

#include "collective.hpp"
#include "policy/cost_model.hpp"
#include "tricell/error.hpp"

namespace tricell::mpi {

using tricell::detail::fail;

void WorkModel::validate() const {
    const struct {
        const char* name;
        double value;
    } fields[] = {
        {"per_visit", costs.per_visit}, {"per_atom", costs.per_atom}, {"per_test", costs.per_test}};
    for (const auto& f : fields) {
        if (!(std::isfinite(f.value) && f.value >= 0)) {
            fail<InvalidArgument>("WorkModel::costs.", f.name, " must be >= 0 (got ", f.value, ")");
        }
    }
    if (max_cells < 1) {
        fail<InvalidArgument>("WorkModel::max_cells must be >= 1 (got 0)");
    }
}

namespace {

// Stencil cells of a grid of one cell per cutoff (the K of region_work).
double stencil_neighbours() {
    return double(stencil_cells(1));
}

// region_work of one cell holding n atoms.
double one_cell_work(double n, const WorkModel& model) {
    OccupancyMoments m;
    m.add(n);
    return region_work(m, stencil_neighbours(), model.costs);
}

// Global cell occupancies on a grid of about one cutoff per cell (periodic positions wrapped,
// open ones clamped into the end cells), summed over all ranks.
struct Occupancy {
    std::array<int, 3> n{{1, 1, 1}};
    std::vector<double> counts; // c fastest
    double at(int a, int b, int c) const {
        return counts[(std::size_t(a) * std::size_t(n[1]) + std::size_t(b)) * std::size_t(n[2]) +
                      std::size_t(c)];
    }
};

Occupancy occupancy(const Decomposition& d, const Box& box, PointsView positions, double cutoff,
                    const WorkModel& model) {
    Occupancy occ;
    detail::agreed(d.comm(), [&] {
        model.validate();
        if (!(std::isfinite(cutoff) && cutoff > 0)) {
            fail<InvalidArgument>("cutoff must be > 0 (got ", cutoff, ")");
        }
        double cells = 1;
        for (int k = 0; k < 3; ++k) {
            const double per_axis =
                std::max(1.0, std::floor(box.perpendicular_widths()[k] / cutoff));
            occ.n[std::size_t(k)] = int(std::min(per_axis, 1e6));
            cells *= occ.n[std::size_t(k)];
        }
        if (cells > double(model.max_cells)) {
            const double scale = std::cbrt(double(model.max_cells) / cells);
            for (int& v : occ.n) {
                v = std::max(1, int(std::floor(v * scale)));
            }
        }
        occ.counts.assign(std::size_t(occ.n[0]) * std::size_t(occ.n[1]) * std::size_t(occ.n[2]),
                          0.0);
        for (std::size_t a = 0; a < positions.size(); ++a) {
            const Eigen::Vector3d x = positions[a];
            if (!x.allFinite()) {
                fail<InvalidArgument>("position ", a, " is not finite");
            }
            const Fractional s = box.wrap(box.to_fractional(Cartesian(x))).wrapped;
            std::array<int, 3> c{};
            for (int k = 0; k < 3; ++k) {
                const int nk = occ.n[std::size_t(k)];
                c[std::size_t(k)] = std::clamp(int(std::floor(s[k] * nk)), 0, nk - 1);
            }
            occ.counts[(std::size_t(c[0]) * std::size_t(occ.n[1]) + std::size_t(c[1])) *
                           std::size_t(occ.n[2]) +
                       std::size_t(c[2])] += 1;
        }
    });
    detail::check_mpi(MPI_Allreduce(MPI_IN_PLACE, occ.counts.data(), int(occ.counts.size()),
                                    MPI_DOUBLE, MPI_SUM, d.comm()),
                      "MPI_Allreduce");
    return occ;
}

// Work of each slab along an axis under a rule.
std::vector<double> slab_work(const Occupancy& occ, int axis, BalanceRule rule,
                              const WorkModel& model) {
    const int n = occ.n[std::size_t(axis)];
    std::vector<OccupancyMoments> moments(static_cast<std::size_t>(n));
    for (int a = 0; a < occ.n[0]; ++a) {
        for (int b = 0; b < occ.n[1]; ++b) {
            for (int c = 0; c < occ.n[2]; ++c) {
                const double v = occ.at(a, b, c);
                const int k = axis == 0 ? a : axis == 1 ? b : c;
                moments[std::size_t(k)].add(v);
            }
        }
    }
    std::vector<double> work(static_cast<std::size_t>(n));
    for (std::size_t k = 0; k < work.size(); ++k) {
        work[k] = rule == BalanceRule::equal_atoms
                      ? moments[k].atoms
                      : region_work(moments[k], stencil_neighbours(), model.costs);
    }
    return work;
}

// Inner boundaries at equal shares of the cumulative work, interpolated inside slabs.
std::vector<double> quantile_bounds(const std::vector<double>& work, int parts) {
    const std::size_t n = work.size();
    std::vector<double> cumulative(n + 1, 0.0);
    for (std::size_t k = 0; k < n; ++k) {
        cumulative[k + 1] = cumulative[k] + work[k];
    }
    std::vector<double> b(std::size_t(parts) + 1);
    for (int p = 0; p <= parts; ++p) {
        b[std::size_t(p)] = double(p) / parts;
    }
    const double total = cumulative[n];
    if (!(total > 0)) {
        return b;
    }
    for (int p = 1; p < parts; ++p) {
        const double target = total * p / parts;
        const std::size_t k = std::size_t(
            std::upper_bound(cumulative.begin(), cumulative.end(), target) - cumulative.begin());
        const std::size_t slab = std::min(n - 1, k == 0 ? 0 : k - 1);
        const double within = work[slab] > 0 ? (target - cumulative[slab]) / work[slab] : 0.5;
        b[std::size_t(p)] = (double(slab) + std::clamp(within, 0.0, 1.0)) / double(n);
    }
    // At least `gap` apart, inside (0, 1).
    const double gap = 1e-6;
    for (int p = 1; p < parts; ++p) {
        b[std::size_t(p)] = std::max(b[std::size_t(p)], b[std::size_t(p) - 1] + gap);
    }
    for (int p = parts - 1; p >= 1; --p) {
        b[std::size_t(p)] = std::min(b[std::size_t(p)], b[std::size_t(p) + 1] - gap);
    }
    return b;
}

} // namespace

void balance(Decomposition& decomposition, const Box& box, PointsView positions, double cutoff,
             BalanceRule rule, const WorkModel& model) {
    if (rule == BalanceRule::equal_volume) {
        detail::agreed(decomposition.comm(), [&] { model.validate(); });
        decomposition.reset_bounds();
        return;
    }
    const Occupancy occ = occupancy(decomposition, box, positions, cutoff, model);
    for (int axis = 0; axis < 3; ++axis) {
        const int parts = decomposition.dims()[std::size_t(axis)];
        decomposition.set_bounds(axis, quantile_bounds(slab_work(occ, axis, rule, model), parts));
    }
}

std::vector<double> estimate_rank_work(const Decomposition& decomposition, const Box& box,
                                       PointsView positions, double cutoff,
                                       const WorkModel& model) {
    const Occupancy occ = occupancy(decomposition, box, positions, cutoff, model);
    const Fractional lo = decomposition.lower(decomposition.rank());
    const Fractional hi = decomposition.upper(decomposition.rank());
    // Share of each cell along each axis inside this rank's domain.
    std::array<std::vector<double>, 3> share;
    for (int k = 0; k < 3; ++k) {
        const int n = occ.n[std::size_t(k)];
        share[std::size_t(k)].resize(std::size_t(n));
        for (int c = 0; c < n; ++c) {
            const double a = std::max(lo[k], double(c) / n);
            const double b = std::min(hi[k], double(c + 1) / n);
            share[std::size_t(k)][std::size_t(c)] = std::max(0.0, b - a) * n;
        }
    }
    double mine = 0;
    for (int a = 0; a < occ.n[0]; ++a) {
        for (int b = 0; b < occ.n[1]; ++b) {
            for (int c = 0; c < occ.n[2]; ++c) {
                const double w =
                    share[0][std::size_t(a)] * share[1][std::size_t(b)] * share[2][std::size_t(c)];
                if (w > 0) {
                    const double v = occ.at(a, b, c);
                    mine += w * one_cell_work(v, model);
                }
            }
        }
    }
    std::vector<double> all(std::size_t(decomposition.size()));
    detail::check_mpi(
        MPI_Allgather(&mine, 1, MPI_DOUBLE, all.data(), 1, MPI_DOUBLE, decomposition.comm()),
        "MPI_Allgather");
    return all;
}

} // namespace tricell::mpi
