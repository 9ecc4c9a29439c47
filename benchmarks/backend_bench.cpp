// Backend timings and the fit of the grid-vs-octree cost model (include/tricell/cost_model.hpp).
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
// i, j, S, d stored), one thread.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <random>
#include <string>
#include <vector>

#include <tricell/tricell.hpp>

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

// Median seconds of build + compute.
double time_search(const System& sys, SearchBackend backend, std::size_t leaf_size = 0,
                   int repeats = 5) {
    NeighborOptions o;
    o.cutoff = cutoff;
    o.backend = backend;
    o.leaf_size = leaf_size;
    tricell::NeighborSearch search;
    tricell::NeighborList list;
    std::vector<double> t;
    for (int r = 0; r < repeats; ++r) {
        const auto start = std::chrono::steady_clock::now();
        search.build(sys.box, sys.positions, o);
        search.compute(list);
        const auto stop = std::chrono::steady_clock::now();
        t.push_back(std::chrono::duration<double>(stop - start).count());
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

// A periodic cube of side `side`: the slab z < f side at rho_hi, the rest at rho_lo.
System mixture(double side, double f, double rho_hi, double rho_lo, std::uint64_t seed) {
    System sys;
    sys.box = Box::from_parameters(side, side, side, 90, 90, 90);
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> u(0, 1);
    const double volume = side * side * side;
    const auto n_hi = std::size_t(std::llround(rho_hi * f * volume));
    const auto n_lo = std::size_t(std::llround(rho_lo * (1 - f) * volume));
    for (std::size_t i = 0; i < n_hi; ++i) {
        sys.positions.emplace_back(side * u(rng), side * u(rng), f * side * u(rng));
    }
    for (std::size_t i = 0; i < n_lo; ++i) {
        sys.positions.emplace_back(side * u(rng), side * u(rng), side * (f + (1 - f) * u(rng)));
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

void run_uniform() {
    std::printf("# uniform: per-atom time (ns), rc = %g A\n", cutoff);
    std::printf("%10s %8s %10s %10s %10s\n", "density", "atoms", "dense", "hash", "octree");
    for (const double rho : densities) {
        const std::size_t atoms = 20000;
        const System sys = uniform(rho, atoms, 7);
        const double scale = 1e9 / double(atoms);
        std::printf("%10.4g %8zu %10.1f %10.1f %10.1f\n", rho, atoms,
                    scale * time_search(sys, SearchBackend::dense),
                    scale * time_search(sys, SearchBackend::hash),
                    scale * time_search(sys, SearchBackend::octree));
    }
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
        const System sys = uniform(rho, 20000, 7);
        std::printf("%10.4g", rho);
        for (const std::size_t s : sizes) {
            std::printf(" %7.1f", 1e9 / 20000 * time_search(sys, SearchBackend::octree, s, 3));
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
        double t[5];
        int k = 0;
        for (const SearchBackend b :
             {SearchBackend::dense, SearchBackend::linked, SearchBackend::hash,
              SearchBackend::octree, SearchBackend::automatic}) {
            t[k] = 1e3 * time_search(sys, b);
            if (side == 80.0) {
                first[k] = t[k];
            }
            last[k] = t[k];
            ++k;
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
    for (int r = 0; r < 5; ++r) { // interleaved, so drifts of the machine hit both alike
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
    if (what == "uniform" || what == "all") {
        run_uniform();
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
