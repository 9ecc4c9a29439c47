#include "tricell/tuning.hpp"

#include <algorithm>
#include <cmath>

#include "detail/pi.hpp"
#include "tricell/error.hpp"

namespace tricell {

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
    // Candidates: each pair once in a half list. Builds: the half stencil either way (a full
    // list with one cutoff is found through it and turned around).
    const double g = model.half ? 0.5 : 1.0, g_build = 0.5;
    const double rho = model.density;
    const double r = model.cutoff + skin;
    SkinPrediction p;
    p.skin = skin;
    p.cell_size = cell_size;
    p.cells_per_cutoff = cells_per_list_radius(cell_size, model.cutoff, skin);
    const double h = r / p.cells_per_cutoff;
    const double cells = double(stencil_cells(p.cells_per_cutoff));
    p.steps_per_build = 1 + skin / (2 * model.displacement_per_step);
    p.candidates_per_atom = g * rho * detail::sphere_volume(r);
    p.build_tests_per_atom = g_build * rho * cells * h * h * h;
    const double visits = g_build * cells / (rho * h * h * h);
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

} // namespace tricell
