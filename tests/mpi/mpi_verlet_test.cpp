// The distributed Verlet list against the serial search at every step: an LJ MD run in which
// atoms cross domains (Newton half lists with reverse_sum, energies and forces against the
// serial md_lj run), and a random walk in
// a skewed, partially periodic, slowly sheared box with wrapping (full and half lists); the
// messages, bytes and ghosts the list counts against the model of tricell/mpi/traffic.hpp on a
// uniform system. Run under mpirun with 1, 2, 3, 4 and 8 ranks.
#include <random>

#include <gtest/gtest.h>

#include "mpi_lj.hpp"
#include "mpi_support.hpp"
#include "support/random_boxes.hpp"
#include "tricell/error.hpp"

namespace {

using tricell::Box;
using tricell::NeighborOptions;
using namespace tricell::testing;

NeighborOptions serial_options(double cutoff, bool half) {
    NeighborOptions options;
    options.cutoff = cutoff;
    options.half = half;
    return options;
}

// Same value on every rank?
template <class T> bool agreed_value(T value) {
    double v = double(value), lo = 0, hi = 0;
    MPI_Allreduce(&v, &lo, 1, MPI_DOUBLE, MPI_MIN, MPI_COMM_WORLD);
    MPI_Allreduce(&v, &hi, 1, MPI_DOUBLE, MPI_MAX, MPI_COMM_WORLD);
    return lo == hi;
}

TEST(MpiVerlet, LjDynamics_NewtonHalfListsMatchSerialEveryStep_AtomsCrossDomains) {
    tricell::mpi::Decomposition d(MPI_COMM_WORLD);
    const md_lj::LjSystem system = md_lj::make_fcc(4, 0.8, 1.0, 3);
    md_lj::MdOptions options;
    mpi_md::MpiLjSimulation sim(d, system, options, tricell::Quantities{true, true, true});
    md_lj::LjSimulation serial(system, options);
    const std::vector<std::uint64_t> first_owned = sim.atoms().ids;
    const int steps = 60;
    for (int step = 0; step <= steps; ++step) {
        SCOPED_TRACE(step);
        if (step > 0) {
            sim.step();
            serial.step();
        }
        ASSERT_EQ(compare_with_serial(sim.list().pairs(), sim.atoms(), sim.box(),
                                      serial_options(options.cutoff, true), d.comm()),
                  "");
        const double n = double(system.positions.size());
        EXPECT_NEAR(sim.total_energy() / n, serial.total_energy() / n, 1e-10);
        EXPECT_NEAR(sim.potential_energy() / n, serial.potential_energy() / n, 1e-10);
        // Forces (the payload after reverse_sum) against the serial forces of the same atoms.
        double worst = 0;
        const tricell::mpi::LocalAtoms& atoms = sim.atoms();
        for (std::size_t a = 0; a < atoms.size(); ++a) {
            const Eigen::Vector3d f(&atoms.payload[6 * a + mpi_md::MpiLjSimulation::force]);
            const Eigen::Vector3d& expected = serial.system().forces[atoms.ids[a]];
            worst = std::max(worst, (f - expected).norm() / (1 + expected.norm()));
        }
        MPI_Allreduce(MPI_IN_PLACE, &worst, 1, MPI_DOUBLE, MPI_MAX, MPI_COMM_WORLD);
        EXPECT_LT(worst, 1e-9);
    }
    EXPECT_TRUE(agreed_value(sim.builds()));
    EXPECT_GT(sim.builds(), std::size_t(2));
    // Some atom now lives on another rank than after the first build.
    std::vector<std::uint64_t> now = sim.atoms().ids, before = first_owned;
    std::sort(now.begin(), now.end());
    std::sort(before.begin(), before.end());
    int moved = now != before, any = 0;
    MPI_Allreduce(&moved, &any, 1, MPI_INT, MPI_MAX, MPI_COMM_WORLD);
    EXPECT_EQ(any, world_size() > 1 ? 1 : 0);
}

TEST(MpiVerlet, RandomWalkInShearedPartlyPeriodicBox_FullAndHalfListsMatchSerial) {
    for (std::uint64_t seed = 0; seed < 6; ++seed) {
        SCOPED_TRACE(seed);
        const bool half = seed < 3;
        std::mt19937_64 rng(seed);
        std::uniform_real_distribution<double> unit(0, 1);
        std::normal_distribution<double> normal;
        const Eigen::Matrix3d h0 = random_box_matrix(rng, 5, 9, 1.5);
        const tricell::Periodicity pbc{{true, seed % 2 == 0, seed != 1}};
        std::vector<Eigen::Vector3d> s(150);
        for (auto& v : s) {
            v = Eigen::Vector3d(unit(rng), unit(rng), unit(rng));
        }
        const double cutoff = 0.4 * Box::from_columns(h0).perpendicular_widths().minCoeff();
        tricell::VerletOptions verlet;
        verlet.neighbors.cutoff = cutoff;
        verlet.neighbors.half = half;
        verlet.neighbors.quantities = tricell::Quantities{true, true, true};
        verlet.skin = 0.15 * cutoff;
        tricell::mpi::DistributedVerletList list(verlet);
        tricell::mpi::Decomposition d(MPI_COMM_WORLD);
        // Every rank walks the same global system and keeps only its own atoms' new positions.
        std::vector<Eigen::Vector3d> x(s.size());
        Eigen::Matrix3d h = h0;
        for (std::size_t g = 0; g < s.size(); ++g) {
            x[g] = h * s[g];
        }
        tricell::mpi::LocalAtoms atoms = deal(x);
        Eigen::Matrix3d shear = Eigen::Matrix3d::Zero();
        shear(0, 1) = 0.002 * h0(0, 0);
        for (int step = 0; step < 25; ++step) {
            SCOPED_TRACE(step);
            const Box box = Box::from_columns(h, pbc);
            list.update(d, box, atoms);
            ASSERT_EQ(compare_with_serial(list.pairs(), atoms, box, serial_options(cutoff, half),
                                          d.comm()),
                      "");
            // Move: the box shears (positions follow affinely), every atom steps at random, a
            // few jump by a lattice vector or are wrapped.
            const Eigen::Matrix3d next = h + shear;
            for (std::size_t a = 0; a < atoms.size(); ++a) {
                const std::uint64_t g = atoms.ids[a];
                std::mt19937_64 atom_rng(seed * 1000003 + std::uint64_t(step) * 7919 + g);
                Eigen::Map<Eigen::Vector3d> p(&atoms.positions[3 * a]);
                Eigen::Vector3d q = next * (h.inverse() * Eigen::Vector3d(p));
                q += 0.02 * cutoff *
                     Eigen::Vector3d(normal(atom_rng), normal(atom_rng), normal(atom_rng));
                const double u = unit(atom_rng);
                if (u < 0.05) {
                    q += next.col(0) * (u < 0.025 ? 1 : -3);
                } else if (u < 0.1) {
                    q = Box::from_columns(next, pbc).wrap(tricell::Cartesian(q));
                }
                p = q;
            }
            h = next;
        }
        EXPECT_TRUE(agreed_value(list.rebuild_count()));
        EXPECT_GT(list.rebuild_count(), std::size_t(1));
        EXPECT_LT(list.rebuild_count(), std::size_t(25));
    }
}

TEST(MpiVerlet, BadPositionOnOneRank_ThrowsEverywhere_ThenRebuilds) {
    std::mt19937_64 rng(5);
    std::uniform_real_distribution<double> unit(0, 1);
    const Eigen::Matrix3d h = random_box_matrix(rng, 6, 9, 1.5);
    const Box box = Box::from_columns(h);
    std::vector<Eigen::Vector3d> x(200);
    for (auto& v : x) {
        v = h * Eigen::Vector3d(unit(rng), unit(rng), unit(rng));
    }
    const double cutoff = 0.3 * box.perpendicular_widths().minCoeff();
    tricell::VerletOptions verlet;
    verlet.neighbors.cutoff = cutoff;
    verlet.neighbors.half = true;
    verlet.neighbors.quantities = tricell::Quantities{true, true, true};
    verlet.skin = 0.2;
    tricell::mpi::DistributedVerletList list(verlet);
    tricell::mpi::Decomposition d(MPI_COMM_WORLD);
    tricell::mpi::LocalAtoms atoms = deal(x);
    EXPECT_TRUE(list.update(d, box, atoms));
    const bool bad_here = world_rank() == world_size() - 1 && atoms.size() > 0;
    const double kept = bad_here ? atoms.positions[1] : 0.0;
    if (bad_here) {
        atoms.positions[1] = std::nan("");
    }
    EXPECT_THROW(list.update(d, box, atoms), tricell::InvalidArgument);
    EXPECT_EQ(list.pairs().size(), 0u);
    if (bad_here) {
        atoms.positions[1] = kept;
    }
    EXPECT_TRUE(list.update(d, box, atoms));
    EXPECT_EQ(compare_with_serial(list.pairs(), atoms, box, serial_options(cutoff, true), d.comm()),
              "");
}

// Sum over ranks.
double total(double mine) {
    double all = 0;
    MPI_Allreduce(&mine, &all, 1, MPI_DOUBLE, MPI_SUM, MPI_COMM_WORLD);
    return all;
}

TEST(MpiVerlet, UniformSystem_CountedTrafficMatchesTheModel) {
    // 6000 uniform random atoms in a skewed periodic box, small random steps (no rebuild after
    // the first build), a reverse_sum of 3 doubles and a forward of 2 per step.
    std::mt19937_64 rng(11);
    std::uniform_real_distribution<double> unit(0, 1);
    Eigen::Matrix3d h;
    h << 18, 2, -1.5, 0, 17, 1.8, 0, 0, 19;
    const Box box = Box::from_columns(h);
    std::vector<Eigen::Vector3d> x(6000);
    for (auto& v : x) {
        v = h * Eigen::Vector3d(unit(rng), unit(rng), unit(rng));
    }
    tricell::VerletOptions verlet;
    verlet.neighbors.cutoff = 1.7;
    verlet.neighbors.half = true;
    verlet.skin = 0.3;
    tricell::mpi::DistributedVerletList list(verlet);
    tricell::mpi::Decomposition d(MPI_COMM_WORLD);
    tricell::mpi::LocalAtoms atoms = deal(x);
    const int steps = 3;
    for (int step = 0; step <= steps; ++step) {
        for (double& c : atoms.positions) {
            c += step == 0 ? 0.0 : 0.01 * (unit(rng) - 0.5);
        }
        list.update(d, box, atoms);
        const tricell::mpi::Halo& halo = list.halo();
        std::vector<double> forces(3 * halo.size(), 1.0);
        list.reverse_sum(d, forces, 3);
        std::vector<double> rows(2 * halo.size(), -1.0);
        for (std::size_t a = 0; a < halo.owned_count(); ++a) {
            rows[2 * a] = double(halo.ids()[a]);
            rows[2 * a + 1] = 0.5 * double(halo.ids()[a]);
        }
        list.forward_values(d, rows, 2);
        int wrong = 0;
        for (std::size_t a = 0; a < halo.size(); ++a) {
            wrong += rows[2 * a] != double(halo.ids()[a]) ||
                     rows[2 * a + 1] != 0.5 * double(halo.ids()[a]);
        }
        EXPECT_EQ(total(wrong), 0);
    }
    EXPECT_EQ(list.rebuild_count(), std::size_t(1));
    const tricell::mpi::ListTraffic& t = list.traffic();
    // A half list's halo holds the upper ghosts only.
    EXPECT_EQ(list.halo().ghost_set(), tricell::mpi::GhostSet::upper);
    const tricell::mpi::HaloModel model =
        tricell::mpi::halo_model(d, box, list.list_radius(), tricell::mpi::GhostSet::upper);
    // Messages: one per neighbour rank per exchange, as the model counts them (exact).
    EXPECT_EQ(int(list.halo().neighbor_ranks().size()), model.messages);
    EXPECT_EQ(t.halo_build.exchanges, 1u);
    EXPECT_EQ(t.halo_update.exchanges, std::uint64_t(steps));
    EXPECT_EQ(t.reverse_sum.exchanges, std::uint64_t(steps + 1));
    EXPECT_EQ(t.forward.exchanges, std::uint64_t(steps + 1));
    EXPECT_EQ(t.halo_build.messages, std::uint64_t(model.messages));
    EXPECT_EQ(t.halo_update.messages, std::uint64_t(steps * model.messages));
    EXPECT_EQ(t.reverse_sum.messages, std::uint64_t((steps + 1) * model.messages));
    EXPECT_EQ(t.forward.messages, std::uint64_t((steps + 1) * model.messages));
    EXPECT_EQ(t.migration.exchanges, 0u); // the first migration is the MPI_Alltoall
    // Ghosts and bytes, summed over ranks, within 10 % of the model (uniform density).
    const double n = double(x.size());
    const double ghosts = total(double(list.halo().ghost_count()));
    EXPECT_NEAR(ghosts / n, model.ghosts_per_atom, 0.1 * model.ghosts_per_atom);
    const double sent = model.sent_ghosts_per_atom * n;
    const auto expect_bytes = [&](const tricell::mpi::Traffic& counted, double per_ghost) {
        const double bytes = total(double(counted.bytes)) / double(counted.exchanges);
        if (sent == 0) {
            EXPECT_EQ(bytes, 0.0); // one rank: every ghost is an image of its own atoms
        } else {
            EXPECT_NEAR(bytes, per_ghost * sent, 0.1 * per_ghost * sent);
        }
    };
    expect_bytes(t.halo_build, double(tricell::mpi::Halo::build_record_bytes));
    expect_bytes(t.halo_update, double(tricell::mpi::Halo::update_record_bytes));
    expect_bytes(t.reverse_sum, 24.0);
    expect_bytes(t.forward, 16.0);
    // Every ghost sent is received: the counted bytes are exactly the ghosts from other ranks.
    EXPECT_EQ(total(double(t.halo_update.bytes)) / double(steps),
              total(double(t.reverse_sum.bytes)) / double(steps + 1) / 24.0 *
                  double(tricell::mpi::Halo::update_record_bytes));
}

} // namespace
