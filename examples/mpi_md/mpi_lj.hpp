// The md_lj Lennard-Jones dynamics over MPI ranks: the reusable part of the mpi_md example, also
// used by tests/mpi/mpi_verlet_test.cpp.
//
// Every rank starts from the same global system (md_lj::make_fcc), keeps the atoms it owns in a
// tricell::mpi::LocalAtoms with velocity and force as the payload (6 doubles per atom, moved with
// the atom when it migrates), and takes its pairs from a tricell::mpi::DistributedVerletList of
// HALF lists with Newton's third law across ranks: each pair, owned-owned or owned-ghost, is on
// one rank only, which adds its force to i and the opposite to j's row (a ghost's row when j is
// a ghost); reverse_sum() then adds every ghost's row into its owner's force, one message per
// neighbour rank. Each pair force is computed once, as in the serial md_lj. The potential energy
// is the sum over the half pairs, kept per rank and summed over ranks only when asked (as an MD
// code's thermodynamic output), so a step's only collectives are the list's. Integration (velocity
// Verlet, positions wrapped after every drift) and the potential are md_lj's, so the energies match
// the serial md_lj::LjSimulation to round-off.
#pragma once

#include <cstddef>
#include <vector>

#include <mpi.h>

#include "lj_system.hpp"
#include "tricell/mpi.hpp"

namespace mpi_md {

class MpiLjSimulation {
  public:
    static constexpr std::size_t velocity = 0; // payload columns
    static constexpr std::size_t force = 3;

    /// `quantities`: what the pairs store besides i and j; the force loop needs D only (as the
    /// serial md_lj), tests comparing the pairs with a serial list ask for all.
    MpiLjSimulation(const tricell::mpi::Decomposition& decomposition, const md_lj::LjSystem& sys,
                    const md_lj::MdOptions& options,
                    const tricell::Quantities& quantities = tricell::Quantities{false, false, true})
        : decomposition_(decomposition), box_(sys.box), options_(options) {
        tricell::VerletOptions verlet;
        verlet.neighbors.cutoff = options.cutoff;
        verlet.neighbors.cells_per_cutoff = options.cells_per_cutoff;
        verlet.neighbors.quantities = quantities;
        verlet.neighbors.half = true;
        verlet.skin = options.skin;
        list_ = tricell::mpi::DistributedVerletList(verlet);
        // Deal the atoms round robin; the first update migrates them to their owners.
        atoms_.payload_width = 6;
        const std::size_t n = sys.positions.size();
        for (std::size_t g = 0; g < n; ++g) {
            if (int(g % std::size_t(decomposition.size())) != decomposition.rank()) {
                continue;
            }
            atoms_.ids.push_back(g);
            for (int k = 0; k < 3; ++k) {
                atoms_.positions.push_back(sys.positions[g][k]);
            }
            for (int k = 0; k < 3; ++k) {
                atoms_.payload.push_back(sys.velocities[g][k]);
            }
            atoms_.payload.insert(atoms_.payload.end(), 3, 0.0);
        }
        compute_forces();
    }

    /// One step: half kick, drift (and wrap), new forces, half kick.
    void step() {
        const double dt = options_.dt;
        for (std::size_t a = 0; a < atoms_.size(); ++a) {
            double* p = &atoms_.payload[6 * a];
            Eigen::Map<Eigen::Vector3d> x(&atoms_.positions[3 * a]);
            for (int k = 0; k < 3; ++k) {
                p[velocity + std::size_t(k)] += 0.5 * dt * p[force + std::size_t(k)];
                x[k] += dt * p[velocity + std::size_t(k)];
            }
            if (options_.wrap) {
                x = box_.wrap(tricell::Cartesian(x));
            }
        }
        compute_forces();
        for (std::size_t a = 0; a < atoms_.size(); ++a) {
            double* p = &atoms_.payload[6 * a];
            for (int k = 0; k < 3; ++k) {
                p[velocity + std::size_t(k)] += 0.5 * dt * p[force + std::size_t(k)];
            }
        }
        ++steps_;
    }

    double kinetic_energy() const {
        double twice = 0;
        for (std::size_t a = 0; a < atoms_.size(); ++a) {
            const double* v = &atoms_.payload[6 * a + velocity];
            twice += v[0] * v[0] + v[1] * v[1] + v[2] * v[2];
        }
        return 0.5 * sum(twice);
    }
    /// Collective, as kinetic_energy().
    double potential_energy() const { return sum(potential_); }
    double total_energy() const { return kinetic_energy() + potential_energy(); }
    std::size_t builds() const { return list_.rebuild_count(); }
    std::size_t steps() const { return steps_; }
    const tricell::mpi::LocalAtoms& atoms() const { return atoms_; }
    const tricell::mpi::DistributedVerletList& list() const { return list_; }
    const tricell::Box& box() const { return box_; }

  private:
    double sum(double mine) const {
        double all = 0;
        MPI_Allreduce(&mine, &all, 1, MPI_DOUBLE, MPI_SUM, decomposition_.comm());
        return all;
    }

    void compute_forces() {
        list_.update(decomposition_, box_, atoms_); // may migrate: atoms_ reordered
        const tricell::mpi::DistributedPairs& pairs = list_.pairs();
        const double cutoff_sq = options_.cutoff * options_.cutoff;
        const double inv_rc6 = 1 / (cutoff_sq * cutoff_sq * cutoff_sq);
        const double energy_shift = 4 * inv_rc6 * (inv_rc6 - 1);
        // Forces on every local atom (owned, then ghosts), summed into the owners afterwards.
        forces_.assign(3 * list_.halo().size(), 0.0);
        double potential = 0;
        for (std::size_t k = 0; k < pairs.size(); ++k) {
            const Eigen::Vector3d r(pairs.vectors[3 * k], pairs.vectors[3 * k + 1],
                                    pairs.vectors[3 * k + 2]);
            const double inv_r2 = 1 / r.squaredNorm();
            const double inv_r6 = inv_r2 * inv_r2 * inv_r2;
            potential += 4 * inv_r6 * (inv_r6 - 1) - energy_shift;
            const Eigen::Vector3d f = (24 * inv_r6 * (2 * inv_r6 - 1) * inv_r2) * r;
            // Whole 3-vectors, as md_lj's loop (a loop over the components is not unrolled at
            // -O2: a third more instructions per pair).
            Eigen::Map<Eigen::Vector3d>(&forces_[3 * pairs.owned[k]]) -= f;
            Eigen::Map<Eigen::Vector3d>(&forces_[3 * pairs.local_j[k]]) += f;
        }
        list_.reverse_sum(decomposition_, forces_, 3);
        for (std::size_t a = 0; a < atoms_.size(); ++a) {
            for (std::size_t c = 0; c < 3; ++c) {
                atoms_.payload[6 * a + force + c] = forces_[3 * a + c];
            }
        }
        potential_ = potential;
    }

    const tricell::mpi::Decomposition& decomposition_;
    tricell::Box box_;
    md_lj::MdOptions options_;
    tricell::mpi::DistributedVerletList list_;
    tricell::mpi::LocalAtoms atoms_;
    std::vector<double> forces_;
    double potential_ = 0; // this rank's share
    std::size_t steps_ = 0;
};

} // namespace mpi_md
