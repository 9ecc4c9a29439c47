// mpi_balance: how evenly three boundary rules share the work of a gas-liquid system.
//
// A liquid slab (density 0.8) fills the first third of an orthorhombic 48 x 16 x 16 box along a,
// gas (density 0.05) the rest; positions uniform at random in each phase (seeded). For the
// domain grid (K x 1 x 1 slabs by default, or MPI_Dims_create's with --grid), each rule places
// the boundaries (tricell::mpi::balance), the atoms migrate, and every rank builds its full list
// at r_c = 2.5 (tricell::mpi::DistributedSearch). Printed per rule, as max / mean over ranks:
// owned atoms, the pairs of owned atoms (the force-loop work), the moment model's estimate, and
// the measured time of the local search (halo exchange excluded; noisy when oversubscribed).
//
//   mpirun -np K mpi_balance [--grid] [--seed 1]
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <random>
#include <string>
#include <vector>

#include "tricell/mpi.hpp"

namespace {

struct Spread {
    double max = 0, mean = 0;
};

Spread spread(double mine, MPI_Comm comm) {
    int size = 1;
    MPI_Comm_size(comm, &size);
    Spread s;
    MPI_Allreduce(&mine, &s.max, 1, MPI_DOUBLE, MPI_MAX, comm);
    MPI_Allreduce(&mine, &s.mean, 1, MPI_DOUBLE, MPI_SUM, comm);
    s.mean /= size;
    return s;
}

} // namespace

int main(int argc, char** argv) {
    MPI_Init(&argc, &argv);
    bool grid = false;
    unsigned long long seed = 1;
    for (int k = 1; k < argc; ++k) {
        const std::string arg = argv[k];
        if (arg == "--grid") {
            grid = true;
        } else if (arg == "--seed" && k + 1 < argc) {
            seed = std::strtoull(argv[++k], nullptr, 10);
        }
    }
    int size = 1, rank = 0;
    MPI_Comm_size(MPI_COMM_WORLD, &size);
    MPI_Comm_rank(MPI_COMM_WORLD, &rank);
    {
        const double lx = 48, ly = 16, lz = 16, cutoff = 2.5;
        const tricell::Box box = tricell::Box::from_parameters(lx, ly, lz, 90, 90, 90);
        // The same global system on every rank; each rank keeps every size-th atom.
        std::mt19937_64 rng(seed);
        std::uniform_real_distribution<double> unit(0, 1);
        std::vector<Eigen::Vector3d> x;
        const auto add_phase = [&](double x0, double x1, double density) {
            const auto n = std::size_t(density * (x1 - x0) * ly * lz);
            for (std::size_t a = 0; a < n; ++a) {
                x.emplace_back(x0 + (x1 - x0) * unit(rng), ly * unit(rng), lz * unit(rng));
            }
        };
        add_phase(0, lx / 3, 0.8);
        add_phase(lx / 3, lx, 0.05);
        tricell::mpi::Decomposition d(MPI_COMM_WORLD, grid ? std::array<int, 3>{{0, 0, 0}}
                                                           : std::array<int, 3>{{size, 1, 1}});
        if (rank == 0) {
            std::printf("# gas-liquid: %zu atoms, liquid 0.8 in a third of %g x %g x %g, gas "
                        "0.05; r_c %g; %d ranks as %d x %d x %d\n",
                        x.size(), lx, ly, lz, cutoff, size, d.dims()[0], d.dims()[1], d.dims()[2]);
            std::printf("# rule          atoms max/mean  pairs max/mean  model max/mean  "
                        "search time max/mean\n");
        }
        const struct {
            tricell::mpi::BalanceRule rule;
            const char* name;
        } rules[] = {{tricell::mpi::BalanceRule::equal_volume, "equal volume"},
                     {tricell::mpi::BalanceRule::equal_atoms, "equal atoms"},
                     {tricell::mpi::BalanceRule::moments, "moment model"}};
        for (const auto& r : rules) {
            tricell::mpi::LocalAtoms atoms;
            for (std::size_t g = std::size_t(rank); g < x.size(); g += std::size_t(size)) {
                atoms.ids.push_back(g);
                atoms.positions.insert(atoms.positions.end(), {x[g][0], x[g][1], x[g][2]});
            }
            tricell::mpi::balance(d, box, atoms.points(), cutoff, r.rule);
            tricell::mpi::migrate(d, box, atoms);
            const std::vector<double> model =
                tricell::mpi::estimate_rank_work(d, box, atoms.points(), cutoff);
            tricell::NeighborOptions options;
            options.cutoff = cutoff;
            tricell::mpi::DistributedSearch search;
            tricell::mpi::DistributedPairs pairs;
            search.build(d, box, atoms, options); // warm-up
            double best = 1e300;
            for (int repeat = 0; repeat < 5; ++repeat) {
                search.build(d, box, atoms, options);
                const auto start = std::chrono::steady_clock::now();
                search.compute(pairs);
                best = std::min(
                    best, std::chrono::duration<double>(std::chrono::steady_clock::now() - start)
                              .count());
            }
            const Spread a = spread(double(atoms.size()), d.comm());
            const Spread p = spread(double(pairs.size()), d.comm());
            const Spread m = spread(model[std::size_t(rank)], d.comm());
            const Spread t = spread(best, d.comm());
            if (rank == 0) {
                std::printf("%-14s  %14.3f  %14.3f  %14.3f  %20.3f\n", r.name, a.max / a.mean,
                            p.max / p.mean, m.max / m.mean, t.max / t.mean);
            }
        }
        if (rank == 0) {
            std::printf("# (1.000 is perfect balance; the force loop's work follows the pairs)\n");
        }
    }
    MPI_Finalize();
    return 0;
}
