// compute_neighbors_batch: every structure's slice equals its own compute_neighbors() list,
// array for array, and the brute-force oracle; the output is the same for any thread count;
// errors name the lowest bad structure and leave the output empty.
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "support/brute_force.hpp"
#include "support/expect_throw_msg.hpp"
#include "support/random_boxes.hpp"
#include "tricell/batch.hpp"
#include "tricell/error.hpp"

using tricell::BatchList;
using tricell::BatchStructure;
using tricell::Box;
using tricell::NeighborList;
using tricell::NeighborOptions;
using tricell::Periodicity;

namespace {

#ifdef TRICELL_PROPERTY_CASES
constexpr int batch_cases = TRICELL_PROPERTY_CASES / 10;
#else
constexpr int batch_cases = 200;
#endif

// A batch of small random structures for one cutoff: cells from much smaller than the cutoff
// to a few cutoffs wide, general tilts, every periodicity, 0 to 40 atoms, some far outside.
struct RandomBatch {
    std::vector<Box> boxes;
    std::vector<std::vector<Eigen::Vector3d>> positions;
    double cutoff = 1;
    std::vector<BatchStructure> view() const {
        std::vector<BatchStructure> out;
        for (std::size_t s = 0; s < boxes.size(); ++s) {
            out.push_back(BatchStructure{boxes[s], positions[s]});
        }
        return out;
    }
};

RandomBatch random_batch(std::uint64_t seed) {
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> unit(0, 1);
    auto integer = [&](int lo, int hi) { return std::uniform_int_distribution<int>(lo, hi)(rng); };
    RandomBatch batch;
    batch.cutoff = 2 + 3 * unit(rng);
    const int count = integer(0, 12);
    for (int s = 0; s < count; ++s) {
        const double len = batch.cutoff * (0.4 + 2.0 * unit(rng));
        const Eigen::Matrix3d h = tricell::testing::random_box_matrix(rng, 0.6 * len, len, 0.6);
        const int bits = integer(0, 2) == 0 ? integer(0, 7) : 7;
        batch.boxes.push_back(
            Box::from_columns(h, Periodicity{{bool(bits & 1), bool(bits & 2), bool(bits & 4)}}));
        std::vector<Eigen::Vector3d> x;
        // fewer atoms in cells smaller than the cutoff (a few thousand pairs at most)
        const int n = integer(0, 5) == 0 ? integer(0, 2) : integer(1, len > batch.cutoff ? 40 : 8);
        for (int i = 0; i < n; ++i) {
            Eigen::Vector3d f(unit(rng), unit(rng), unit(rng));
            if (integer(0, 6) == 0) {
                f[integer(0, 2)] += double(integer(-50, 50));
            }
            x.push_back(h * f);
        }
        batch.positions.push_back(x);
    }
    return batch;
}

template <class T, class U> void expect_slice(const T& all, std::size_t from, const U& part) {
    ASSERT_LE(from + part.size(), all.size());
    for (std::size_t k = 0; k < part.size(); ++k) {
        ASSERT_EQ(all[from + k], part[k]) << "at " << k; // bit for bit, also for doubles
    }
}

// The batch slice of structure s equals `single` (computed alone) in every column.
void expect_same_as_single(const BatchList& batch, std::size_t s, const NeighborList& single) {
    const std::size_t begin = batch.pair_offsets()[s];
    ASSERT_EQ(batch.pair_offsets()[s + 1] - begin, single.size());
    expect_slice(batch.i(), begin, single.i());
    expect_slice(batch.j(), begin, single.j());
    expect_slice(batch.shifts(), 3 * begin, single.shifts());
    expect_slice(batch.distances(), begin, single.distances());
    expect_slice(batch.vectors(), 3 * begin, single.vectors());
}

tricell::testing::PairMap slice_map(const BatchList& batch, std::size_t s) {
    tricell::testing::PairMap out;
    for (std::size_t k = batch.pair_offsets()[s]; k < batch.pair_offsets()[s + 1]; ++k) {
        const Eigen::Vector3d d(batch.vectors()[3 * k], batch.vectors()[3 * k + 1],
                                batch.vectors()[3 * k + 2]);
        out[tricell::testing::PairKey{batch.i()[k], batch.j()[k], batch.shifts()[3 * k],
                                      batch.shifts()[3 * k + 1], batch.shifts()[3 * k + 2]}] =
            tricell::testing::PairValue{batch.distances()[k], d};
    }
    return out;
}

} // namespace

TEST(Batch, EachStructureEqualsItsOwnListAndTheBruteForce_RandomBatches) {
    BatchList batch; // reused across cases: stale buffers must never leak into a result
    NeighborList single;
    for (int c = 0; c < batch_cases; ++c) {
        const std::uint64_t seed = 9100 + std::uint64_t(c);
        SCOPED_TRACE(seed);
        const RandomBatch input = random_batch(seed);
        NeighborOptions options;
        options.cutoff = input.cutoff;
        options.half = c % 2 == 1;
        options.sorted = c % 3 == 0;
        options.grouped = c % 6 == 1;
        options.quantities.vectors = true;
        options.threads = 1 + c % 3;
        tricell::compute_neighbors_batch(input.view(), options, batch);
        const std::size_t count = input.boxes.size();
        ASSERT_EQ(batch.structure_count(), count);
        ASSERT_EQ(batch.pair_offsets().front(), 0u);
        ASSERT_EQ(batch.pair_offsets().back(), batch.size());
        std::size_t atoms = 0;
        for (std::size_t s = 0; s < count; ++s) {
            SCOPED_TRACE(s);
            ASSERT_EQ(batch.atom_offsets()[s], atoms);
            atoms += input.positions[s].size();
            NeighborOptions alone = options;
            alone.threads = 1;
            tricell::compute_neighbors(input.boxes[s], input.positions[s], alone, single);
            expect_same_as_single(batch, s, single);
            tricell::testing::PairMap expected = tricell::testing::brute_force_pairs(
                input.boxes[s], input.positions[s], input.cutoff);
            if (options.half) {
                expected = tricell::testing::canonical_half(expected);
            }
            const tricell::testing::PairMap got = slice_map(batch, s);
            ASSERT_EQ(got.size(), expected.size());
            for (const auto& [key, value] : expected) {
                const auto it = got.find(key);
                ASSERT_NE(it, got.end());
                EXPECT_NEAR(it->second.distance, value.distance, 1e-9);
            }
            if (options.with_offsets()) {
                // offsets() index the shared columns: atom a of s owns [offsets[k], offsets[k+1])
                for (std::size_t a = 0; a < input.positions[s].size(); ++a) {
                    const std::size_t k = batch.atom_offsets()[s] + a;
                    ASSERT_EQ(batch.offsets()[k + 1] - batch.offsets()[k],
                              single.offsets()[a + 1] - single.offsets()[a]);
                    ASSERT_EQ(batch.offsets()[k] - batch.pair_offsets()[s], single.offsets()[a]);
                }
            }
        }
        ASSERT_EQ(batch.atom_offsets().back(), atoms);
        EXPECT_EQ(batch.offsets().size(), options.with_offsets() ? atoms + 1 : 0u);
    }
}

TEST(Batch, OutputIsIdenticalForAnyThreadCount) {
    for (int c = 0; c < batch_cases / 4; ++c) {
        const std::uint64_t seed = 9700 + std::uint64_t(c);
        SCOPED_TRACE(seed);
        RandomBatch input = random_batch(seed);
        for (int more = 0; more < 3; ++more) { // enough structures for uneven runs
            const RandomBatch extra = random_batch(seed * 31 + std::uint64_t(more));
            for (std::size_t s = 0; s < extra.boxes.size(); ++s) {
                input.boxes.push_back(extra.boxes[s]);
                input.positions.push_back(extra.positions[s]);
            }
        }
        NeighborOptions options;
        options.cutoff = input.cutoff;
        options.half = c % 2 == 0;
        options.sorted = c % 3 == 1;
        BatchList one, many;
        options.threads = 1;
        tricell::compute_neighbors_batch(input.view(), options, one);
        for (int threads : {2, 3, 7, 0}) {
            SCOPED_TRACE(threads);
            options.threads = threads;
            tricell::compute_neighbors_batch(input.view(), options, many);
            EXPECT_EQ(many.pair_offsets(), one.pair_offsets());
            EXPECT_EQ(many.atom_offsets(), one.atom_offsets());
            EXPECT_EQ(many.offsets(), one.offsets());
            EXPECT_TRUE(many.i() == one.i());
            EXPECT_TRUE(many.j() == one.j());
            EXPECT_TRUE(many.shifts() == one.shifts());
            EXPECT_TRUE(many.distances() == one.distances());
            EXPECT_TRUE(many.vectors().empty());
        }
    }
}

TEST(Batch, QuantitiesPickTheColumns) {
    const RandomBatch input = random_batch(9001);
    NeighborOptions options;
    options.cutoff = input.cutoff;
    options.quantities.shifts = false;
    options.quantities.distances = false;
    BatchList batch;
    tricell::compute_neighbors_batch(input.view(), options, batch);
    EXPECT_EQ(batch.i().size(), batch.size());
    EXPECT_TRUE(batch.shifts().empty());
    EXPECT_TRUE(batch.distances().empty());
    EXPECT_TRUE(batch.vectors().empty());
}

TEST(Batch, EmptyBatchAndEmptyStructures) {
    NeighborOptions options;
    options.cutoff = 3;
    BatchList batch;
    tricell::compute_neighbors_batch(std::vector<BatchStructure>{}, options, batch);
    EXPECT_EQ(batch.structure_count(), 0u);
    EXPECT_EQ(batch.size(), 0u);
    EXPECT_EQ(batch.pair_offsets(), std::vector<std::size_t>{0});

    const Box cube = Box::from_parameters(2, 2, 2, 90, 90, 90);
    const std::vector<Eigen::Vector3d> none, one{{0.5, 0.5, 0.5}};
    std::vector<BatchStructure> input{{cube, none}, {cube, one}, {cube, none}};
    options.sorted = true;
    options.threads = 3;
    tricell::compute_neighbors_batch(input, options, batch);
    const NeighborList alone = tricell::compute_neighbors(cube, one, options);
    ASSERT_GT(alone.size(), 0u); // the atom's own images within 3 of a 2-wide cube
    EXPECT_EQ(batch.pair_offsets(), (std::vector<std::size_t>{0, 0, alone.size(), alone.size()}));
    EXPECT_EQ(batch.atom_offsets(), (std::vector<std::size_t>{0, 0, 1, 1}));
    EXPECT_EQ(batch.offsets(), (std::vector<std::size_t>{0, alone.size()}));
}

TEST(Batch, ErrorsNameTheLowestBadStructureAndLeaveTheOutputEmpty) {
    const RandomBatch input = random_batch(9002);
    std::vector<std::vector<Eigen::Vector3d>> positions(20, {{1, 1, 1}, {2, 1, 1}});
    const double nan = std::numeric_limits<double>::quiet_NaN();
    positions[13][1] = Eigen::Vector3d(0, nan, 0);
    positions[17][0] = Eigen::Vector3d(nan, 0, 0);
    const Box cube = Box::from_parameters(5, 5, 5, 90, 90, 90);
    std::vector<BatchStructure> structures;
    for (const auto& x : positions) {
        structures.push_back(BatchStructure{cube, x});
    }
    NeighborOptions options;
    options.cutoff = 2;
    for (int threads : {1, 2, 4, 20}) {
        SCOPED_TRACE(threads);
        options.threads = threads;
        BatchList batch;
        tricell::compute_neighbors_batch(input.view(), options, batch); // something to clear
        EXPECT_THROW_MSG(tricell::compute_neighbors_batch(structures, options, batch),
                         tricell::InvalidArgument, "structure 13: position 1 is not finite");
        EXPECT_EQ(batch.size(), 0u);
        EXPECT_EQ(batch.structure_count(), 0u);
        EXPECT_TRUE(batch.distances().empty());
    }

    options.cutoff = -1.5;
    BatchList batch;
    EXPECT_THROW_MSG(tricell::compute_neighbors_batch(input.view(), options, batch),
                     tricell::InvalidArgument, "cutoff must be > 0 (got -1.5)");
    options.cutoff = 2;
    EXPECT_THROW_MSG(tricell::compute_neighbors_batch(nullptr, 3, options, batch),
                     tricell::InvalidArgument, "structures: null data for 3 structures");
}

TEST(Batch, MaxPairsBoundsTheWholeBatch) {
    const Box cube = Box::from_parameters(4, 4, 4, 90, 90, 90);
    const std::vector<Eigen::Vector3d> x{{1, 1, 1}, {2, 1, 1}, {1, 2, 1}};
    std::vector<BatchStructure> structures(10, BatchStructure{cube, x});
    NeighborOptions options;
    options.cutoff = 1.5;
    BatchList batch;
    tricell::compute_neighbors_batch(structures, options, batch);
    const std::size_t total = batch.size();
    ASSERT_EQ(total, 10u * 6u); // 0-1, 0-2, 1-2 (sqrt 2) both ways in each structure
    for (int threads : {1, 3}) {
        options.threads = threads;
        options.max_pairs = total;
        tricell::compute_neighbors_batch(structures, options, batch);
        EXPECT_EQ(batch.size(), total);
        options.max_pairs = total - 1;
        EXPECT_THROW_MSG(tricell::compute_neighbors_batch(structures, options, batch),
                         tricell::InvalidArgument,
                         "the batch has too many pairs in total, more than max_pairs = 59");
        EXPECT_EQ(batch.size(), 0u);
    }
}

// Concatenated positions (one N_total x 3 array, as machine-learning codes pass a batch): each
// structure a view into it, global indices asked for. Every structure's slice is its own list
// with i and j moved by its first atom's index, indices into the one array; structures
// overlapping in space (the same coordinates twice) and empty ones never share a pair.
TEST(Batch, GlobalIndicesNumberTheConcatenatedPositions_RandomBatches) {
    BatchList local, global;
    for (int c = 0; c < batch_cases / 2; ++c) {
        const std::uint64_t seed = 9400 + std::uint64_t(c);
        SCOPED_TRACE(seed);
        RandomBatch input = random_batch(seed);
        if (!input.boxes.empty()) { // a copy of a structure at the same place, and an empty one
            input.boxes.push_back(input.boxes.front());
            input.positions.push_back(input.positions.front());
            input.boxes.insert(input.boxes.begin() + 1, input.boxes.back());
            input.positions.insert(input.positions.begin() + 1, std::vector<Eigen::Vector3d>());
        }
        std::vector<Eigen::Vector3d> all;
        std::vector<std::size_t> first{0};
        for (const auto& x : input.positions) {
            all.insert(all.end(), x.begin(), x.end());
            first.push_back(all.size());
        }
        std::vector<BatchStructure> views;
        for (std::size_t s = 0; s < input.boxes.size(); ++s) {
            views.push_back(BatchStructure{
                input.boxes[s], tricell::PointsView(all.empty() ? nullptr : all[first[s]].data(),
                                                    first[s + 1] - first[s])});
        }
        NeighborOptions options;
        options.cutoff = input.cutoff;
        options.half = c % 2 == 1;
        options.sorted = c % 3 == 0;
        options.quantities.vectors = true;
        options.threads = 1 + c % 3;
        tricell::compute_neighbors_batch(views, options, local);
        tricell::compute_neighbors_batch(views, options, global, tricell::BatchIndices::global);
        EXPECT_EQ(local.indices(), tricell::BatchIndices::local);
        ASSERT_EQ(global.indices(), tricell::BatchIndices::global);
        ASSERT_EQ(global.pair_offsets(), local.pair_offsets());
        ASSERT_EQ(global.atom_offsets(), first);
        EXPECT_EQ(global.offsets(), local.offsets());
        EXPECT_TRUE(global.shifts() == local.shifts());
        EXPECT_TRUE(global.distances() == local.distances());
        EXPECT_TRUE(global.vectors() == local.vectors());
        for (std::size_t s = 0; s < views.size(); ++s) {
            for (std::size_t k = global.pair_offsets()[s]; k < global.pair_offsets()[s + 1]; ++k) {
                ASSERT_EQ(global.i()[k], local.i()[k] + first[s]);
                ASSERT_EQ(global.j()[k], local.j()[k] + first[s]);
                ASSERT_LT(global.j()[k], first[s + 1]) << "a pair joining two structures";
                // D from the one array: x_j - x_i + H S.
                const Eigen::Vector3d d =
                    all[global.j()[k]] - all[global.i()[k]] +
                    input.boxes[s].matrix() * global.columns().shift(k).cast<double>();
                const Eigen::Vector3d listed = global.columns().vector(k);
                ASSERT_NEAR((d - listed).norm(), 0.0, 1e-9 * (1 + d.norm()));
            }
        }
    }
}

TEST(Batch, GlobalIndicesRefuseMoreAtomsThanFitThem) {
    // 70000 views of the same 65536 points: 4.6e9 atoms, refused before any is read.
    const std::vector<Eigen::Vector3d> points(65536, Eigen::Vector3d::Zero());
    const Box cube = Box::from_parameters(4, 4, 4, 90, 90, 90);
    const std::vector<BatchStructure> views(70000, BatchStructure{cube, points});
    NeighborOptions options;
    options.cutoff = 1;
    BatchList batch;
    EXPECT_THROW_MSG(
        tricell::compute_neighbors_batch(views, options, batch, tricell::BatchIndices::global),
        tricell::InvalidArgument,
        "global indices number at most 4294967295 atoms, but the batch has 4587520000");
}
