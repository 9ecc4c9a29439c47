// tricell::mpi against the serial search: the union of the ranks' lists is the serial list, as
// sets of global (i, j, S), full and half, on random triclinic and strongly skewed boxes, every
// combination of periodic axes, atoms far outside the box, random domain grids and boundaries,
// cutoffs larger than a domain and than the box. Run under mpirun with 1, 2, 3, 4 and 8 ranks
// (tests/CMakeLists.txt). Every rank draws the same random system from the seed.
#include <random>
#include <set>

#include <gtest/gtest.h>

#include "mpi_support.hpp"
#include "support/expect_throw_msg.hpp"
#include "support/random_systems.hpp"
#include "tricell/error.hpp"

#ifndef TRICELL_MPI_CASES
#define TRICELL_MPI_CASES 60
#endif

namespace {

using tricell::Box;
using tricell::NeighborOptions;
using tricell::mpi::Decomposition;
using tricell::mpi::LocalAtoms;
using namespace tricell::testing;

// A random ordered factorisation of the number of ranks into a 3D grid.
std::array<int, 3> random_dims(std::mt19937_64& rng) {
    const int p = world_size();
    std::vector<std::array<int, 3>> all;
    for (int a = 1; a <= p; ++a) {
        for (int b = 1; a * b <= p; ++b) {
            if (p % (a * b) == 0) {
                all.push_back({{a, b, p / (a * b)}});
            }
        }
    }
    return all[std::uniform_int_distribution<std::size_t>(0, all.size() - 1)(rng)];
}

// Random strictly increasing boundaries 0 < ... < 1 on every axis.
void random_bounds(Decomposition& d, std::mt19937_64& rng) {
    std::uniform_real_distribution<double> weight(0.05, 1.0);
    for (int axis = 0; axis < 3; ++axis) {
        const int n = d.dims()[std::size_t(axis)];
        std::vector<double> w(static_cast<std::size_t>(n));
        double total = 0;
        for (double& v : w) {
            v = weight(rng);
            total += v;
        }
        std::vector<double> b(std::size_t(n) + 1, 0.0);
        for (int k = 0; k < n; ++k) {
            b[std::size_t(k) + 1] = b[std::size_t(k)] + w[std::size_t(k)] / total;
        }
        b.back() = 1;
        d.set_bounds(axis, b);
    }
}

NeighborOptions options_for(double cutoff, bool half) {
    NeighborOptions options;
    options.cutoff = cutoff;
    options.half = half;
    options.quantities = tricell::Quantities{true, true, true};
    return options;
}

TEST(MpiNeighbors, UnionEqualsSerial_RandomSystems) {
    int cases = 0;
    for (std::uint64_t seed = 0; seed < TRICELL_MPI_CASES; ++seed) {
        SCOPED_TRACE(seed);
        const RandomSystem sys = random_system(seed);
        SCOPED_TRACE(sys.kind);
        const Box box = sys.box();
        std::mt19937_64 rng(seed + 1000);
        Decomposition d(MPI_COMM_WORLD,
                        seed % 3 == 0 ? std::array<int, 3>{{0, 0, 0}} : random_dims(rng));
        if (seed % 2 == 1) {
            random_bounds(d, rng);
        }
        LocalAtoms atoms = deal(sys.positions);
        tricell::mpi::migrate(d, box, atoms);
        ASSERT_TRUE(tricell::mpi::all_owned(d, box, atoms));
        for (bool half : {false, true}) {
            SCOPED_TRACE(half ? "half" : "full");
            const NeighborOptions options = options_for(sys.cutoff, half);
            const auto pairs = tricell::mpi::compute_neighbors(d, box, atoms, options);
            EXPECT_EQ(compare_with_serial(pairs, atoms, box, options, d.comm()), "");
        }
        ++cases;
    }
    EXPECT_EQ(cases, TRICELL_MPI_CASES);
}

// Per-atom radii and species tables: the distributed options hold one value per owned atom,
// the serial ones one per global atom.
TEST(MpiNeighbors, UnionEqualsSerial_VariableCutoffs) {
    for (std::uint64_t seed = 0; seed < 16; ++seed) {
        SCOPED_TRACE(seed);
        const RandomSystem sys = random_system(seed);
        const Box box = sys.box();
        std::mt19937_64 rng(seed + 77);
        std::uniform_real_distribution<double> unit(0, 1);
        const std::size_t n = sys.positions.size();
        NeighborOptions serial = options_for(sys.cutoff, seed % 4 < 2);
        serial.cutoff = 0;
        std::vector<double> radii(n);
        std::vector<std::int32_t> species(n);
        for (std::size_t g = 0; g < n; ++g) {
            radii[g] = 0.6 * sys.cutoff * unit(rng);
            species[g] = std::int32_t(std::uniform_int_distribution<int>(0, 2)(rng));
        }
        const bool by_species = seed % 2 == 1;
        if (by_species) {
            serial.species = species;
            serial.species_cutoffs = {{0, 0, sys.cutoff},
                                      {0, 1, 0.7 * sys.cutoff},
                                      {1, 2, 1.2 * sys.cutoff},
                                      {2, 2, 0.4 * sys.cutoff}}; // 1-1 and 0-2 never count
        } else {
            serial.radii = radii;
        }
        Decomposition d(MPI_COMM_WORLD, random_dims(rng));
        LocalAtoms atoms = deal(sys.positions);
        tricell::mpi::migrate(d, box, atoms);
        NeighborOptions options = serial;
        options.radii.clear();
        options.species.clear();
        for (std::uint64_t g : atoms.ids) {
            if (by_species) {
                options.species.push_back(species[g]);
            } else {
                options.radii.push_back(radii[g]);
            }
        }
        const auto pairs = tricell::mpi::compute_neighbors(d, box, atoms, options);
        EXPECT_EQ(compare_with_serial(pairs, atoms, box, serial, d.comm()), "");
    }
}

// A cutoff of several domain widths along an axis cut into as many domains as there are ranks,
// open along another axis: halos several ranks deep, and a domain's own images.
TEST(MpiNeighbors, UnionEqualsSerial_CutoffLargerThanDomains) {
    for (std::uint64_t seed = 0; seed < 6; ++seed) {
        SCOPED_TRACE(seed);
        std::mt19937_64 rng(seed);
        const Eigen::Matrix3d h = random_box_matrix(rng, 4, 8, 1.0);
        const Box box =
            Box::from_columns(h, tricell::Periodicity{{true, seed % 2 == 0, seed % 3 != 0}});
        std::uniform_real_distribution<double> unit(0, 1);
        std::vector<Eigen::Vector3d> x(120);
        for (auto& p : x) {
            p = h * Eigen::Vector3d(unit(rng), unit(rng), unit(rng));
        }
        Decomposition d(MPI_COMM_WORLD, {{world_size(), 1, 1}});
        const double width = box.perpendicular_widths()[0] / world_size();
        const double cutoff = std::min(2.5 * width, 0.9 * box.perpendicular_widths().minCoeff());
        LocalAtoms atoms = deal(x);
        tricell::mpi::migrate(d, box, atoms);
        for (bool half : {false, true}) {
            const NeighborOptions options = options_for(cutoff, half);
            tricell::mpi::DistributedSearch search;
            search.build(d, box, atoms, options);
            tricell::mpi::DistributedPairs pairs;
            search.compute(pairs);
            EXPECT_EQ(compare_with_serial(pairs, atoms, box, options, d.comm()), "");
            if (world_size() >= 3) {
                // The halo reaches past the nearest domains.
                EXPECT_GE(search.halo().neighbor_ranks().size(), std::size_t(2));
            }
        }
    }
}

TEST(MpiNeighbors, SortedOutput_IsOrderedByIJS) {
    const RandomSystem sys = random_system(13);
    const Box box = sys.box();
    Decomposition d(MPI_COMM_WORLD);
    LocalAtoms atoms = deal(sys.positions);
    tricell::mpi::migrate(d, box, atoms);
    NeighborOptions options = options_for(sys.cutoff, false);
    options.sorted = true;
    const auto pairs = tricell::mpi::compute_neighbors(d, box, atoms, options);
    for (std::size_t k = 1; k < pairs.size(); ++k) {
        const auto a = std::make_tuple(pairs.i[k - 1], pairs.j[k - 1], pairs.shifts[3 * k - 3],
                                       pairs.shifts[3 * k - 2], pairs.shifts[3 * k - 1]);
        const auto b = std::make_tuple(pairs.i[k], pairs.j[k], pairs.shifts[3 * k],
                                       pairs.shifts[3 * k + 1], pairs.shifts[3 * k + 2]);
        ASSERT_LT(a, b) << k;
    }
    EXPECT_EQ(compare_with_serial(pairs, atoms, box, options, d.comm()), "");
}

TEST(MpiMigrate, EveryAtomReachesItsOwner_WithItsPayload) {
    for (std::uint64_t seed = 0; seed < 10; ++seed) {
        SCOPED_TRACE(seed);
        const RandomSystem sys = random_system(seed);
        const Box box = sys.box();
        std::mt19937_64 rng(seed);
        Decomposition d(MPI_COMM_WORLD, random_dims(rng));
        random_bounds(d, rng);
        LocalAtoms atoms = deal(sys.positions, 2);
        tricell::mpi::migrate(d, box, atoms);
        EXPECT_TRUE(tricell::mpi::all_owned(d, box, atoms));
        for (std::size_t a = 0; a < atoms.size(); ++a) {
            const std::uint64_t g = atoms.ids[a];
            ASSERT_LT(g, sys.positions.size());
            EXPECT_EQ(atoms.positions[3 * a], sys.positions[g][0]); // positions unchanged
            EXPECT_EQ(atoms.payload[2 * a + 1], double(g) * 10 + 1);
        }
        unsigned long local = atoms.size(), total = 0;
        MPI_Allreduce(&local, &total, 1, MPI_UNSIGNED_LONG, MPI_SUM, MPI_COMM_WORLD);
        EXPECT_EQ(total, sys.positions.size());
        // Migrating again moves nothing.
        const std::vector<std::uint64_t> before = atoms.ids;
        tricell::mpi::migrate(d, box, atoms);
        EXPECT_EQ(atoms.ids, before);
    }
}

TEST(MpiErrors, BadInputFailsOnEveryRank_WithTheMessage) {
    EXPECT_THROW_MSG(Decomposition(MPI_COMM_WORLD, {{world_size() + 1, 1, 1}}),
                     tricell::InvalidArgument, "do not fit");
    Decomposition d(MPI_COMM_WORLD);
    EXPECT_THROW_MSG(d.set_bounds(0, std::vector<double>(std::size_t(d.dims()[0]) + 1, 0.5)),
                     tricell::InvalidArgument, "must start at 0 and end at 1");
    const Box box = Box::from_parameters(5, 5, 5, 90, 90, 90);
    // Only the last rank holds a bad position; every rank throws its message.
    LocalAtoms atoms;
    if (world_rank() == world_size() - 1) {
        atoms.ids = {3};
        atoms.positions = {1, std::nan(""), 1};
    }
    EXPECT_THROW_MSG(tricell::mpi::migrate(d, box, atoms), tricell::InvalidArgument,
                     "position of atom id 3 is not finite");
    // Atoms that are not this rank's own: a search names migrate().
    LocalAtoms wrong;
    if (world_size() > 1 && world_rank() == 0) {
        const tricell::Fractional far(d.upper(world_size() - 1) - Eigen::Vector3d::Constant(1e-3));
        const tricell::Cartesian x = box.to_cartesian(far);
        wrong.ids = {0};
        wrong.positions = {x[0], x[1], x[2]};
    }
    if (world_size() > 1) {
        EXPECT_THROW_MSG(tricell::mpi::compute_neighbors(d, box, wrong, options_for(1.0, false)),
                         tricell::InvalidArgument, "call tricell::mpi::migrate() first");
    }
    EXPECT_THROW_MSG(tricell::mpi::compute_neighbors(d, box, LocalAtoms{}, options_for(-1, false)),
                     tricell::InvalidArgument, "cutoff must be > 0 (got -1)");
}

} // namespace

int main(int argc, char** argv) {
    MPI_Init(&argc, &argv);
    ::testing::InitGoogleTest(&argc, argv);
    if (world_rank() != 0) {
        // One report: rank 0 prints; every rank's verdict is collected below.
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
