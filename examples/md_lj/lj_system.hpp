// Lennard-Jones molecular dynamics in a triclinic periodic box: the reusable part of the md_lj
// example, also used by benchmarks/verlet_bench.cpp and tests/unit/verlet_test.cpp.
//
// Reduced units (epsilon = sigma = mass = 1). The potential is cut at r_c (2.5 sigma) and shifted
// to vanish there, U(r) = 4 (r^-12 - r^-6) - U(r_c) for r < r_c. Forces come from a half
// neighbour list: each pair is visited once and its force is added to both atoms with opposite
// signs. Time integration is velocity Verlet, and the positions are wrapped into the box after
// every drift, which the Verlet list must (and does) tolerate without rebuilding. The start is
// an FCC crystal at density rho in a box whose lattice vectors are tilted by whole cubic cells
// (so the crystal stays periodic in it), with Gaussian velocities from a fixed seed scaled to
// temperature T. The neighbours come either from a tricell::VerletList with a skin or, for
// comparison, from a fresh tricell::compute_neighbors() at r_c every step.
#pragma once

#include <cmath>
#include <cstdint>
#include <random>
#include <stdexcept>
#include <utility>
#include <vector>

#include <Eigen/Core>
#include <Eigen/LU>

#include <tricell/neighbor_list.hpp>
#include <tricell/verlet.hpp>

namespace md_lj {

struct LjSystem {
    tricell::Box box = tricell::Box::from_parameters(1, 1, 1, 90, 90, 90);
    std::vector<Eigen::Vector3d> positions, velocities, forces;
};

/// An FCC crystal of 4 cells^3 atoms at `density`. With the cubic lattice constant a and
/// L = cells a, the box vectors are (L, 0, 0), (a, L, 0) and (-a, a, L): tilted by whole cells,
/// so the crystal is periodic in the box. Velocities are Gaussian (seeded), with zero total
/// momentum, scaled to the kinetic temperature `temperature` (3 N - 3 degrees of freedom).
inline LjSystem make_fcc(int cells, double density, double temperature, std::uint64_t seed) {
    if (cells < 1) {
        throw std::invalid_argument("cells must be >= 1");
    }
    const double a = std::cbrt(4.0 / density);
    const double length = cells * a;
    LjSystem sys;
    sys.box = tricell::Box::from_lammps(length, length, length, a, -a, a);
    const Eigen::Matrix3d& h = sys.box.matrix();
    const Eigen::Matrix3d h_inv = h.inverse();
    // The lattice sites inside the box, s in [0, 1)^3.
    const double basis[4][3] = {{0, 0, 0}, {0, 0.5, 0.5}, {0.5, 0, 0.5}, {0.5, 0.5, 0}};
    const Eigen::Vector3d offset(0.1, 0.2, 0.3);
    for (int i = -2; i <= cells + 2; ++i) {
        for (int j = -2; j <= cells + 2; ++j) {
            for (int k = -2; k <= cells + 2; ++k) {
                for (const auto& b : basis) {
                    const Eigen::Vector3d r =
                        a * (Eigen::Vector3d(i + b[0], j + b[1], k + b[2]) + offset);
                    // A site on a face counts on the lower face only, whatever the rounding.
                    const Eigen::Vector3d s = (h_inv * r).array() + 1e-9;
                    if ((s.array() >= 0).all() && (s.array() < 1).all()) {
                        sys.positions.push_back(r);
                    }
                }
            }
        }
    }
    const std::size_t n = sys.positions.size();
    if (n != std::size_t(4 * cells * cells * cells)) {
        throw std::logic_error("FCC construction found the wrong number of sites");
    }
    std::mt19937_64 rng(seed);
    std::normal_distribution<double> normal;
    Eigen::Vector3d momentum = Eigen::Vector3d::Zero();
    for (std::size_t i = 0; i < n; ++i) {
        sys.velocities.emplace_back(normal(rng), normal(rng), normal(rng));
        momentum += sys.velocities.back();
    }
    double twice_kinetic = 0;
    for (Eigen::Vector3d& v : sys.velocities) {
        v -= momentum / double(n);
        twice_kinetic += v.squaredNorm();
    }
    const double scale = std::sqrt(temperature * double(3 * n - 3) / twice_kinetic);
    for (Eigen::Vector3d& v : sys.velocities) {
        v *= scale;
    }
    sys.forces.assign(n, Eigen::Vector3d::Zero());
    return sys;
}

/// Sets `forces` to the Lennard-Jones forces of a half list (each pair once, D = x_j - x_i + H S
/// stored as vectors, pairs beyond r_c skipped) and returns the potential energy.
template <class List>
double lj_forces(const List& list, double cutoff, std::vector<Eigen::Vector3d>& forces) {
    for (Eigen::Vector3d& f : forces) {
        f.setZero();
    }
    const double cutoff_sq = cutoff * cutoff;
    const double inv_rc6 = 1 / (cutoff_sq * cutoff_sq * cutoff_sq);
    const double energy_shift = 4 * inv_rc6 * (inv_rc6 - 1);
    const auto& is = list.i();
    const auto& js = list.j();
    const double* d = list.vectors().data();
    double potential = 0;
    for (std::size_t k = 0; k < list.size(); ++k) {
        const Eigen::Vector3d r(d[3 * k], d[3 * k + 1], d[3 * k + 2]);
        const double r_sq = r.squaredNorm();
        if (r_sq >= cutoff_sq) {
            continue;
        }
        const double inv_r2 = 1 / r_sq;
        const double inv_r6 = inv_r2 * inv_r2 * inv_r2;
        potential += 4 * inv_r6 * (inv_r6 - 1) - energy_shift;
        // -dU/dr / r: the force on j is +scale * D, on i -scale * D.
        const Eigen::Vector3d f = (24 * inv_r6 * (2 * inv_r6 - 1) * inv_r2) * r;
        forces[js[k]] += f;
        forces[is[k]] -= f;
    }
    return potential;
}

enum class NeighborMode {
    verlet,     ///< tricell::VerletList with a skin
    every_step, ///< tricell::compute_neighbors at r_c every step
};

struct MdOptions {
    double dt = 0.005;
    double cutoff = 2.5;
    double skin = 0.3;
    double cells_per_cutoff = 2; ///< cells per list radius
    NeighborMode mode = NeighborMode::verlet;
    bool wrap = true; ///< wrap positions into the box after every drift
};

/// Velocity-Verlet NVE dynamics of an LjSystem.
class LjSimulation {
  public:
    LjSimulation(LjSystem system, const MdOptions& options)
        : sys_(std::move(system)), options_(options) {
        tricell::VerletOptions verlet;
        verlet.neighbors.cutoff = options_.cutoff;
        verlet.skin = options_.skin;
        verlet.neighbors.half = true;
        verlet.neighbors.cells_per_cutoff = options_.cells_per_cutoff;
        verlet.neighbors.quantities = tricell::Quantities{false, false, true};
        verlet_ = tricell::VerletList(verlet);
        neighbor_options_.cutoff = options_.cutoff;
        neighbor_options_.half = true;
        neighbor_options_.cells_per_cutoff = options_.cells_per_cutoff;
        neighbor_options_.quantities = tricell::Quantities{false, false, true};
        compute_forces();
    }

    /// One step: half kick, drift (and wrap), new forces, half kick.
    void step() {
        const double dt = options_.dt;
        for (std::size_t i = 0; i < sys_.positions.size(); ++i) {
            sys_.velocities[i] += 0.5 * dt * sys_.forces[i];
            sys_.positions[i] += dt * sys_.velocities[i];
            if (options_.wrap) {
                sys_.positions[i] = sys_.box.wrap(tricell::Cartesian(sys_.positions[i]));
            }
        }
        compute_forces();
        for (std::size_t i = 0; i < sys_.positions.size(); ++i) {
            sys_.velocities[i] += 0.5 * dt * sys_.forces[i];
        }
        ++steps_;
    }

    double kinetic_energy() const {
        double twice = 0;
        for (const Eigen::Vector3d& v : sys_.velocities) {
            twice += v.squaredNorm();
        }
        return 0.5 * twice;
    }
    double potential_energy() const { return potential_; }
    double total_energy() const { return kinetic_energy() + potential_; }
    /// Neighbour-list builds so far (every step in NeighborMode::every_step).
    std::size_t builds() const {
        return options_.mode == NeighborMode::verlet ? verlet_.rebuild_count() : steps_ + 1;
    }
    std::size_t steps() const { return steps_; }
    const LjSystem& system() const { return sys_; }
    const tricell::VerletList& verlet() const { return verlet_; }

  private:
    void compute_forces() {
        if (options_.mode == NeighborMode::verlet) {
            verlet_.update(sys_.box, sys_.positions);
            potential_ = lj_forces(verlet_.pairs(), options_.cutoff, sys_.forces);
        } else {
            tricell::compute_neighbors(sys_.box, sys_.positions, neighbor_options_, list_);
            potential_ = lj_forces(list_, options_.cutoff, sys_.forces);
        }
    }

    LjSystem sys_;
    MdOptions options_;
    tricell::VerletList verlet_;
    tricell::NeighborOptions neighbor_options_;
    tricell::NeighborList list_;
    double potential_ = 0;
    std::size_t steps_ = 0;
};

} // namespace md_lj
