// tricell::mpi against the serial search: the union of the ranks' lists is the serial list, as
// sets of global (i, j, S), full and half, on random triclinic and strongly skewed boxes, every
// combination of periodic axes, atoms far outside the box, random domain grids and boundaries,
// cutoffs larger than a domain and than the box. Run under mpirun with 1, 2, 3, 4 and 8 ranks
// (tests/CMakeLists.txt). Every rank draws the same random system from the seed.
#include <algorithm>
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

// A pair force and a per-atom energy share that a Newton half list gives to both ends: F on i,
// -F on j, e / 2 on each (a soft potential, finite for coincident atoms).
struct PairForce {
    Eigen::Vector3d f;
    double e;
};
PairForce soft_force(const Eigen::Vector3d& d, double distance, double cutoff) {
    const double x = cutoff - distance;
    return PairForce{d * (x * x), x * x * x};
}

// Newton's third law across ranks: each rank runs the force loop over its half list (forces
// and energy shares on owned and ghost rows, four doubles per atom), Halo::reverse_sum() adds
// the ghost rows into their owners, and the owners' rows equal the serial half list's sums to
// 1e-12 relative. Random systems and domain grids, cutoffs beyond a domain and the box.
TEST(MpiNeighbors, NewtonHalfList_ReverseSumGivesTheSerialForces) {
    for (std::uint64_t seed = 0; seed < TRICELL_MPI_CASES / 3 + 6; ++seed) {
        SCOPED_TRACE(seed);
        RandomSystem sys = random_system(seed);
        std::mt19937_64 rng(seed + 2000);
        Decomposition d(MPI_COMM_WORLD, random_dims(rng));
        if (seed >= TRICELL_MPI_CASES / 3) { // the cutoff reaches past the nearest domains
            d = Decomposition(MPI_COMM_WORLD, {{world_size(), 1, 1}});
            const double width = sys.box().perpendicular_widths()[0] / world_size();
            sys.cutoff = std::min(2.5 * width, sys.cutoff * 2);
        } else if (seed % 2 == 1) {
            random_bounds(d, rng);
        }
        const Box box = sys.box();
        LocalAtoms atoms = deal(sys.positions);
        tricell::mpi::migrate(d, box, atoms);
        const NeighborOptions options = options_for(sys.cutoff, true);
        tricell::mpi::DistributedSearch search;
        search.build(d, box, atoms, options);
        tricell::mpi::DistributedPairs pairs;
        search.compute(pairs);
        EXPECT_EQ(compare_with_serial(pairs, atoms, box, options, d.comm()), "");
        const tricell::mpi::Halo& halo = search.halo();
        std::vector<double> rows(4 * halo.size(), 0.0);
        for (std::size_t k = 0; k < pairs.size(); ++k) {
            ASSERT_EQ(halo.ids()[pairs.local_j[k]], pairs.j[k]);
            const Eigen::Vector3d v(&pairs.vectors[3 * k]);
            const PairForce p = soft_force(v, pairs.distances[k], sys.cutoff);
            for (std::size_t c = 0; c < 3; ++c) {
                rows[4 * pairs.owned[k] + c] += p.f[c];
                rows[4 * pairs.local_j[k] + c] -= p.f[c];
            }
            rows[4 * pairs.owned[k] + 3] += p.e / 2;
            rows[4 * pairs.local_j[k] + 3] += p.e / 2;
        }
        halo.reverse_sum(d, rows, 4);
        std::vector<double> mine;
        for (std::size_t a = 0; a < atoms.size(); ++a) {
            mine.insert(mine.end(), {double(atoms.ids[a]), rows[4 * a], rows[4 * a + 1],
                                     rows[4 * a + 2], rows[4 * a + 3]});
        }
        const std::vector<double> all = gather_to_root(mine, d.comm());
        std::string verdict;
        if (world_rank() == 0) {
            const std::size_t n = sys.positions.size();
            std::vector<double> expected(4 * n, 0.0), scale(n, 1e-300);
            // Positions many boxes away carry rounding of eps |x| into every D, serial and
            // distributed alike: the tolerance grows with |x| / (box size), 1 near the box.
            double far = 0;
            for (const Eigen::Vector3d& x : sys.positions) {
                far = std::max(far, x.norm() / sys.h.norm());
            }
            const tricell::NeighborList serial =
                tricell::compute_neighbors(box, sys.positions, options);
            for (std::size_t k = 0; k < serial.size(); ++k) {
                const PairForce p = soft_force(serial.vector(k), serial.distances()[k], sys.cutoff);
                const std::size_t i = serial.i()[k], j = serial.j()[k];
                for (std::size_t c = 0; c < 3; ++c) {
                    expected[4 * i + c] += p.f[c];
                    expected[4 * j + c] -= p.f[c];
                }
                expected[4 * i + 3] += p.e / 2;
                expected[4 * j + 3] += p.e / 2;
                scale[i] += p.f.norm() + p.e;
                scale[j] += p.f.norm() + p.e;
            }
            if (all.size() != 5 * n) {
                verdict = std::to_string(all.size() / 5) + " rows for " + std::to_string(n);
            }
            for (std::size_t r = 0; verdict.empty() && 5 * r < all.size(); ++r) {
                const auto id = std::size_t(all[5 * r]);
                for (std::size_t c = 0; c < 4; ++c) {
                    if (!(std::abs(all[5 * r + 1 + c] - expected[4 * id + c]) <=
                          1e-12 * (1 + far) * scale[id])) {
                        verdict = "atom " + std::to_string(id) + " value " + std::to_string(c) +
                                  ": " + std::to_string(all[5 * r + 1 + c]) + ", serial " +
                                  std::to_string(expected[4 * id + c]);
                    }
                }
            }
        }
        EXPECT_EQ(share_verdict(verdict, d.comm()), "");
    }
}

// Halo::forward copies each owner's row into its ghosts (any width); a wrong size fails on
// every rank with the message.
TEST(MpiNeighbors, HaloForward_CopiesOwnersRowsIntoGhosts) {
    const RandomSystem sys = random_system(3);
    Decomposition d(MPI_COMM_WORLD);
    const Box box = sys.box();
    LocalAtoms atoms = deal(sys.positions);
    tricell::mpi::migrate(d, box, atoms);
    tricell::mpi::DistributedSearch search;
    search.build(d, box, atoms, options_for(sys.cutoff, true));
    const tricell::mpi::Halo& halo = search.halo();
    for (std::size_t width : {std::size_t(1), std::size_t(3)}) {
        std::vector<double> rows(width * halo.size(), std::nan(""));
        for (std::size_t a = 0; a < halo.owned_count(); ++a) {
            for (std::size_t c = 0; c < width; ++c) {
                rows[width * a + c] = double(halo.ids()[a]) * 1.5 + double(c);
            }
        }
        halo.forward(d, rows, width);
        int wrong = 0;
        for (std::size_t a = 0; a < halo.size(); ++a) {
            for (std::size_t c = 0; c < width; ++c) {
                wrong += rows[width * a + c] != double(halo.ids()[a]) * 1.5 + double(c);
            }
        }
        MPI_Allreduce(MPI_IN_PLACE, &wrong, 1, MPI_INT, MPI_SUM, d.comm());
        EXPECT_EQ(wrong, 0);
        EXPECT_EQ(halo.comm_messages_sent(), int(halo.neighbor_ranks().size()));
    }
    std::vector<double> short_rows(world_rank() == 0 ? 1 : 4 * halo.size());
    std::vector<double> right(4 * halo.size());
    if (world_rank() == 0) {
        EXPECT_THROW_MSG(halo.reverse_sum(d, short_rows, 4), tricell::InvalidArgument,
                         "Halo::reverse_sum needs 4 values per local atom");
    } else {
        EXPECT_THROW(halo.reverse_sum(d, right, 4), tricell::InvalidArgument);
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

// Migration to halo neighbours only: after moves shorter than the halo reach every new owner is
// a neighbour, and the result (ids, positions, payload, order) is migrate()'s; after long jumps
// (some owner beyond the neighbours, with 8 ranks in a 8 x 1 x 1 grid) it falls back to it.
TEST(MpiMigrate, AmongHaloNeighbors_SameAsMigrate) {
    for (std::uint64_t seed = 0; seed < 8; ++seed) {
        SCOPED_TRACE(seed);
        std::mt19937_64 rng(seed);
        const Eigen::Matrix3d h = random_box_matrix(rng, 8, 12, 0.5);
        const Box box = Box::from_columns(h, tricell::Periodicity{{true, true, seed % 2 == 0}});
        std::uniform_real_distribution<double> unit(0, 1);
        std::vector<Eigen::Vector3d> x(300);
        for (auto& p : x) {
            p = h * Eigen::Vector3d(unit(rng), unit(rng), unit(rng));
        }
        Decomposition d(MPI_COMM_WORLD,
                        seed < 4 ? random_dims(rng) : std::array<int, 3>{{world_size(), 1, 1}});
        LocalAtoms atoms = deal(x, 2);
        tricell::mpi::migrate(d, box, atoms);
        const double reach = 0.08 * box.perpendicular_widths().minCoeff();
        tricell::mpi::Halo halo;
        halo.build(d, box, atoms.ids, atoms.points(), reach);
        const bool jump = seed % 4 == 3;
        std::normal_distribution<double> step(0, jump ? 5.0 : reach / 4);
        for (double& v : atoms.positions) {
            v += jump ? step(rng) * 3 : std::clamp(step(rng), -reach / 2, reach / 2);
        }
        LocalAtoms expected = atoms;
        tricell::mpi::migrate(d, box, expected);
        const bool near = tricell::mpi::migrate(d, box, atoms, halo.neighbor_ranks());
        EXPECT_TRUE(near || jump);
        if (jump && world_size() == 8 && d.dims()[0] == 8) {
            EXPECT_FALSE(near);
        }
        EXPECT_EQ(atoms.ids, expected.ids);
        EXPECT_EQ(atoms.positions, expected.positions);
        EXPECT_EQ(atoms.payload, expected.payload);
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
