#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "scan/distance_kernel.hpp"
#include "support/brute_force.hpp"
#include "support/expect_throw_msg.hpp"
#include "support/identical_lists.hpp"
#include "support/random_boxes.hpp"
#include "tricell/error.hpp"
#include "tricell/neighbor_list.hpp"

using tricell::Box;
using tricell::NeighborList;
using tricell::NeighborOptions;
using tricell::SearchBackend;
using tricell::Shift;

namespace {
NeighborOptions with_cutoff(double cutoff) {
    NeighborOptions o;
    o.cutoff = cutoff;
    o.quantities.vectors = true;
    return o;
}
const Box cube10 = Box::from_parameters(10, 10, 10, 90, 90, 90);
} // namespace

TEST(NeighborList, TwoAtomsAcrossTheBoundary) {
    const std::vector<Eigen::Vector3d> x{{0.5, 5, 5}, {9.5, 5, 5}};
    NeighborOptions o = with_cutoff(1.5);
    o.sorted = true;
    const NeighborList list = tricell::compute_neighbors(cube10, x, o);
    ASSERT_EQ(list.size(), 2u);
    EXPECT_EQ(list.i()[0], 0u);
    EXPECT_EQ(list.j()[0], 1u);
    EXPECT_EQ(list.shift(0), Shift(-1, 0, 0)); // x1 - x0 + H S = (-1, 0, 0)
    EXPECT_DOUBLE_EQ(list.distances()[0], 1.0);
    EXPECT_TRUE(list.vector(0).isApprox(Eigen::Vector3d(-1, 0, 0)));
    EXPECT_EQ(list.i()[1], 1u);
    EXPECT_EQ(list.shift(1), Shift(1, 0, 0));
    EXPECT_EQ(list.offsets(), (std::vector<std::size_t>{0, 1, 2}));
}

TEST(NeighborList, ShiftIsRelativeToTheCallersPositionsFarOutside) {
    // Atom 1 is 1000 boxes away along a: its pair with atom 0 needs S = (-1000 - 1, 0, 0).
    const std::vector<Eigen::Vector3d> x{{0.5, 5, 5}, {9.5 + 10000, 5, 5}};
    NeighborOptions o = with_cutoff(1.5);
    o.half = true;
    const NeighborList list = tricell::compute_neighbors(cube10, x, o);
    ASSERT_EQ(list.size(), 1u);
    EXPECT_EQ(list.shift(0), Shift(-1001, 0, 0));
    const Eigen::Vector3d d = x[1] - x[0] + cube10.matrix() * Eigen::Vector3d(-1001, 0, 0);
    EXPECT_NEAR(d.norm(), 1.0, 1e-9);
    EXPECT_NEAR(list.distances()[0], 1.0, 1e-9);
}

TEST(NeighborList, OneAtomSeesItsOwnImages) {
    const Box box = Box::from_parameters(2, 2, 2, 90, 90, 90);
    const std::vector<Eigen::Vector3d> x{{0.3, 0.3, 0.3}};
    NeighborList list = tricell::compute_neighbors(box, x, with_cutoff(2.5));
    EXPECT_EQ(list.size(), 6u); // +-a, +-b, +-c
    NeighborOptions o = with_cutoff(2.5);
    o.half = true;
    o.sorted = true;
    list = tricell::compute_neighbors(box, x, o);
    ASSERT_EQ(list.size(), 3u); // canonical: S lexicographically positive
    EXPECT_EQ(list.shift(0), Shift(0, 0, 1));
    EXPECT_EQ(list.shift(1), Shift(0, 1, 0));
    EXPECT_EQ(list.shift(2), Shift(1, 0, 0));
}

TEST(NeighborList, HalfListOrientationIsCanonical) {
    const std::vector<Eigen::Vector3d> x{{9.5, 5, 5}, {0.5, 5, 5}, {5, 5, 5}};
    NeighborOptions o = with_cutoff(4.6);
    o.half = true;
    const NeighborList list = tricell::compute_neighbors(cube10, x, o);
    ASSERT_EQ(list.size(), 3u);
    for (std::size_t k = 0; k < list.size(); ++k) {
        EXPECT_LT(list.i()[k], list.j()[k]);
    }
}

TEST(NeighborList, CoincidentAtomsArePairsAtDistanceZero) {
    const std::vector<Eigen::Vector3d> x{{1, 2, 3}, {1, 2, 3}};
    const NeighborList list = tricell::compute_neighbors(cube10, x, with_cutoff(1.0));
    ASSERT_EQ(list.size(), 2u);
    EXPECT_EQ(list.distances()[0], 0.0);
}

TEST(NeighborList, EmptyInputGivesEmptyList) {
    const std::vector<Eigen::Vector3d> none;
    NeighborOptions o = with_cutoff(3.0);
    o.sorted = true;
    const NeighborList list = tricell::compute_neighbors(cube10, none, o);
    EXPECT_TRUE(list.empty());
    EXPECT_EQ(list.offsets(), std::vector<std::size_t>{0});
}

TEST(NeighborList, OpenSystemHasNoImages) {
    const Box box = Box::from_parameters(3, 3, 3, 90, 90, 90, tricell::Periodicity::none());
    const std::vector<Eigen::Vector3d> x{{0, 0, 0}, {2.9, 0, 0}, {-50, 0, 0}, {-51, 0, 0}};
    const NeighborList list = tricell::compute_neighbors(box, x, with_cutoff(1.5));
    ASSERT_EQ(list.size(), 2u); // only 2-3, both orientations; 0-1 only through an image
    EXPECT_EQ(list.shift(0), Shift(0, 0, 0));
}

TEST(NeighborList, QuantitiesSubsetStoresOnlyWhatWasAsked) {
    const std::vector<Eigen::Vector3d> x{{0.5, 5, 5}, {9.5, 5, 5}};
    NeighborOptions o = with_cutoff(1.5);
    o.quantities = tricell::Quantities{false, false, false};
    o.sorted = true; // sorting needs S internally; it is still dropped from the output
    const NeighborList list = tricell::compute_neighbors(cube10, x, o);
    EXPECT_EQ(list.size(), 2u);
    EXPECT_TRUE(list.shifts().empty());
    EXPECT_TRUE(list.distances().empty());
    EXPECT_TRUE(list.vectors().empty());
}

TEST(NeighborList, SortedOrderAndOffsets) {
    std::vector<Eigen::Vector3d> x;
    for (int k = 0; k < 40; ++k) {
        x.emplace_back(std::fmod(k * 3.7, 10.0), std::fmod(k * 1.3, 10.0),
                       std::fmod(k * 7.1, 10.0));
    }
    NeighborOptions o = with_cutoff(4.0);
    o.sorted = true;
    const NeighborList list = tricell::compute_neighbors(cube10, x, o);
    ASSERT_EQ(list.offsets().size(), x.size() + 1);
    for (std::size_t k = 1; k < list.size(); ++k) {
        const auto key = [&](std::size_t p) {
            const Shift s = list.shift(p);
            return std::make_tuple(list.i()[p], list.j()[p], s[0], s[1], s[2]);
        };
        ASSERT_LT(key(k - 1), key(k));
    }
    for (std::uint32_t i = 0; i < x.size(); ++i) {
        for (std::size_t p = list.offsets()[i]; p < list.offsets()[i + 1]; ++p) {
            EXPECT_EQ(list.i()[p], i);
        }
    }
}

TEST(NeighborList, ReusedOutputIsOverwritten) {
    NeighborList list;
    const std::vector<Eigen::Vector3d> x{{0.5, 5, 5}, {9.5, 5, 5}};
    tricell::compute_neighbors(cube10, x, with_cutoff(1.5), list);
    tricell::compute_neighbors(cube10, x, with_cutoff(0.5), list);
    EXPECT_TRUE(list.empty());
    EXPECT_TRUE(list.distances().empty());
}

TEST(NeighborList, RejectsBadCutoff) {
    const std::vector<Eigen::Vector3d> x{{0, 0, 0}};
    EXPECT_THROW_MSG(tricell::compute_neighbors(cube10, x, with_cutoff(-1.5)),
                     tricell::InvalidArgument, "cutoff must be > 0 (got -1.5)");
    EXPECT_THROW_MSG(tricell::compute_neighbors(cube10, x, with_cutoff(0)),
                     tricell::InvalidArgument, "cutoff must be > 0 (got 0)");
    EXPECT_THROW_MSG(tricell::compute_neighbors(cube10, x, with_cutoff(std::nan(""))),
                     tricell::InvalidArgument, "cutoff must be finite (got nan)");
    EXPECT_THROW_MSG(
        tricell::compute_neighbors(cube10, x, with_cutoff(std::numeric_limits<double>::infinity())),
        tricell::InvalidArgument, "cutoff must be finite (got inf)");
    NeighborOptions o = with_cutoff(1);
    o.cells_per_cutoff = 0.5;
    EXPECT_THROW_MSG(tricell::compute_neighbors(cube10, x, o), tricell::InvalidArgument,
                     "cells_per_cutoff must be 0 (chosen by the search) or >= 1 (got 0.5)");
    o.cells_per_cutoff = -1;
    EXPECT_THROW_MSG(tricell::compute_neighbors(cube10, x, o), tricell::InvalidArgument,
                     "cells_per_cutoff must be 0 (chosen by the search) or >= 1 (got -1)");
    o.cells_per_cutoff = 0;
    o.threads = -2;
    EXPECT_THROW_MSG(tricell::compute_neighbors(cube10, x, o), tricell::InvalidArgument,
                     "threads must be in [0, 1024] (got -2)");
}

TEST(NeighborList, RejectsBadVariableCutoffsNamingThem) {
    const std::vector<Eigen::Vector3d> x{{0, 0, 0}, {1, 0, 0}};
    NeighborOptions o;
    o.radii = {1.0, -0.5};
    EXPECT_THROW_MSG(tricell::compute_neighbors(cube10, x, o), tricell::InvalidArgument,
                     "radii[1] must be finite and >= 0 (got -0.5)");
    o.radii = {1.0};
    EXPECT_THROW_MSG(tricell::compute_neighbors(cube10, x, o), tricell::InvalidArgument,
                     "radii has 1 entries for 2 positions");
    o.radii = {1.0, 1.0};
    o.cutoff = 3;
    EXPECT_THROW_MSG(tricell::compute_neighbors(cube10, x, o), tricell::InvalidArgument,
                     "cutoff must be 0 when radii decide which pairs count (got 3)");
    o.cutoff = 0;
    o.species_cutoffs = {{1, 2, 2.0}};
    EXPECT_THROW_MSG(tricell::compute_neighbors(cube10, x, o), tricell::InvalidArgument,
                     "set radii or species_cutoffs, not both");
    o.radii.clear();
    EXPECT_THROW_MSG(tricell::compute_neighbors(cube10, x, o), tricell::InvalidArgument,
                     "species has 0 entries for 2 positions");
    o.species = {1, 2};
    o.species_cutoffs = {{1, 2, 2.0}, {2, 1, 2.5}};
    EXPECT_THROW_MSG(tricell::compute_neighbors(cube10, x, o), tricell::InvalidArgument,
                     "species pair 2-1 has two cutoffs in species_cutoffs (2 and 2.5)");
    o.species_cutoffs = {{1, 2, 0.0}};
    EXPECT_THROW_MSG(tricell::compute_neighbors(cube10, x, o), tricell::InvalidArgument,
                     "species_cutoffs[0] (species 1-2) must be finite and > 0 (got 0)");
    o.species_cutoffs.clear();
    o.cutoff = 1;
    EXPECT_THROW_MSG(tricell::compute_neighbors(cube10, x, o), tricell::InvalidArgument,
                     "species is set but species_cutoffs is empty");
    o = NeighborOptions();
    o.cutoff = 1;
    o.hash_table_size = std::size_t(1) << 40;
    EXPECT_THROW_MSG(tricell::compute_neighbors(cube10, x, o), tricell::InvalidArgument,
                     "hash_table_size must be at most 2^31");
    EXPECT_THROW_MSG(
        tricell::parse_backend("fast"), tricell::InvalidArgument,
        "unknown search backend 'fast' (expected auto, dense, linked, hash, octree or direct)");
    for (const SearchBackend b : tricell::search_backends()) {
        EXPECT_EQ(tricell::parse_backend(tricell::backend_name(b)), b);
    }
    EXPECT_EQ(tricell::backend_choices(), "auto, dense, linked, hash, octree or direct");
}

TEST(NeighborList, ZeroRadiiOrAbsentSpeciesGiveNoPairs) {
    const std::vector<Eigen::Vector3d> x{{0, 0, 0}, {1, 0, 0}};
    NeighborOptions o;
    o.radii = {0.0, 0.0};
    o.sorted = true;
    NeighborList list = tricell::compute_neighbors(cube10, x, o);
    EXPECT_TRUE(list.empty());
    EXPECT_EQ(list.offsets(), (std::vector<std::size_t>{0, 0, 0}));
    o.radii.clear();
    o.species = {1, 1};
    o.species_cutoffs = {{1, 2, 5.0}}; // species 2 never occurs
    EXPECT_TRUE(tricell::compute_neighbors(cube10, x, o).empty());
    o.species_cutoffs = {{1, 1, 1.0}}; // d = 1 is not < 1
    EXPECT_TRUE(tricell::compute_neighbors(cube10, x, o).empty());
    o.species_cutoffs = {{1, 1, std::nextafter(1.0, 2.0)}};
    EXPECT_EQ(tricell::compute_neighbors(cube10, x, o).size(), 2u);
}

TEST(NeighborList, RejectsNonFinitePositionNamingIt) {
    std::vector<Eigen::Vector3d> x(20, Eigen::Vector3d(1, 1, 1));
    x[17].y() = std::numeric_limits<double>::quiet_NaN();
    EXPECT_THROW_MSG(tricell::compute_neighbors(cube10, x, with_cutoff(1)),
                     tricell::InvalidArgument, "position 17 is not finite");
}

TEST(NeighborList, DirectBackendRefusesMillionsOfImages) {
    // Two atoms 1e6 apart along the open axis of a 1 x 1 slab, cutoff 1100: the direct backend's
    // images would number (2 * 1101 + 1)^2, about 4.9e6, refused before any is listed.
    const Box slab =
        Box::from_parameters(1, 1, 1, 90, 90, 90, tricell::Periodicity{{true, true, false}});
    const std::vector<Eigen::Vector3d> x{{0.5, 0.5, 0}, {0.5, 0.5, 1e6}};
    NeighborOptions o = with_cutoff(1100);
    o.backend = SearchBackend::direct;
    EXPECT_THROW_MSG(tricell::compute_neighbors(slab, x, o), tricell::InvalidArgument,
                     "more than the direct backend enumerates");
}

TEST(NeighborList, RejectsPositionTooFarToWrap) {
    const std::vector<Eigen::Vector3d> x{{0, 0, 0}, {1e12, 0, 0}};
    EXPECT_THROW_MSG(tricell::compute_neighbors(cube10, x, with_cutoff(1)),
                     tricell::InvalidArgument, "position 1: fractional coordinate a");
}

TEST(NeighborList, BatchedOutputEqualsBruteForceForAnyThreadCount) {
    // The batched in-place output of 2 to 4 threads (lib/output/unit_ordered_batches.hpp) against
    // one thread storing directly and against brute force: a list of about 294000 pairs, and
    // clustered atoms whose list is several times the per-cell estimate, so the final columns
    // must grow while batches are copied in.
    // The large lists reuse one list object (its per-thread batch columns too); the clustered
    // ones start from an empty list each time, so that no capacity is left from before.
    NeighborList reused;
    for (std::uint64_t seed = 0; seed < 4; ++seed) {
        SCOPED_TRACE(seed);
        std::mt19937_64 rng(seed);
        std::uniform_real_distribution<double> u(0, 10), jitter(-0.05, 0.05);
        std::vector<Eigen::Vector3d> x;
        double cutoff = 0.5;
        if (seed % 2 == 0) {
            for (int k = 0; k < 2000; ++k) {
                x.emplace_back(u(rng), u(rng), u(rng));
            }
            cutoff = 2.6; // about 294000 pairs
        } else {
            for (int k = 0; k < 80; ++k) {
                const double c = k < 40 ? 1.0 : 6.0;
                x.emplace_back(c + jitter(rng), c + jitter(rng), c + jitter(rng));
            }
        }
        const tricell::testing::PairMap expected =
            tricell::testing::brute_force_pairs(cube10, x, cutoff);
        NeighborOptions o = with_cutoff(cutoff);
        o.quantities.vectors = true;
        if (seed % 2 == 1) {
            o.backend = tricell::SearchBackend::dense;
            o.max_cells = 8; // cells of 5: the per-cell estimate cannot see the clusters
        }
        NeighborList first;
        for (const int threads : {1, 2, 3, 4}) {
            SCOPED_TRACE(threads);
            o.threads = threads;
            NeighborList fresh;
            NeighborList& list = seed % 2 == 0 ? reused : fresh;
            tricell::compute_neighbors(cube10, x, o, list);
            ASSERT_EQ(list.size(), expected.size());
            if (threads == 1) {
                first = list;
                const tricell::testing::PairMap found = tricell::testing::to_map(list);
                for (const auto& [key, value] : expected) {
                    const auto it = found.find(key);
                    ASSERT_NE(it, found.end());
                    EXPECT_NEAR(it->second.distance, value.distance, 1e-12);
                }
            } else {
                ASSERT_EQ(list.i(), first.i());
                ASSERT_EQ(list.j(), first.j());
                ASSERT_EQ(list.shifts(), first.shifts());
                ASSERT_EQ(list.distances(), first.distances());
                ASSERT_EQ(list.vectors(), first.vectors());
            }
        }
    }
}

// A full list in the search's order is found through the half stencil and turned around: on
// every backend its search makes the half list's distance tests, and about half of those
// of the same list grouped (which keeps the full stencil), with the same pairs.
TEST(NeighborList, UnorderedFullListSearchesTheHalfStencil) {
    std::mt19937_64 rng{7};
    std::uniform_real_distribution<double> u(0, 1);
    const Box box =
        Box::from_columns((Eigen::Matrix3d() << 14, 2, -1, 0, 13, 1.5, 0, 0, 15).finished(),
                          tricell::Periodicity::all());
    std::vector<Eigen::Vector3d> x;
    for (int k = 0; k < 600; ++k) {
        x.push_back(box.matrix() * Eigen::Vector3d(u(rng), u(rng), u(rng)));
    }
    const auto tests = [&](const NeighborOptions& o) {
        tricell::NeighborSearch search;
        search.build(box, x, o);
        double sum = 0;
        for (const double t : search.unit_work().measured) {
            sum += t;
        }
        return sum;
    };
    for (const SearchBackend backend : tricell::search_backends()) {
        SCOPED_TRACE(tricell::backend_name(backend));
        NeighborOptions o = with_cutoff(4);
        o.backend = backend;
        o.half = true;
        const double half = tests(o);
        o.half = false;
        const double full = tests(o);
        o.grouped = true;
        const double grouped = tests(o);
        EXPECT_NEAR(full, half, 0.02 * half); // kernel calls of fewer atoms may prune differently
        EXPECT_GT(grouped, 1.6 * full);
        NeighborList unordered, by_i;
        o.quantities.vectors = true;
        o.grouped = false;
        tricell::compute_neighbors(box, x, o, unordered);
        o.grouped = true;
        tricell::compute_neighbors(box, x, o, by_i);
        const tricell::testing::PairMap a = tricell::testing::to_map(unordered);
        const tricell::testing::PairMap b = tricell::testing::to_map(by_i);
        ASSERT_EQ(a.size(), unordered.size());
        ASSERT_EQ(a.size(), b.size());
        for (const auto& [key, value] : a) {
            const auto found = b.find(key);
            ASSERT_TRUE(found != b.end());
            EXPECT_EQ(found->second.distance, value.distance);
            EXPECT_EQ(found->second.vector, value.vector);
        }
    }
}

TEST(NeighborList, DirectBackendOrderIsTheSameForAnyThreadCount) {
    // An open box: S = 0 is the direct backend's only image. A few atoms take one range through
    // the range kernel, many the per-pair path; either way the unordered list is identical for
    // 1 to 3 threads (its work units are atoms, split anywhere between threads).
    const Box open =
        Box::from_columns(Eigen::Matrix3d::Identity() * 30, tricell::Periodicity::none());
    for (const int atoms : {40, 63, 64, 1200}) {
        SCOPED_TRACE(atoms);
        std::mt19937_64 rng{std::uint64_t(atoms)};
        std::uniform_real_distribution<double> u(0, atoms < 100 ? 6.0 : 20.0);
        std::vector<Eigen::Vector3d> x;
        for (int k = 0; k < atoms; ++k) {
            x.emplace_back(u(rng), u(rng), u(rng));
        }
        for (const bool half : {false, true}) {
            NeighborOptions o = with_cutoff(3);
            o.backend = SearchBackend::direct;
            o.half = half;
            NeighborList first;
            for (const int threads : {1, 2, 3}) {
                o.threads = threads;
                const NeighborList list = tricell::compute_neighbors(open, x, o);
                if (threads == 1) {
                    first = list;
                    const tricell::testing::PairMap expected =
                        tricell::testing::brute_force_pairs(open, x, 3);
                    ASSERT_EQ(list.size(), half ? expected.size() / 2 : expected.size());
                } else {
                    ASSERT_EQ(list.i(), first.i()) << threads << " threads, half " << half;
                    ASSERT_EQ(list.j(), first.j()) << threads << " threads, half " << half;
                }
            }
        }
    }
}

TEST(NeighborList, ThreadedBuildNamesTheFirstBadPosition) {
    // The checks and the wrap run on contiguous ranges of atoms, one per thread: the error names
    // the lowest bad index whatever the thread count, and a non-finite position anywhere comes
    // before a position too far to wrap.
    for (const int threads : {1, 2, 3, 4}) {
        SCOPED_TRACE(threads);
        std::vector<Eigen::Vector3d> x(200, Eigen::Vector3d(1, 1, 1));
        NeighborOptions o = with_cutoff(1);
        o.threads = threads;
        x[170].z() = std::numeric_limits<double>::infinity();
        x[190].x() = std::numeric_limits<double>::quiet_NaN();
        EXPECT_THROW_MSG(tricell::compute_neighbors(cube10, x, o), tricell::InvalidArgument,
                         "position 170 is not finite");
        x[150].x() = 1e12;
        x[160].y() = 1e12;
        EXPECT_THROW_MSG(tricell::compute_neighbors(cube10, x, o), tricell::InvalidArgument,
                         "position 170 is not finite");
        x[170].z() = x[190].x() = 1;
        EXPECT_THROW_MSG(tricell::compute_neighbors(cube10, x, o), tricell::InvalidArgument,
                         "position 150: fractional coordinate a");
    }
}

TEST(NeighborList, RefusesAbsurdPairCountBeforeAllocating) {
    const std::vector<Eigen::Vector3d> x{{0, 0, 0}, {1, 1, 1}};
    NeighborOptions o = with_cutoff(5000);
    EXPECT_THROW_MSG(tricell::compute_neighbors(cube10, x, o), tricell::InvalidArgument,
                     "more than max_pairs = 500000000");
    o.cutoff = 30;
    o.max_pairs = 100;
    EXPECT_THROW_MSG(tricell::compute_neighbors(cube10, x, o), tricell::InvalidArgument,
                     "estimated from the density");
}

TEST(NeighborList, ErrorLeavesOutputEmptyNotHalfWritten) {
    // The estimate passes (uniform density), but the atoms are clustered: the actual count
    // exceeds max_pairs while storing.
    std::vector<Eigen::Vector3d> x(30, Eigen::Vector3d(1, 1, 1));
    NeighborOptions o = with_cutoff(0.5);
    o.max_pairs = 100;
    NeighborList list;
    const std::vector<Eigen::Vector3d> pair{{0, 0, 0}, {0.1, 0, 0}};
    tricell::compute_neighbors(cube10, pair, with_cutoff(0.5), list);
    ASSERT_EQ(list.size(), 2u);
    EXPECT_THROW_MSG(tricell::compute_neighbors(cube10, x, o, list), tricell::InvalidArgument,
                     "the neighbour list has too many pairs, more than max_pairs = 100");
    EXPECT_TRUE(list.empty());
    EXPECT_TRUE(list.distances().empty());
    // The same with threads: each chunk stays below the limit, the total does not.
    x.resize(12);
    x.insert(x.end(), 12, Eigen::Vector3d(6, 6, 6));
    o.threads = 2;
    o.max_pairs = 2 * 12 * 11;
    o.max_cells = 64;
    tricell::compute_neighbors(cube10, x, o, list);
    ASSERT_EQ(list.size(), 2u * 12 * 11);
    o.max_pairs = 2 * 12 * 11 - 1;
    EXPECT_THROW_MSG(tricell::compute_neighbors(cube10, x, o, list), tricell::InvalidArgument,
                     "more than max_pairs");
    EXPECT_TRUE(list.empty());
}

TEST(NeighborList, StrictCutoffHoldsToTheLastBit) {
    // |D| rounds to exactly 5 here; cutoff^2 rounded would let it in.
    const Box open = Box::from_parameters(20, 20, 20, 90, 90, 90, tricell::Periodicity::none());
    const std::vector<Eigen::Vector3d> x{
        {0, 0, 0}, {-1.1332655556774685, -2.9323795585259296, -3.888040548278054}};
    const NeighborList list = tricell::compute_neighbors(open, x, with_cutoff(5.0));
    for (std::size_t k = 0; k < list.size(); ++k) {
        EXPECT_LT(list.distances()[k], 5.0);
    }
    for (const double cutoff : {1e-300, 0.1, 1.0, 2.5, 5.0, 7.3, 1e10}) {
        const double t = tricell::detail::strict_threshold_sq(cutoff);
        EXPECT_LT(std::sqrt(std::nextafter(t, 0.0)), cutoff) << cutoff;
        EXPECT_GE(std::sqrt(t), cutoff) << cutoff;
    }
}

TEST(NeighborList, TinyCutoffStillFindsCoincidentAtoms) {
    const std::vector<Eigen::Vector3d> x{{1, 1, 1}, {1, 1, 1}};
    EXPECT_EQ(tricell::compute_neighbors(cube10, x, with_cutoff(1e-300)).size(), 2u);
}

TEST(NeighborList, FailedBuildLeavesNoUsableSearch) {
    tricell::NeighborSearch search;
    NeighborList list;
    EXPECT_THROW_MSG(search.compute(list), tricell::InvalidArgument, "needs a successful build");
    std::vector<Eigen::Vector3d> few(10, Eigen::Vector3d(1, 2, 3));
    search.build(cube10, few, with_cutoff(10));
    std::vector<Eigen::Vector3d> many(3000, Eigen::Vector3d(4, 5, 6));
    NeighborOptions o = with_cutoff(1);
    o.max_pairs = 10;
    EXPECT_THROW(search.build(cube10, many, o), tricell::InvalidArgument);
    EXPECT_THROW_MSG(search.compute(list), tricell::InvalidArgument, "needs a successful build");
    EXPECT_TRUE(list.empty());
}

TEST(NeighborList, RejectsAbsurdThreadAndCellCounts) {
    const std::vector<Eigen::Vector3d> x{{0, 0, 0}};
    NeighborOptions o = with_cutoff(1);
    o.threads = 5000;
    EXPECT_THROW_MSG(tricell::compute_neighbors(cube10, x, o), tricell::InvalidArgument,
                     "threads must be in [0, 1024] (got 5000)");
    o.threads = 1;
    o.max_cells = std::size_t(1) << 40;
    EXPECT_THROW_MSG(tricell::compute_neighbors(cube10, x, o), tricell::InvalidArgument,
                     "max_cells must be at most 2^31");
}

namespace {

// A dense cluster of `n` atoms (0.1 per cubic unit) centred at `centre`.
std::vector<Eigen::Vector3d> cluster(std::size_t n, const Eigen::Vector3d& centre,
                                     std::uint64_t seed) {
    std::mt19937_64 rng(seed);
    const double side = std::cbrt(double(n) / 0.1);
    std::uniform_real_distribution<double> u(-side / 2, side / 2);
    std::vector<Eigen::Vector3d> x(n);
    for (auto& r : x) {
        r = centre + Eigen::Vector3d(u(rng), u(rng), u(rng));
    }
    return x;
}

} // namespace

TEST(HashBackend, OneSlotTableGivesTheSameListAsTheDenseGrid) {
    // Every non-empty cell collides in the single slot: lookups must compare coordinates.
    const auto x = cluster(400, Eigen::Vector3d(5, 5, 5), 3);
    NeighborOptions o = with_cutoff(2.5);
    o.sorted = true;
    o.backend = tricell::SearchBackend::dense;
    const NeighborList dense = tricell::compute_neighbors(cube10, x, o);
    o.backend = tricell::SearchBackend::hash;
    for (const std::size_t slots : {std::size_t(1), std::size_t(2), std::size_t(7)}) {
        o.hash_table_size = slots;
        const NeighborList hashed = tricell::compute_neighbors(cube10, x, o);
        EXPECT_EQ(hashed.i(), dense.i()) << slots << " slots";
        EXPECT_EQ(hashed.j(), dense.j());
        EXPECT_EQ(hashed.shifts(), dense.shifts());
        EXPECT_EQ(hashed.distances(), dense.distances());
    }
    EXPECT_GT(dense.size(), 1000u);
}

TEST(HashBackend, MemoryFollowsTheAtomsNotTheVolume) {
    // Two clusters a million units apart along open axes, and a cluster in a periodic box of
    // 10^4 per side: the hash stores at most one cell per atom, and auto takes it.
    std::vector<Eigen::Vector3d> x = cluster(300, Eigen::Vector3d(0, 0, 0), 5);
    const auto far = cluster(300, Eigen::Vector3d(1e6, -1e6, 3e5), 6);
    x.insert(x.end(), far.begin(), far.end());
    const Box open = Box::from_parameters(10, 10, 10, 90, 90, 90, tricell::Periodicity::none());
    const Box huge = Box::from_parameters(1e4, 1e4, 1e4, 90, 90, 90);
    for (const Box& box : {open, huge}) {
        NeighborOptions o = with_cutoff(2.0);
        tricell::NeighborSearch search;
        search.build(box, x, o);
        EXPECT_EQ(search.info().backend, tricell::SearchBackend::hash);
        EXPECT_LE(search.info().stored_cells, x.size());
        NeighborList list;
        search.compute(list);
        o.backend = tricell::SearchBackend::dense;
        const NeighborList dense = tricell::compute_neighbors(box, x, o);
        EXPECT_EQ(list.size(), dense.size());
        EXPECT_GT(list.size(), 0u);
    }
}

TEST(NeighborSearch, AutoTakesTheDenseGridForAUniformLiquid) {
    std::vector<Eigen::Vector3d> x = cluster(2000, Eigen::Vector3d(0, 0, 0), 9);
    const double side = std::cbrt(2000 / 0.1);
    const Box box = Box::from_parameters(side, side, side, 90, 90, 90);
    tricell::NeighborSearch search;
    search.build(box, x, with_cutoff(5));
    EXPECT_EQ(search.info().backend, tricell::SearchBackend::dense);
    EXPECT_FALSE(search.info().reduced_frame);
}

// The direct backend keeps its images from one build to the next while the frame, periodicity,
// radius and (rounded) atom spread stay the same. A search reused along a random walk that
// changes one of them at a time (or nothing) must still give, every time, exactly the dense
// grid's sorted list and the brute-force pairs.
TEST(DirectBackend, ReusedSearchFollowsEveryChangeOfBoxRadiusAndAtoms) {
    std::mt19937_64 rng(13);
    std::uniform_real_distribution<double> unit(0, 1);
    Eigen::Matrix3d h = tricell::testing::random_box_matrix(rng, 2, 4, 0.5);
    tricell::Periodicity pbc = tricell::Periodicity::all();
    double cutoff = 5;
    std::vector<Eigen::Vector3d> x(4);
    for (auto& r : x) {
        r = h * Eigen::Vector3d(unit(rng), unit(rng), unit(rng));
    }
    NeighborOptions direct;
    direct.backend = SearchBackend::direct;
    direct.sorted = true;
    direct.quantities.vectors = true;
    NeighborOptions dense = direct;
    dense.backend = SearchBackend::dense;
    tricell::NeighborSearch search;
    NeighborList list, reference;
    std::size_t pairs = 0;
    for (int step = 0; step < 300; ++step) {
        SCOPED_TRACE(step);
        switch (rng() % 6) {
        case 0:
            h = tricell::testing::random_box_matrix(rng, 2, 4, 0.5);
            break;
        case 1:
            pbc.axes[rng() % 3] = !pbc.axes[rng() % 3];
            break;
        case 2:
            cutoff = 2 + 5 * unit(rng);
            break;
        case 3: // one atom moved a little (the rounded spread usually unchanged)
            x[rng() % x.size()] += 0.05 * Eigen::Vector3d(unit(rng), unit(rng), unit(rng));
            break;
        case 4: // one atom moved far (the spread changes)
            x[rng() % x.size()] = h * Eigen::Vector3d(3 * unit(rng), unit(rng), unit(rng));
            break;
        default: // nothing changes
            break;
        }
        direct.cutoff = dense.cutoff = cutoff;
        const Box box = Box::from_columns(h, pbc);
        search.build(box, x, direct);
        search.compute(list);
        tricell::compute_neighbors(box, x, dense, reference);
        tricell::testing::expect_identical(reference, list);
        const auto expected = tricell::testing::brute_force_pairs(box, x, cutoff);
        const auto found = tricell::testing::to_map(list);
        for (const auto& [key, value] : expected) {
            if (std::abs(value.distance - cutoff) > 1e-9 && found.count(key) == 0) {
                ADD_FAILURE() << "missing pair at distance " << value.distance;
            }
        }
        for (const auto& [key, value] : found) {
            if (std::abs(value.distance - cutoff) > 1e-9 && expected.count(key) == 0) {
                ADD_FAILURE() << "extra pair at distance " << value.distance;
            }
        }
        pairs += list.size();
    }
    EXPECT_GT(pairs, 10000u);
}

// A search keeps its large buffers from one build to the next (the dense grid's cell of each
// atom and its threaded sort's table, the atom table, the cell boxes), so that a repeated search
// writes into memory already in use. Reused over systems that grow and shrink, with thread
// counts and list kinds that change, it must give, every time, exactly the list of a fresh
// search, and every pair of the brute force.
TEST(NeighborSearch, ReusedDenseSearchEqualsAFreshOneAsSizesAndThreadsChange) {
    std::mt19937_64 rng(29);
    std::uniform_real_distribution<double> unit(0, 1);
    tricell::NeighborSearch reused;
    NeighborList list, reference;
    std::size_t pairs = 0;
    for (int step = 0; step < 40; ++step) {
        SCOPED_TRACE(step);
        const std::size_t n = 1 + rng() % 3000;
        const double cutoff = 2 + 2 * unit(rng);
        Eigen::Matrix3d h = tricell::testing::random_box_matrix(rng, 1, 1.5, 0.3);
        h *= std::cbrt(double(n) / (0.02 + 0.08 * unit(rng)) / std::abs(h.determinant()));
        std::vector<Eigen::Vector3d> x(n);
        for (auto& r : x) {
            r = h * Eigen::Vector3d(unit(rng), unit(rng), unit(rng));
        }
        NeighborOptions o = with_cutoff(cutoff);
        o.backend = SearchBackend::dense;
        o.threads = int(1 + rng() % 3);
        o.half = rng() % 2 == 0;
        const Box box = Box::from_columns(h);
        reused.build(box, x, o);
        reused.compute(list);
        tricell::NeighborSearch fresh;
        fresh.build(box, x, o);
        fresh.compute(reference);
        tricell::testing::expect_identical(reference, list);
        if (n <= 800) {
            const auto all = tricell::testing::brute_force_pairs(box, x, cutoff);
            const auto expected = o.half ? tricell::testing::canonical_half(all) : all;
            const auto found = tricell::testing::to_map(list);
            std::size_t wrong = 0;
            for (const auto& [key, value] : expected) {
                wrong += std::abs(value.distance - cutoff) > 1e-9 && found.count(key) == 0;
            }
            for (const auto& [key, value] : found) {
                wrong += std::abs(value.distance - cutoff) > 1e-9 && expected.count(key) == 0;
            }
            EXPECT_EQ(wrong, 0u) << "pairs missing or extra against the brute force";
        }
        pairs += list.size();
    }
    EXPECT_GT(pairs, 100000u);
}

TEST(NeighborSearch, CellsOfHalfACutoffOnlyForManyNeighboursAndOneCutoff) {
    // The automatic grid (cells_per_cutoff = 0) takes cells of half a cutoff only where the
    // dense backend's range kernel gains from them: one cutoff for all atoms, no query, and
    // enough neighbours per atom (policy/cost_model.hpp); else cells of one cutoff.
    const Box box = Box::from_parameters(30, 30, 30, 90, 90, 90);
    const double cutoff = 6; // a sphere of 905 A^3
    const auto cells_of = [&](std::size_t atoms, NeighborOptions o) {
        std::mt19937_64 rng(atoms);
        std::uniform_real_distribution<double> u(0, 30);
        std::vector<Eigen::Vector3d> x(atoms);
        for (Eigen::Vector3d& p : x) {
            p = Eigen::Vector3d(u(rng), u(rng), u(rng));
        }
        o.cutoff = o.radii.empty() ? cutoff : 0;
        o.backend = SearchBackend::dense;
        tricell::NeighborSearch search;
        search.build(box, x, o);
        return search.info().cells;
    };
    for (const bool half : {false, true}) {
        SCOPED_TRACE(half ? "half" : "full");
        NeighborOptions whole, halves, chosen;
        whole.half = halves.half = chosen.half = half;
        whole.cells_per_cutoff = 1;
        halves.cells_per_cutoff = 2;
        const std::size_t many = 6000, few = 1200; // 200 and 40 neighbours per atom
        ASSERT_NE(cells_of(many, whole), cells_of(many, halves));
        EXPECT_EQ(cells_of(many, chosen), cells_of(many, halves));
        EXPECT_EQ(cells_of(few, chosen), cells_of(few, whole));
        NeighborOptions radii = chosen; // per-atom radii take the general scan
        radii.radii.assign(many, cutoff / 2);
        EXPECT_EQ(cells_of(many, radii), cells_of(many, whole));
        NeighborOptions query = chosen; // as does a subset search
        query.query = std::vector<std::uint32_t>{0, 1, 2};
        EXPECT_EQ(cells_of(many, query), cells_of(many, whole));
    }
}
