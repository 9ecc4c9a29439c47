// Backend timings and the fit of the grid-vs-octree cost model (lib/policy/cost_model.hpp).
// A plain timing program, not a test; run it pinned to one core:
//     taskset -c 0 build/benchmarks/backend_bench [uniform|mixture|droplet|liquid|leaf|all]
//
// uniform  per-atom time of each backend on uniform random gases and liquids, rc = 5 A, over
//          densities from 5e-4 to 0.1 /A^3; the model's per-atom costs are fitted to these.
// mixture  the two-density system of the model: a periodic cube with a slab (volume fraction f)
//          at rho_hi and the rest at rho_lo; f from 0 to 1. Prints measured times, the measured
//          crossover f (where the octree stops being faster than the grid auto would use) and
//          the f* the fitted model predicts.
// droplet  10^4 atoms at 0.1 /A^3 (radius 28.8 A) in periodic cubes of 80, 400 and 1600 A.
// liquid   a uniform liquid (0.1 /A^3, 32000 atoms): auto against the dense grid.
// leaf     octree time against leaf_size (how the default n_max was chosen).
//
// Every time is the median of several runs of NeighborSearch::build + compute (full list,
// i, j, S, d stored), one thread, in CPU time of that thread (robust on a shared machine).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <ctime>
#include <iterator>
#include <random>
#include <string>
#include <vector>

#include <Eigen/Cholesky>

#include <tricell/tricell.hpp>

#include "policy/cost_model.hpp"

namespace {

using tricell::Box;
using tricell::NeighborOptions;
using tricell::SearchBackend;

constexpr double cutoff = 5.0;
constexpr double pi = 3.14159265358979323846;

struct System {
    Box box = Box::from_parameters(1, 1, 1, 90, 90, 90);
    std::vector<Eigen::Vector3d> positions;
};

double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return v[v.size() / 2];
}

// CPU time of the calling thread, so that other processes on a shared machine (which take the
// core away, not the work) disturb the timings as little as possible.
double thread_seconds() {
    timespec t{};
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
    return double(t.tv_sec) + 1e-9 * double(t.tv_nsec);
}

// Seconds (thread CPU time) of one build + compute.
double time_once(const System& sys, SearchBackend backend, std::size_t leaf_size,
                 tricell::NeighborSearch& search, tricell::NeighborList& list) {
    NeighborOptions o;
    o.cutoff = cutoff;
    o.backend = backend;
    o.leaf_size = leaf_size;
    const double start = thread_seconds();
    search.build(sys.box, sys.positions, o);
    search.compute(list);
    return thread_seconds() - start;
}

// Median seconds of each backend, the runs interleaved so that a drift of the machine's load hits
// every backend alike.
std::vector<double> time_backends(const System& sys, const std::vector<SearchBackend>& backends,
                                  int repeats = 9) {
    std::vector<std::vector<double>> t(backends.size());
    tricell::NeighborSearch search;
    tricell::NeighborList list;
    for (int r = 0; r < repeats; ++r) {
        for (std::size_t b = 0; b < backends.size(); ++b) {
            t[b].push_back(time_once(sys, backends[b], 0, search, list));
        }
    }
    std::vector<double> out;
    for (const std::vector<double>& v : t) {
        out.push_back(median(v));
    }
    return out;
}

double time_search(const System& sys, SearchBackend backend, std::size_t leaf_size = 0,
                   int repeats = 7) {
    tricell::NeighborSearch search;
    tricell::NeighborList list;
    std::vector<double> t;
    for (int r = 0; r < repeats; ++r) {
        t.push_back(time_once(sys, backend, leaf_size, search, list));
    }
    return median(t);
}

SearchBackend chosen(const System& sys) {
    NeighborOptions o;
    o.cutoff = cutoff;
    tricell::NeighborSearch search;
    search.build(sys.box, sys.positions, o);
    return search.info().backend;
}

// Uniform random atoms in a periodic cube.
System uniform(double density, std::size_t atoms, std::uint64_t seed) {
    System sys;
    const double side = std::cbrt(double(atoms) / density);
    sys.box = Box::from_parameters(side, side, side, 90, 90, 90);
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> u(0, side);
    for (std::size_t i = 0; i < atoms; ++i) {
        sys.positions.emplace_back(u(rng), u(rng), u(rng));
    }
    return sys;
}

// A periodic cube of side `side`: a sphere at the centre (volume fraction f) at rho_hi, the
// rest at rho_lo (a droplet in its vapour).
System mixture(double side, double f, double rho_hi, double rho_lo, std::uint64_t seed) {
    System sys;
    sys.box = Box::from_parameters(side, side, side, 90, 90, 90);
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> u(0, side);
    const double volume = side * side * side;
    const double radius = std::cbrt(3 * f * volume / (4 * pi));
    const Eigen::Vector3d centre(side / 2, side / 2, side / 2);
    const auto n_hi = std::size_t(std::llround(rho_hi * f * volume));
    const auto n_lo = std::size_t(std::llround(rho_lo * (1 - f) * volume));
    std::size_t hi = 0, lo = 0;
    while (hi < n_hi || lo < n_lo) {
        const Eigen::Vector3d p(u(rng), u(rng), u(rng));
        const bool inside = (p - centre).norm() < radius;
        if (inside && hi < n_hi) {
            sys.positions.push_back(p);
            ++hi;
        } else if (!inside && lo < n_lo) {
            sys.positions.push_back(p);
            ++lo;
        }
    }
    return sys;
}

// 10^4 atoms at 0.1 /A^3 in a sphere at the centre of a periodic cube.
System droplet(double side, std::uint64_t seed) {
    System sys;
    sys.box = Box::from_parameters(side, side, side, 90, 90, 90);
    const std::size_t atoms = 10000;
    const double radius = std::cbrt(3 * double(atoms) / (4 * pi * 0.1));
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> u(-1, 1);
    const Eigen::Vector3d centre(side / 2, side / 2, side / 2);
    while (sys.positions.size() < atoms) {
        const Eigen::Vector3d p(u(rng), u(rng), u(rng));
        if (p.squaredNorm() < 1) {
            sys.positions.push_back(centre + radius * p);
        }
    }
    return sys;
}

const double densities[] = {0.0005, 0.001, 0.002, 0.005, 0.01, 0.02, 0.05, 0.1};

// Least squares with relative weights: minimises sum ((basis . c - y) / y)^2.
template <int P>
Eigen::Matrix<double, P, 1> fit(const std::vector<Eigen::Matrix<double, P, 1>>& basis,
                                const std::vector<double>& y) {
    Eigen::Matrix<double, P, P> a = Eigen::Matrix<double, P, P>::Zero();
    Eigen::Matrix<double, P, 1> b = Eigen::Matrix<double, P, 1>::Zero();
    for (std::size_t k = 0; k < y.size(); ++k) {
        const Eigen::Matrix<double, P, 1> row = basis[k] / y[k];
        a += row * row.transpose();
        b += row;
    }
    return a.ldlt().solve(b);
}

// The grid auto would use without the octree: dense when the cells fit under its cap.
SearchBackend grid_for(const System& sys) {
    double cells = 1;
    for (int k = 0; k < 3; ++k) {
        cells *= std::max(1.0, std::floor(sys.box.perpendicular_widths()[k] / cutoff));
    }
    return tricell::choose_grid_backend(cells, 4.0 * double(sys.positions.size()) + 64);
}

// Fits OctreeCosts to per-atom times of uniform systems (see cost_model.hpp).
tricell::OctreeCosts fit_uniform(bool print) {
    tricell::OctreeCosts costs;
    std::vector<Eigen::Vector3d> dense_basis, hash_basis;
    std::vector<double> dense_y, hash_y, oct_y, oct_x;
    double occupancy = 0;
    if (print) {
        std::printf("# uniform: per-atom time (ns), rc = %g A, 40000 atoms\n", cutoff);
        std::printf("%10s %10s %10s %10s %10s\n", "density", "dense", "hash", "octree",
                    "atoms/leaf");
    }
    for (const double rho : densities) {
        const std::size_t atoms = 40000; // the size of the mixtures below
        const System sys = uniform(rho, atoms, 7);
        const double scale = 1e9 / double(atoms);
        const std::vector<double> t =
            time_backends(sys, {SearchBackend::dense, SearchBackend::hash, SearchBackend::octree});
        const double d = scale * t[0], h = scale * t[1], o = scale * t[2];
        NeighborOptions opt;
        opt.cutoff = cutoff;
        opt.backend = SearchBackend::octree;
        tricell::NeighborSearch search;
        search.build(sys.box, sys.positions, opt);
        const double per_leaf = double(atoms) / double(search.info().stored_cells);
        occupancy += per_leaf / double(std::size(densities));
        if (print) {
            std::printf("%10.4g %10.1f %10.1f %10.1f %10.1f\n", rho, d, h, o, per_leaf);
        }
        const double lambda = rho * cutoff * cutoff * cutoff;
        const Eigen::Vector3d basis(1, 27 * (1 - std::exp(-lambda)) / lambda, 27 * lambda);
        if (grid_for(sys) == SearchBackend::dense) { // the dense grid at full resolution only
            dense_basis.push_back(basis);
            dense_y.push_back(d);
        }
        hash_basis.push_back(basis);
        hash_y.push_back(h);
        oct_x.push_back(rho);
        oct_y.push_back(o);
    }
    costs.leaf_occupancy = occupancy;
    const Eigen::Vector3d dc = fit<3>(dense_basis, dense_y);
    const Eigen::Vector3d hc = fit<3>(hash_basis, hash_y);
    std::vector<Eigen::Vector2d> oct_basis;
    tricell::OctreeCosts unit = costs;
    unit.octree[0] = 0;
    unit.octree[1] = 1;
    for (const double rho : oct_x) {
        oct_basis.emplace_back(1, tricell::octree_cost_per_atom(rho, cutoff, unit));
    }
    const Eigen::Vector2d oc = fit<2>(oct_basis, oct_y);
    for (int k = 0; k < 3; ++k) {
        costs.dense[k] = dc[k];
        costs.hash[k] = hc[k];
    }
    costs.octree[0] = oc[0];
    costs.octree[1] = oc[1];
    if (print) {
        std::printf("fitted: dense {%.4g, %.4g, %.4g}  hash {%.4g, %.4g, %.4g}  octree {%.4g, "
                    "%.4g}  leaf_occupancy %.3g\n",
                    dc[0], dc[1], dc[2], hc[0], hc[1], hc[2], oc[0], oc[1], occupancy);
        std::printf("%10s %10s %10s %10s  (model, ns per atom)\n", "density", "dense", "hash",
                    "octree");
        for (const double rho : densities) {
            std::printf("%10.4g %10.1f %10.1f %10.1f\n", rho,
                        tricell::grid_cost_per_atom(SearchBackend::dense, rho, cutoff, costs),
                        tricell::grid_cost_per_atom(SearchBackend::hash, rho, cutoff, costs),
                        tricell::octree_cost_per_atom(rho, cutoff, costs));
        }
    }
    return costs;
}

// The two-density sweep: measured crossover against the model's f*.
// The box grows as f shrinks so that every system holds `atoms` atoms, the size of the uniform
// systems the costs were fitted on (per-atom costs grow with N through the caches).
void run_mixture(const tricell::OctreeCosts& costs, double atoms, double rho_hi, double rho_lo,
                 const std::vector<double>& fractions) {
    std::printf("# mixture: %g atoms in a periodic cube, a sphere of volume fraction f at %g /A^3, "
                "the rest at %g /A^3\n",
                atoms, rho_hi, rho_lo);
    std::printf("%8s %8s %7s %10s %10s %10s %10s\n", "f", "box A", "auto's", "hash ms", "octree ms",
                "model grid", "model oct");
    double measured = -1, previous_f = 0, previous_gap = 0;
    for (std::size_t k = 0; k < fractions.size(); ++k) {
        const double f = fractions[k];
        const double volume = atoms / (f * rho_hi + (1 - f) * rho_lo);
        const double side = std::cbrt(volume);
        const System sys = mixture(side, f, rho_hi, rho_lo, 5 + k);
        // The model's f* compares the octree with the hash (what auto uses in these vapours,
        // where the dense grid's cap bites); the grid auto would pick is shown alongside.
        const SearchBackend grid = SearchBackend::hash;
        const std::vector<double> t = time_backends(sys, {grid, SearchBackend::octree});
        const double g = 1e3 * t[0], o = 1e3 * t[1];
        const double n_hi = f * volume * rho_hi, n_lo = (1 - f) * volume * rho_lo;
        const double mg = 1e-6 * (n_hi * tricell::grid_cost_per_atom(grid, rho_hi, cutoff, costs) +
                                  n_lo * tricell::grid_cost_per_atom(grid, rho_lo, cutoff, costs));
        const double mo = 1e-6 * (n_hi * tricell::octree_cost_per_atom(rho_hi, cutoff, costs) +
                                  n_lo * tricell::octree_cost_per_atom(rho_lo, cutoff, costs));
        std::printf("%8.4g %8.1f %7s %10.2f %10.2f %10.2f %10.2f\n", f, side,
                    tricell::backend_name(grid_for(sys)), g, o, mg, mo);
        const double gap = o - g; // < 0: the octree is faster
        if (k > 0 && measured < 0 && previous_gap < 0 && gap >= 0) {
            measured = previous_f + (f - previous_f) * (-previous_gap) / (gap - previous_gap);
        }
        if (k == 0 && gap >= 0) {
            measured = 0;
        }
        previous_f = f;
        previous_gap = gap;
    }
    const SearchBackend grid = SearchBackend::hash;
    const double predicted = tricell::octree_crossover(grid, rho_hi, rho_lo, cutoff, costs);
    if (measured < 0) {
        std::printf("(the octree is faster at every f measured: the crossover lies beyond %g)\n",
                    fractions.back());
    }
    std::printf("crossover: measured f = %.4g, predicted f* = %.4g (%s grid): ", measured,
                predicted, tricell::backend_name(grid));
    const bool small = predicted < 0.1 || measured < 0.1;
    const bool ok =
        small ? (measured > 0 && predicted / measured <= 1.5 && measured / predicted <= 1.5) ||
                    std::abs(predicted - measured) <= 0.01
              : std::abs(predicted - measured) <= 0.1;
    std::printf("%s (%s)\n", ok ? "within the bound" : "OUTSIDE the bound",
                small ? "factor 1.5" : "+-0.1");
}

void run_leaf() {
    std::printf("# octree per-atom time (ns) against leaf_size, rc = %g A\n", cutoff);
    std::printf("%10s", "density");
    const std::size_t sizes[] = {2, 4, 8, 12, 16, 24, 32, 48, 64};
    for (const std::size_t s : sizes) {
        std::printf(" %7zu", s);
    }
    std::printf("\n");
    for (const double rho : densities) {
        const System sys = uniform(rho, 40000, 7);
        std::printf("%10.4g", rho);
        for (const std::size_t s : sizes) {
            std::printf(" %7.1f", 1e9 / 40000 * time_search(sys, SearchBackend::octree, s, 3));
        }
        std::printf("\n");
    }
}

void run_droplet() {
    std::printf("# droplet: 10^4 atoms at 0.1 /A^3 (radius 28.8 A), rc = %g A, ms\n", cutoff);
    std::printf("%8s %10s %10s %10s %10s %10s %8s\n", "box", "dense", "linked", "hash", "octree",
                "auto", "auto is");
    double first[5] = {0, 0, 0, 0, 0};
    double last[5] = {0, 0, 0, 0, 0};
    for (const double side : {80.0, 400.0, 1600.0}) {
        const System sys = droplet(side, 3);
        const std::vector<double> seconds =
            time_backends(sys, {SearchBackend::dense, SearchBackend::linked, SearchBackend::hash,
                                SearchBackend::octree, SearchBackend::automatic});
        double t[5];
        for (int k = 0; k < 5; ++k) {
            t[k] = 1e3 * seconds[std::size_t(k)];
            if (side == 80.0) {
                first[k] = t[k];
            }
            last[k] = t[k];
        }
        std::printf("%8g %10.2f %10.2f %10.2f %10.2f %10.2f %8s\n", side, t[0], t[1], t[2], t[3],
                    t[4], tricell::backend_name(chosen(sys)));
    }
    std::printf("%8s %10.2f %10.2f %10.2f %10.2f %10.2f   (1600 A / 80 A)\n", "ratio",
                last[0] / first[0], last[1] / first[1], last[2] / first[2], last[3] / first[3],
                last[4] / first[4]);
}

void run_liquid() {
    const System sys = uniform(0.1, 32000, 11);
    std::vector<double> dense, automatic;
    for (int r = 0; r < 11; ++r) { // interleaved, so drifts of the machine hit both alike
        dense.push_back(time_search(sys, SearchBackend::dense));
        automatic.push_back(time_search(sys, SearchBackend::automatic));
    }
    const double d = median(dense), a = median(automatic);
    std::printf("# uniform liquid, 32000 atoms at 0.1 /A^3, rc = %g A\n", cutoff);
    std::printf("dense %.2f ms, auto (%s) %.2f ms, auto / dense = %.3f\n", 1e3 * d,
                tricell::backend_name(chosen(sys)), 1e3 * a, a / d);
}

} // namespace

int main(int argc, char** argv) {
    const std::string what = argc > 1 ? argv[1] : "all";
    if (what == "uniform" || what == "mixture" || what == "all") {
        const tricell::OctreeCosts costs = fit_uniform(true);
        if (what != "uniform") {
            // A liquid droplet in its vapour (density ratio 100), and a ratio of 100 at lower
            // density.
            run_mixture(costs, 40000, 0.1, 0.001,
                        {0.002, 0.005, 0.008, 0.01, 0.012, 0.015, 0.02, 0.025, 0.03, 0.04, 0.05});
            run_mixture(costs, 40000, 0.05, 0.0005,
                        {0.005, 0.01, 0.015, 0.02, 0.025, 0.03, 0.04, 0.05, 0.07, 0.1});
        }
    }
    if (what == "leaf") {
        run_leaf();
    }
    if (what == "droplet" || what == "all") {
        run_droplet();
    }
    if (what == "liquid" || what == "all") {
        run_liquid();
    }
    return 0;
}
