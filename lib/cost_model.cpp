#include "tricell/cost_model.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <numeric>

#include "tricell/error.hpp"

namespace tricell {

namespace {
constexpr double pi = 3.14159265358979323846;
} // namespace

double occupancy_work(double atoms, double neighbours, const OccupancyCosts& costs) {
    if (atoms <= 0) {
        return 0;
    }
    return costs.per_visit * neighbours + costs.per_atom * atoms +
           costs.per_test * neighbours * atoms * atoms;
}

double region_work(const OccupancyMoments& m, double neighbours, const OccupancyCosts& costs) {
    return costs.per_visit * neighbours * m.nonempty + costs.per_atom * m.atoms +
           costs.per_test * neighbours * m.atoms_sq;
}

double expected_pairs(double atoms, double volume, double sphere) {
    if (!(volume > 0) || !(atoms > 0)) {
        return 0;
    }
    return atoms * atoms / volume * sphere;
}

std::vector<std::size_t> split_work(const std::vector<double>& work, std::size_t parts) {
    std::vector<std::size_t> bounds{0};
    const std::size_t units = work.size();
    const double total = std::accumulate(work.begin(), work.end(), 0.0);
    if (parts > 1 && total > 0) {
        double running = 0;
        for (std::size_t u = 0; u + 1 < units && bounds.size() < parts; ++u) {
            running += work[u];
            if (running >= total * double(bounds.size()) / double(parts)) {
                bounds.push_back(u + 1);
            }
        }
    }
    bounds.push_back(units);
    return bounds;
}

bool choose_direct(std::size_t atoms, double min_width, double radius) {
    if (!std::isfinite(min_width)) {
        return atoms <= 12;
    }
    return (atoms <= 12 && min_width < 2 * radius) || (atoms <= 32 && min_width < radius);
}

SearchBackend choose_grid_backend(double full_resolution_cells, double max_cells) {
    return full_resolution_cells <= max_cells ? SearchBackend::dense : SearchBackend::hash;
}

double cells_per_list_radius(CellSize rule, double cutoff, double skin) {
    switch (rule) {
    case CellSize::list_radius:
        return 1;
    case CellSize::cutoff:
        return (cutoff + skin) / cutoff;
    case CellSize::half_list_radius:
        return 2;
    case CellSize::third_list_radius:
        return 3;
    }
    return 2;
}

std::size_t stencil_cells(double cells_per_cutoff) {
    if (!(std::isfinite(cells_per_cutoff) && cells_per_cutoff >= 1 && cells_per_cutoff < 1e3)) {
        detail::fail<InvalidArgument>("cells_per_cutoff must be in [1, 1000) (got ",
                                      cells_per_cutoff, ")");
    }
    const int reach = int(std::ceil(cells_per_cutoff));
    const double k_sq = cells_per_cutoff * cells_per_cutoff;
    auto gap = [](int a) {
        const int g = std::max(0, std::abs(a) - 1);
        return double(g) * double(g);
    };
    std::size_t count = 0;
    for (int a = -reach; a <= reach; ++a) {
        for (int b = -reach; b <= reach; ++b) {
            for (int c = -reach; c <= reach; ++c) {
                if (gap(a) + gap(b) + gap(c) < k_sq) {
                    ++count;
                }
            }
        }
    }
    return count;
}

void SkinCostModel::validate() const {
    auto positive = [](const char* name, double v) {
        if (!(std::isfinite(v) && v > 0)) {
            detail::fail<InvalidArgument>(name, " must be > 0 (got ", v, ")");
        }
    };
    auto non_negative = [](const char* name, double v) {
        if (!(std::isfinite(v) && v >= 0)) {
            detail::fail<InvalidArgument>(name, " must be >= 0 (got ", v, ")");
        }
    };
    positive("cutoff", cutoff);
    positive("density", density);
    positive("displacement_per_step", displacement_per_step);
    non_negative("build_per_atom", build_per_atom);
    non_negative("build_per_test", build_per_test);
    non_negative("build_per_cell_visit", build_per_cell_visit);
    non_negative("refresh_per_atom", refresh_per_atom);
    non_negative("refresh_per_candidate", refresh_per_candidate);
    non_negative("max_skin", max_skin);
}

SkinPrediction predict_skin_cost(const SkinCostModel& model, double skin, CellSize cell_size) {
    model.validate();
    if (!(std::isfinite(skin) && skin >= 0)) {
        detail::fail<InvalidArgument>("skin must be >= 0 (got ", skin, ")");
    }
    const double g = model.half ? 0.5 : 1.0;
    const double rho = model.density;
    const double r = model.cutoff + skin;
    SkinPrediction p;
    p.skin = skin;
    p.cell_size = cell_size;
    p.cells_per_cutoff = cells_per_list_radius(cell_size, model.cutoff, skin);
    const double h = r / p.cells_per_cutoff;
    const double cells = double(stencil_cells(p.cells_per_cutoff));
    p.steps_per_build = 1 + skin / (2 * model.displacement_per_step);
    p.candidates_per_atom = g * rho * 4.0 / 3.0 * pi * r * r * r;
    p.build_tests_per_atom = g * rho * cells * h * h * h;
    const double visits = g * cells / (rho * h * h * h);
    p.build_cost = model.build_per_atom + model.build_per_test * p.build_tests_per_atom +
                   model.build_per_cell_visit * visits;
    p.refresh_cost = model.refresh_per_atom + model.refresh_per_candidate * p.candidates_per_atom;
    p.cost_per_step = p.build_cost / p.steps_per_build + p.refresh_cost;
    return p;
}

SkinPrediction tune_skin(const SkinCostModel& model, CellSize cell_size) {
    model.validate();
    const double max_skin = model.max_skin > 0 ? model.max_skin : model.cutoff;
    // A fine scan (the cost is smooth in the skin except where the h = r_c stencil changes),
    // then golden-section refinement around the best point.
    constexpr int samples = 2000;
    auto cost = [&](double skin) {
        return predict_skin_cost(model, skin, cell_size).cost_per_step;
    };
    int best = 0;
    double best_cost = cost(0);
    for (int s = 1; s <= samples; ++s) {
        const double c = cost(max_skin * s / samples);
        if (c < best_cost) {
            best = s;
            best_cost = c;
        }
    }
    double lo = max_skin * std::max(0, best - 1) / samples;
    double hi = max_skin * std::min(samples, best + 1) / samples;
    const double ratio = (std::sqrt(5.0) - 1) / 2;
    double a = hi - ratio * (hi - lo);
    double b = lo + ratio * (hi - lo);
    double ca = cost(a);
    double cb = cost(b);
    for (int it = 0; it < 60; ++it) {
        if (ca < cb) {
            hi = b;
            b = a;
            cb = ca;
            a = hi - ratio * (hi - lo);
            ca = cost(a);
        } else {
            lo = a;
            a = b;
            ca = cb;
            b = lo + ratio * (hi - lo);
            cb = cost(b);
        }
    }
    double skin = max_skin * best / samples;
    const double refined = 0.5 * (lo + hi);
    if (cost(refined) < best_cost) {
        skin = refined;
    }
    return predict_skin_cost(model, skin, cell_size);
}

SkinPrediction tune_skin(const SkinCostModel& model) {
    SkinPrediction best = tune_skin(model, CellSize::list_radius);
    for (const CellSize rule :
         {CellSize::cutoff, CellSize::half_list_radius, CellSize::third_list_radius}) {
        const SkinPrediction p = tune_skin(model, rule);
        if (p.cost_per_step < best.cost_per_step) {
            best = p;
        }
    }
    return best;
}

std::size_t octree_leaf_size(const OctreeCosts& costs) {
    return std::size_t(std::max(1.0, std::round(costs.leaf_size)));
}

double grid_cost_per_atom(SearchBackend grid, double density, double cutoff,
                          const OctreeCosts& costs) {
    const double* g = grid == SearchBackend::hash ? costs.hash : costs.dense;
    const double lambda = density * cutoff * cutoff * cutoff;
    const double visits = lambda > 1e-12 ? (1 - std::exp(-lambda)) / lambda : 1.0;
    constexpr double stencil = 27;
    return g[0] + g[1] * stencil * visits + g[2] * stencil * lambda;
}

double octree_cost_per_atom(double density, double cutoff, const OctreeCosts& costs) {
    const double x = density * cutoff * cutoff * cutoff;
    const double n = costs.leaf_occupancy;
    const double tests =
        8 * n + 24 * std::cbrt(n * n * x) + 6 * pi * std::cbrt(n * x * x) + 4 * pi / 3 * x;
    return costs.octree[0] + costs.octree[1] * tests;
}

bool grid_always_cheaper(SearchBackend grid, double cutoff, const OctreeCosts& costs) {
    // Both costs depend on the density only through x = rho r^3, so the answer does not depend
    // on the cutoff; the scan (70 points, each with an exp and two cube roots: about 50k
    // instructions, as much as a whole 1-atom search) is kept per thread for the last grid and
    // constants, since auto asks it on every build.
    struct Memo {
        bool valid = false;
        SearchBackend grid = SearchBackend::dense;
        OctreeCosts costs;
        bool cheaper = false;
    };
    thread_local Memo memo;
    if (memo.valid && memo.grid == grid &&
        std::memcmp(&memo.costs, &costs, sizeof(OctreeCosts)) == 0) {
        return memo.cheaper;
    }
    const double volume = cutoff * cutoff * cutoff;
    bool cheaper = true;
    for (double x = 1e-6; x <= 16; x *= 1.25) { // up to the densest fitted (0.1 /A^3 at 5 A)
        if (grid_cost_per_atom(grid, x / volume, cutoff, costs) >=
            octree_cost_per_atom(x / volume, cutoff, costs)) {
            cheaper = false;
            break;
        }
    }
    memo = Memo{true, grid, costs, cheaper};
    return cheaper;
}

double octree_crossover(SearchBackend grid, double rho_hi, double rho_lo, double cutoff,
                        const OctreeCosts& costs) {
    const double saved_lo = rho_lo * (grid_cost_per_atom(grid, rho_lo, cutoff, costs) -
                                      octree_cost_per_atom(rho_lo, cutoff, costs));
    const double lost_hi = rho_hi * (octree_cost_per_atom(rho_hi, cutoff, costs) -
                                     grid_cost_per_atom(grid, rho_hi, cutoff, costs));
    if (saved_lo <= 0) {
        return lost_hi < 0 ? 1.0 : 0.0;
    }
    if (lost_hi <= 0) {
        return 1.0;
    }
    return saved_lo / (saved_lo + lost_hi);
}

} // namespace tricell
