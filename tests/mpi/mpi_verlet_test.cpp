// The distributed Verlet list against the serial search at every step: an LJ MD run in which
// atoms cross domains (Newton half lists with reverse_sum, energies and forces against the
// serial md_lj run), and a random walk in
// a skewed, partially periodic, slowly sheared box with wrapping (half lists). Run under mpirun
// with 1, 2, 3, 4 and 8 ranks.
#include <random>

#include <gtest/gtest.h>

#include "mpi_lj.hpp"
#include "mpi_support.hpp"
#include "support/random_boxes.hpp"

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
    mpi_md::MpiLjSimulation sim(d, system, options);
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

TEST(MpiVerlet, RandomWalkInShearedPartlyPeriodicBox_HalfListsMatchSerial) {
    for (std::uint64_t seed = 0; seed < 3; ++seed) {
        SCOPED_TRACE(seed);
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
        verlet.neighbors.half = true;
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
            ASSERT_EQ(compare_with_serial(list.pairs(), atoms, box, serial_options(cutoff, true),
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

} // namespace

int main(int argc, char** argv) {
    MPI_Init(&argc, &argv);
    ::testing::InitGoogleTest(&argc, argv);
    if (world_rank() != 0) {
        delete ::testing::UnitTest::GetInstance()->listeners().Release(
            ::testing::UnitTest::GetInstance()->listeners().default_result_printer());
    }
    int failed = RUN_ALL_TESTS() != 0;
    int any = 0;
    MPI_Allreduce(&failed, &any, 1, MPI_INT, MPI_MAX, MPI_COMM_WORLD);
    if (world_rank() == 0) {
        std::printf("%s on %d ranks\n", any ? "MPI TESTS FAILED" : "MPI TESTS PASSED",
                    world_size());
    }
    MPI_Finalize();
    return any;
}
