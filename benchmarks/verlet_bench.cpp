// Verlet-list benchmark: steps per second of the md_lj example with a Verlet list at
// several skins, against a fresh neighbour list every step, and the skin the cost model picks.
//
// Workload: 2048 Lennard-Jones atoms (FCC at rho = 0.8, started at T = 1, in a tilted box),
// r_c = 2.5, dt = 0.005, half list, positions wrapped every step; every run starts from the same
// state after 500 steps of equilibration. Before the timed runs, main() calibrates the cost
// model on this system: build cost (for several list radii and cell sizes, fitted to
// b0 + b1 n_t + b2 n_v per atom), refresh cost (fitted to f0 + f1 n_c per atom) and the largest
// displacement per step. tricell::tune_skin() then picks the skin and cell size. The timed runs
// use that cell size for every skin, so only the skin varies. The summary at the end states
// whether the tuned skin's time per step is within 10 % of the best measured skin.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <map>
#include <string>
#include <vector>

#include <Eigen/Dense>
#include <benchmark/benchmark.h>

#include "lj_system.hpp"
#include "policy/cost_model.hpp"
#include <tricell/verlet.hpp>

namespace {

using Clock = std::chrono::steady_clock;

constexpr double cutoff = 2.5;
constexpr int cells = 8; // 4 * 8^3 = 2048 atoms
constexpr int timed_steps = 1000;

md_lj::LjSystem equilibrated() {
    md_lj::MdOptions options;
    md_lj::LjSimulation sim(md_lj::make_fcc(cells, 0.8, 1.0, 1), options);
    for (int s = 0; s < 500; ++s) {
        sim.step();
    }
    return sim.system();
}

const md_lj::LjSystem& start() {
    static const md_lj::LjSystem sys = equilibrated();
    return sys;
}

template <class F> double best_seconds(int repeats, F&& f) {
    double best = 1e30;
    for (int r = 0; r < repeats; ++r) {
        const auto t0 = Clock::now();
        f();
        best = std::min(best, std::chrono::duration<double>(Clock::now() - t0).count());
    }
    return best;
}

tricell::VerletOptions list_options(double skin, double cells_per_cutoff) {
    tricell::VerletOptions o;
    o.neighbors.cutoff = cutoff;
    o.skin = skin;
    o.neighbors.half = true;
    o.neighbors.quantities = tricell::Quantities{false, false, true};
    o.neighbors.cells_per_cutoff = cells_per_cutoff;
    return o;
}

// Least squares y ~ X c with c >= 0 (columns with a negative coefficient are dropped).
Eigen::VectorXd fit_non_negative(const Eigen::MatrixXd& x, const Eigen::VectorXd& y) {
    std::vector<int> keep;
    for (int c = 0; c < x.cols(); ++c) {
        keep.push_back(c);
    }
    while (true) {
        Eigen::MatrixXd sub(x.rows(), Eigen::Index(keep.size()));
        for (std::size_t k = 0; k < keep.size(); ++k) {
            sub.col(Eigen::Index(k)) = x.col(keep[k]);
        }
        const Eigen::VectorXd c = sub.colPivHouseholderQr().solve(y);
        Eigen::VectorXd full = Eigen::VectorXd::Zero(x.cols());
        int worst = -1;
        for (std::size_t k = 0; k < keep.size(); ++k) {
            full[keep[k]] = c[Eigen::Index(k)];
            if (c[Eigen::Index(k)] < 0 && (worst < 0 || c[Eigen::Index(k)] < c[worst])) {
                worst = int(k);
            }
        }
        if (worst < 0) {
            return full;
        }
        keep.erase(keep.begin() + worst);
    }
}

const char* rule_name(tricell::CellSize rule) {
    switch (rule) {
    case tricell::CellSize::list_radius:
        return "h=r_l";
    case tricell::CellSize::cutoff:
        return "h=r_c";
    case tricell::CellSize::half_list_radius:
        return "h=r_l/2";
    case tricell::CellSize::third_list_radius:
        return "h=r_l/3";
    }
    return "?";
}

const tricell::CellSize all_rules[] = {tricell::CellSize::list_radius, tricell::CellSize::cutoff,
                                       tricell::CellSize::half_list_radius,
                                       tricell::CellSize::third_list_radius};

// Measures costs on the equilibrated system and fits the model.
tricell::SkinCostModel calibrate() {
    const md_lj::LjSystem& sys = start();
    const double n = double(sys.positions.size());
    tricell::SkinCostModel model;
    model.cutoff = cutoff;
    model.density = n / sys.box.volume();
    model.half = true;
    model.max_skin = 1.0;

    // Largest displacement per step (minimum image), averaged over 200 steps.
    {
        md_lj::MdOptions options;
        md_lj::LjSimulation sim(sys, options);
        double sum = 0;
        for (int s = 0; s < 200; ++s) {
            const std::vector<Eigen::Vector3d> before = sim.system().positions;
            sim.step();
            double largest = 0;
            for (std::size_t i = 0; i < before.size(); ++i) {
                const tricell::Cartesian d(sim.system().positions[i] - before[i]);
                largest = std::max(largest, sys.box.minimum_image(d).distance);
            }
            sum += largest;
        }
        model.displacement_per_step = sum / 200;
    }

    // Builds and refreshes at several radii and cell sizes, seconds per atom.
    std::vector<double> build_y, build_t, build_v, refresh_y, refresh_c;
    for (const double skin : {0.0, 0.2, 0.4, 0.6, 0.8}) {
        for (const tricell::CellSize rule : all_rules) {
            const double k = tricell::cells_per_list_radius(rule, cutoff, skin);
            tricell::VerletList list(list_options(skin, k));
            const double rebuild = best_seconds(7, [&] { list.rebuild(sys.box, sys.positions); });
            const double refresh = best_seconds(7, [&] { list.update(sys.box, sys.positions); });
            const tricell::SkinPrediction p = tricell::predict_skin_cost(model, skin, rule);
            const double h = (cutoff + skin) / k;
            build_y.push_back((rebuild - refresh) / n);
            build_t.push_back(p.build_tests_per_atom);
            build_v.push_back(0.5 * double(tricell::stencil_cells(k)) /
                              (model.density * h * h * h));
            if (rule == tricell::CellSize::half_list_radius) {
                refresh_y.push_back(refresh / n);
                refresh_c.push_back(p.candidates_per_atom);
            }
        }
    }
    Eigen::MatrixXd xb(Eigen::Index(build_y.size()), 3);
    Eigen::VectorXd yb(Eigen::Index(build_y.size()));
    for (std::size_t r = 0; r < build_y.size(); ++r) {
        xb.row(Eigen::Index(r)) << 1, build_t[r], build_v[r];
        yb[Eigen::Index(r)] = build_y[r];
    }
    const Eigen::VectorXd b = fit_non_negative(xb, yb);
    Eigen::MatrixXd xf(Eigen::Index(refresh_y.size()), 2);
    Eigen::VectorXd yf(Eigen::Index(refresh_y.size()));
    for (std::size_t r = 0; r < refresh_y.size(); ++r) {
        xf.row(Eigen::Index(r)) << 1, refresh_c[r];
        yf[Eigen::Index(r)] = refresh_y[r];
    }
    const Eigen::VectorXd f = fit_non_negative(xf, yf);
    model.build_per_atom = b[0];
    model.build_per_test = b[1];
    model.build_per_cell_visit = b[2];
    model.refresh_per_atom = f[0];
    model.refresh_per_candidate = f[1];
    return model;
}

struct Run {
    std::string label;
    double seconds_per_step = 1e30; // best over repetitions
    double steps_per_build = 0;
};
std::map<std::string, Run> runs;

void bm_md(benchmark::State& state, const std::string& label, md_lj::MdOptions options) {
    Run& run = runs[label];
    run.label = label;
    for (auto _ : state) {
        state.PauseTiming();
        md_lj::LjSimulation sim(start(), options);
        const std::size_t builds0 = sim.builds();
        state.ResumeTiming();
        const auto t0 = Clock::now();
        for (int s = 0; s < timed_steps; ++s) {
            sim.step();
        }
        const double seconds = std::chrono::duration<double>(Clock::now() - t0).count();
        run.seconds_per_step = std::min(run.seconds_per_step, seconds / timed_steps);
        run.steps_per_build = double(timed_steps) / double(sim.builds() - builds0);
        state.counters["builds"] = double(sim.builds() - builds0);
    }
    state.counters["steps/s"] = benchmark::Counter(double(timed_steps) * double(state.iterations()),
                                                   benchmark::Counter::kIsRate);
}

} // namespace

int main(int argc, char** argv) {
    benchmark::Initialize(&argc, argv);
    const tricell::SkinCostModel model = calibrate();
    const double n = double(start().positions.size());
    std::printf("cost model for %d atoms (rho %.3f, r_c %.1f, half list), per atom:\n", int(n),
                model.density, cutoff);
    std::printf("  displacement per step v = %.4f\n", model.displacement_per_step);
    std::printf("  build   = %.3g s + %.3g s * tests + %.3g s * cell visits\n",
                model.build_per_atom, model.build_per_test, model.build_per_cell_visit);
    std::printf("  refresh = %.3g s + %.3g s * candidates\n", model.refresh_per_atom,
                model.refresh_per_candidate);
    std::printf("  predicted cost per step (us, whole system) by skin and cell size:\n");
    std::printf("  %6s", "skin");
    for (const tricell::CellSize rule : all_rules) {
        std::printf(" %9s", rule_name(rule));
    }
    std::printf("\n");
    const std::vector<double> skins{0.0, 0.1, 0.2, 0.3, 0.4, 0.5, 0.8};
    for (const double skin : skins) {
        std::printf("  %6.2f", skin);
        for (const tricell::CellSize rule : all_rules) {
            std::printf(" %9.1f",
                        1e6 * n * tricell::predict_skin_cost(model, skin, rule).cost_per_step);
        }
        std::printf("\n");
    }
    for (const tricell::CellSize rule : all_rules) {
        const tricell::SkinPrediction p = tricell::tune_skin(model, rule);
        std::printf("  best skin with %-8s %.3f (%.1f us per step, %.1f steps per build)\n",
                    rule_name(rule), p.skin, 1e6 * n * p.cost_per_step, p.steps_per_build);
    }
    const tricell::SkinPrediction tuned = tricell::tune_skin(model);
    std::printf("  tuned: skin %.3f, %s (cells_per_cutoff %.3f)\n\n", tuned.skin,
                rule_name(tuned.cell_size), tuned.cells_per_cutoff);
    std::fflush(stdout);

    auto add = [&](const std::string& label, md_lj::MdOptions options) {
        benchmark::RegisterBenchmark(
            ("md_lj/" + label).c_str(),
            [label, options](benchmark::State& state) { bm_md(state, label, options); })
            ->Iterations(1)
            ->Repetitions(3)
            ->Unit(benchmark::kMillisecond);
    };
    md_lj::MdOptions every;
    every.mode = md_lj::NeighborMode::every_step;
    every.cells_per_cutoff = 2;
    add("every_step", every);
    std::vector<std::string> skin_labels;
    for (const double skin : skins) {
        md_lj::MdOptions o;
        o.skin = skin;
        o.cells_per_cutoff = tricell::cells_per_list_radius(tuned.cell_size, cutoff, skin);
        char label[64];
        std::snprintf(label, sizeof label, "verlet/skin:%.2f", skin);
        skin_labels.push_back(label);
        add(label, o);
    }
    md_lj::MdOptions o;
    o.skin = tuned.skin;
    o.cells_per_cutoff = tuned.cells_per_cutoff;
    char tuned_label[64];
    std::snprintf(tuned_label, sizeof tuned_label, "verlet/tuned:%.3f", tuned.skin);
    add(tuned_label, o);
    // h = r_c against h = r_l at the tuned skin.
    for (const tricell::CellSize rule :
         {tricell::CellSize::cutoff, tricell::CellSize::list_radius}) {
        md_lj::MdOptions c = o;
        c.cells_per_cutoff = tricell::cells_per_list_radius(rule, cutoff, tuned.skin);
        add(std::string("verlet/tuned_skin_") + rule_name(rule), c);
    }
    benchmark::RunSpecifiedBenchmarks();
    benchmark::Shutdown();
    if (runs.count(tuned_label) == 0) {
        return 0; // filtered out
    }

    std::printf("\nsummary (best of 3 runs of %d steps each):\n", timed_steps);
    // The model column is the list work only (builds and refreshes); the measured time per step
    // also holds the force loop and the integrator, which do not depend on the skin.
    std::printf("  %-28s %10s %12s %14s %16s\n", "run", "steps/s", "us/step", "steps/build",
                "model list us");
    double best = 1e30;
    std::string best_label;
    for (const auto& [label, run] : runs) {
        std::printf("  %-28s %10.1f %12.1f %14.1f", label.c_str(), 1 / run.seconds_per_step,
                    1e6 * run.seconds_per_step, run.steps_per_build);
        if (label.rfind("verlet/skin:", 0) == 0) {
            const double skin = std::stod(label.substr(12));
            std::printf(" %16.1f",
                        1e6 * n *
                            tricell::predict_skin_cost(model, skin, tuned.cell_size).cost_per_step);
            if (run.seconds_per_step < best) {
                best = run.seconds_per_step;
                best_label = label;
            }
        }
        std::printf("\n");
    }
    const double ratio = runs[tuned_label].seconds_per_step / best;
    std::printf("tuned skin %.3f: %.1f us/step; best measured skin (%s): %.1f us/step; ratio %.3f "
                "-> %s 10%% of the best\n",
                tuned.skin, 1e6 * runs[tuned_label].seconds_per_step, best_label.c_str(),
                1e6 * best, ratio, ratio <= 1.10 ? "within" : "NOT within");
    return 0;
}
