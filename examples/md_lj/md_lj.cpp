// md_lj: Lennard-Jones NVE molecular dynamics of an FCC crystal (melting at T = 1, rho = 0.8)
// in a tilted periodic box, with forces from a tricell::VerletList. Prints the energies per
// atom as it goes, then the number of list builds and the speed.
//
//   md_lj [--steps 2000] [--skin 0.3] [--atoms 864] [--seed 1] [--dt 0.005] [--every-step]
//
// --atoms is rounded to the nearest 4 n^3 (n FCC cells per side); --every-step recomputes the
// neighbour list at r_c every step instead of using the Verlet list.
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <string>

#include "lj_system.hpp"

int main(int argc, char** argv) {
    int steps = 2000;
    int atoms = 864;
    unsigned long long seed = 1;
    md_lj::MdOptions options;
    for (int k = 1; k < argc; ++k) {
        const std::string arg = argv[k];
        const char* value = k + 1 < argc ? argv[k + 1] : nullptr;
        if (arg == "--every-step") {
            options.mode = md_lj::NeighborMode::every_step;
            continue;
        }
        if (value == nullptr || (arg != "--steps" && arg != "--skin" && arg != "--atoms" &&
                                 arg != "--seed" && arg != "--dt")) {
            std::fprintf(stderr, "usage: md_lj [--steps N] [--skin D] [--atoms N] [--seed S] "
                                 "[--dt T] [--every-step]\n");
            return 2;
        }
        ++k;
        if (arg == "--steps") {
            steps = std::atoi(value);
        } else if (arg == "--skin") {
            options.skin = std::atof(value);
        } else if (arg == "--atoms") {
            atoms = std::atoi(value);
        } else if (arg == "--seed") {
            seed = std::strtoull(value, nullptr, 10);
        } else {
            options.dt = std::atof(value);
        }
    }
    try {
        const int cells = std::max(1, int(std::lround(std::cbrt(atoms / 4.0))));
        md_lj::LjSimulation sim(md_lj::make_fcc(cells, 0.8, 1.0, seed), options);
        const double n = double(sim.system().positions.size());
        std::printf("# %d atoms, rho 0.8, r_c %g, skin %g, dt %g, %s\n", int(n), options.cutoff,
                    options.skin, options.dt,
                    options.mode == md_lj::NeighborMode::verlet ? "Verlet list" : "every step");
        std::printf("# step  kinetic/N  potential/N  total/N\n");
        const int every = std::max(1, steps / 10);
        const auto start = std::chrono::steady_clock::now();
        for (int s = 0; s <= steps; ++s) {
            if (s > 0) {
                sim.step();
            }
            if (s % every == 0) {
                std::printf("%6d %10.6f %12.6f %10.6f\n", s, sim.kinetic_energy() / n,
                            sim.potential_energy() / n, sim.total_energy() / n);
            }
        }
        const double seconds =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        std::printf("# list builds: %zu in %d steps; %.1f steps/s\n", sim.builds(), steps,
                    steps / seconds);
    } catch (const std::exception& e) {
        std::fprintf(stderr, "md_lj: %s\n", e.what());
        return 1;
    }
    return 0;
}
