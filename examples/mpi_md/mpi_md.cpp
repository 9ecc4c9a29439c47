// mpi_md: the md_lj Lennard-Jones NVE dynamics (FCC melting at T = 1, rho = 0.8, tilted box)
// over MPI ranks with tricell::mpi (domain decomposition, halo exchange, distributed Verlet
// list). Prints the energies per atom as it goes (at step 0 and every tenth of the run), the list
// builds, the speed (wall time of the whole loop, the slowest rank's) and the halo (ghost fraction
// and neighbour ranks per rank). With --check, rank 0 also runs the serial md_lj simulation and the
// energies are compared at every step, and it prints the largest difference (exit status 1 above
// 1e-8 per atom); the speed then includes the serial steps. With --traffic, rank 0 prints the
// messages and bytes each rank sent per exchange, as counted by the library
// (DistributedVerletList::traffic(), means over ranks), beside the model of
// tricell/mpi/traffic.hpp.
//
//   mpirun -np K mpi_md [--steps 200] [--atoms 864 | --atoms-per-rank N] [--skin 0.3]
//                       [--seed 1] [--dt 0.005] [--check] [--traffic]
//
// --atoms is rounded to the nearest 4 n^3; --atoms-per-rank N asks for about N K atoms (weak
// scaling).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <optional>
#include <string>

#include "mpi_lj.hpp"

namespace {

struct HaloSummary {
    double ghost_fraction_mean = 0, ghost_fraction_max = 0;
    double neighbors_mean = 0;
    int neighbors_max = 0;
};

HaloSummary summarize(const tricell::mpi::Decomposition& d, const tricell::mpi::Halo& halo) {
    const tricell::mpi::HaloStats& s = halo.stats();
    double fraction = s.owned > 0 ? double(s.ghosts) / double(s.owned) : 0;
    double neighbors = s.neighbor_ranks;
    HaloSummary out;
    MPI_Allreduce(&fraction, &out.ghost_fraction_mean, 1, MPI_DOUBLE, MPI_SUM, d.comm());
    MPI_Allreduce(&fraction, &out.ghost_fraction_max, 1, MPI_DOUBLE, MPI_MAX, d.comm());
    MPI_Allreduce(&neighbors, &out.neighbors_mean, 1, MPI_DOUBLE, MPI_SUM, d.comm());
    MPI_Allreduce(&s.neighbor_ranks, &out.neighbors_max, 1, MPI_INT, MPI_MAX, d.comm());
    out.ghost_fraction_mean /= d.size();
    out.neighbors_mean /= d.size();
    return out;
}

// Mean over ranks.
double mean(const tricell::mpi::Decomposition& d, double mine) {
    double all = 0;
    MPI_Allreduce(&mine, &all, 1, MPI_DOUBLE, MPI_SUM, d.comm());
    return all / d.size();
}

// Counted per exchange (means over ranks) against the model, one table row per kind.
void print_traffic(const tricell::mpi::Decomposition& d, const mpi_md::MpiLjSimulation& sim,
                   double reach) {
    const tricell::mpi::ListTraffic& t = sim.list().traffic();
    const tricell::mpi::HaloStats& s = sim.list().halo().stats();
    const tricell::mpi::HaloModel model =
        tricell::mpi::halo_model(d, sim.box(), reach, sim.list().halo().ghost_set());
    const double owned = mean(d, double(s.owned));
    const double ghosts = mean(d, double(s.ghosts));
    const double sent_ghosts = model.sent_ghosts_per_atom * owned;
    struct Row {
        const char* kind;
        const tricell::mpi::Traffic& counted;
        double bytes_per_ghost; // 0: not modelled
    };
    const Row rows[] = {
        {"halo update (positions)", t.halo_update, double(tricell::mpi::Halo::update_record_bytes)},
        {"reverse_sum (forces)", t.reverse_sum, 24.0},
        {"halo build", t.halo_build, double(tricell::mpi::Halo::build_record_bytes)},
        {"migration (neighbours)", t.migration, 0.0},
    };
    if (d.rank() == 0) {
        std::printf("# traffic per rank per exchange, counted (mean over ranks) / model; ghosts "
                    "per owned atom %.3f / %.3f (sent %.3f)\n",
                    ghosts / owned, model.ghosts_per_atom, model.sent_ghosts_per_atom);
        std::printf("# | ranks | kind | exchanges | messages | model | bytes | model |\n");
    }
    for (const Row& r : rows) {
        const double calls = double(std::max<std::uint64_t>(r.counted.exchanges, 1));
        const double messages = mean(d, double(r.counted.messages) / calls);
        const double bytes = mean(d, double(r.counted.bytes) / calls);
        if (d.rank() == 0) {
            std::printf("| %d | %s | %llu | %.2f | %d | %.0f | ", d.size(), r.kind,
                        static_cast<unsigned long long>(r.counted.exchanges), messages,
                        model.messages, bytes);
            if (r.bytes_per_ghost > 0) {
                std::printf("%.0f |\n", r.bytes_per_ghost * sent_ghosts);
            } else {
                std::printf("- |\n");
            }
        }
    }
}

int run(int argc, char** argv) {
    int steps = 200;
    int atoms = 864;
    int atoms_per_rank = 0;
    unsigned long long seed = 1;
    bool check = false;
    bool traffic = false;
    md_lj::MdOptions options;
    for (int k = 1; k < argc; ++k) {
        const std::string arg = argv[k];
        const char* value = k + 1 < argc ? argv[k + 1] : nullptr;
        if (arg == "--check") {
            check = true;
            continue;
        }
        if (arg == "--traffic") {
            traffic = true;
            continue;
        }
        if (value == nullptr || (arg != "--steps" && arg != "--skin" && arg != "--atoms" &&
                                 arg != "--seed" && arg != "--dt" && arg != "--atoms-per-rank")) {
            std::fprintf(stderr, "usage: mpi_md [--steps N] [--atoms N | --atoms-per-rank N] "
                                 "[--skin D] [--seed S] [--dt T] [--check] [--traffic]\n");
            return 2;
        }
        ++k;
        if (arg == "--steps") {
            steps = std::atoi(value);
        } else if (arg == "--skin") {
            options.skin = std::atof(value);
        } else if (arg == "--atoms") {
            atoms = std::atoi(value);
        } else if (arg == "--atoms-per-rank") {
            atoms_per_rank = std::atoi(value);
        } else if (arg == "--seed") {
            seed = std::strtoull(value, nullptr, 10);
        } else {
            options.dt = std::atof(value);
        }
    }
    tricell::mpi::Decomposition decomposition(MPI_COMM_WORLD);
    const int rank = decomposition.rank();
    if (atoms_per_rank > 0) {
        atoms = atoms_per_rank * decomposition.size();
    }
    const int cells = std::max(1, int(std::lround(std::cbrt(atoms / 4.0))));
    const md_lj::LjSystem system = md_lj::make_fcc(cells, 0.8, 1.0, seed);
    mpi_md::MpiLjSimulation sim(decomposition, system, options);
    const double n = double(system.positions.size());
    // The serial reference exists only where it is compared (rank 0 with --check).
    std::optional<md_lj::LjSimulation> serial;
    if (check && rank == 0) {
        serial.emplace(system, options);
    }
    const auto& dims = decomposition.dims();
    if (rank == 0) {
        std::printf("# %d atoms on %d ranks (%d x %d x %d), rho 0.8, r_c %g, skin %g, dt %g\n",
                    int(n), decomposition.size(), dims[0], dims[1], dims[2], options.cutoff,
                    options.skin, options.dt);
        std::printf("# step  kinetic/N  potential/N  total/N%s\n",
                    serial ? "  |total - serial|/N" : "");
    }
    const int every = std::max(1, steps / 10);
    double worst = 0;
    MPI_Barrier(decomposition.comm());
    const auto start = std::chrono::steady_clock::now();
    for (int s = 0; s <= steps; ++s) {
        if (s > 0) {
            sim.step();
            if (serial) {
                serial->step();
            }
        }
        if (!check && s % every != 0) {
            continue; // energies are collectives: only where printed or compared
        }
        const double kinetic = sim.kinetic_energy();
        const double potential = sim.potential_energy();
        double difference = 0;
        if (serial) {
            difference = std::abs(kinetic + potential - serial->total_energy()) / n;
            difference = std::max(difference, std::abs(potential - serial->potential_energy()) / n);
            worst = std::max(worst, difference);
        }
        if (rank == 0 && s % every == 0) {
            std::printf("%6d %10.6f %12.6f %10.6f", s, kinetic / n, potential / n,
                        (kinetic + potential) / n);
            if (serial) {
                std::printf("  %.3g", difference);
            }
            std::printf("\n");
        }
    }
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    double slowest = 0;
    MPI_Allreduce(&seconds, &slowest, 1, MPI_DOUBLE, MPI_MAX, decomposition.comm());
    const HaloSummary halo = summarize(decomposition, sim.list().halo());
    if (rank == 0) {
        std::printf("# list builds: %zu in %d steps; %.1f steps/s; %.3g atom-steps/s per rank\n",
                    sim.builds(), steps, steps / slowest,
                    n * steps / slowest / decomposition.size());
        std::printf("# ghosts per owned atom (list radius %g): mean %.3f, max %.3f; neighbour "
                    "ranks: mean %.1f, max %d\n",
                    options.cutoff + options.skin, halo.ghost_fraction_mean,
                    halo.ghost_fraction_max, halo.neighbors_mean, halo.neighbors_max);
        if (serial) {
            std::printf("# largest |energy - serial| per atom: %.3g (%s)\n", worst,
                        worst <= 1e-8 ? "MATCHES SERIAL" : "DIFFERS FROM SERIAL");
        }
    }
    if (traffic) {
        print_traffic(decomposition, sim, options.cutoff + options.skin);
    }
    return serial && worst > 1e-8 ? 1 : 0;
}

} // namespace

int main(int argc, char** argv) {
    MPI_Init(&argc, &argv);
    int status = 0;
    try {
        status = run(argc, argv);
    } catch (const std::exception& e) {
        std::fprintf(stderr, "mpi_md: %s\n", e.what());
        status = 1;
    }
    int worst = 0;
    MPI_Allreduce(&status, &worst, 1, MPI_INT, MPI_MAX, MPI_COMM_WORLD);
    MPI_Finalize();
    return worst;
}
