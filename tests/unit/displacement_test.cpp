// Tests of tricell::DisplacementTracker on its own (VerletList's tests cover it through the
// list): the state before a record, the jumps since the record for atoms wrapped or moved by
// lattice vectors in skewed boxes, the threshold of the rule with a per-pair cutoff and a
// strained box, and a changed atom count or periodicity.
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "support/expect_throw_msg.hpp"
#include "support/random_boxes.hpp"
#include "tricell/displacement.hpp"
#include "tricell/error.hpp"

using tricell::Box;
using tricell::DisplacementTracker;
using tricell::InvalidArgument;
using tricell::Periodicity;

namespace {

std::vector<Eigen::Vector3d> random_points(std::mt19937_64& rng, const Box& box, std::size_t n) {
    std::uniform_real_distribution<double> frac(-3.0, 4.0); // some atoms cells away
    std::vector<Eigen::Vector3d> x(n);
    for (auto& r : x) {
        r = box.matrix() * Eigen::Vector3d(frac(rng), frac(rng), frac(rng));
    }
    return x;
}

TEST(DisplacementTracker, NothingRecorded) {
    const DisplacementTracker tracker;
    const Box box = Box::from_parameters(5, 5, 5, 90, 90, 90);
    const std::vector<Eigen::Vector3d> x(3, Eigen::Vector3d(1, 2, 3));
    EXPECT_FALSE(tracker.recorded());
    EXPECT_TRUE(tracker.needs_rebuild(box, x, 1.0, 2.0));
    EXPECT_LT(tracker.budget(box, 1.0, 2.0), 0);
    EXPECT_TRUE(std::isinf(tracker.max_displacement(box, x)));
    std::vector<std::int32_t> jumps(9);
    EXPECT_FALSE(tracker.jumps_since_record(box, x, 1.0, 2.0, jumps.data()));
}

// Atoms moved by random lattice vectors k plus a small displacement: the jumps are k, and a
// recorded pair (i, j, S) is the current pair (i, j, S + k_j - k_i).
TEST(DisplacementTracker, JumpsSinceTheRecordInSkewedBoxes) {
    for (std::uint64_t seed = 1; seed <= 20; ++seed) {
        SCOPED_TRACE(seed);
        std::mt19937_64 rng(seed);
        const Box box = Box::from_columns(tricell::testing::random_box_matrix(rng, 4, 7, 2.0));
        const auto x0 = random_points(rng, box, 30);
        DisplacementTracker tracker;
        tracker.record(box, x0);
        const double skin = 0.4, cutoff = 3.0;
        ASSERT_DOUBLE_EQ(tracker.budget(box, skin, cutoff), skin / 2);
        std::uniform_int_distribution<int> lattice(-5, 5);
        std::normal_distribution<double> small(0, 0.03);
        std::vector<Eigen::Vector3d> x = x0;
        std::vector<Eigen::Vector3i> k(x.size());
        for (std::size_t i = 0; i < x.size(); ++i) {
            k[i] = Eigen::Vector3i(lattice(rng), lattice(rng), lattice(rng));
            x[i] += box.matrix() * k[i].cast<double>() +
                    Eigen::Vector3d(small(rng), small(rng), small(rng)).normalized() * 0.1;
        }
        EXPECT_NEAR(tracker.max_displacement(box, x), 0.1, 1e-9);
        EXPECT_FALSE(tracker.needs_rebuild(box, x, skin, cutoff));
        std::vector<std::int32_t> jumps(3 * x.size());
        ASSERT_TRUE(tracker.jumps_since_record(box, x, skin, cutoff, jumps.data()));
        for (std::size_t i = 0; i < x.size(); ++i) {
            // The atom is back where it was recorded, up to its small move: x - H k = x0 + d.
            const Eigen::Vector3i got(jumps[3 * i], jumps[3 * i + 1], jumps[3 * i + 2]);
            EXPECT_EQ(got, -k[i]) << "atom " << i;
        }
        const Eigen::Vector3i s(1, -2, 0);
        const Eigen::Vector3d recorded = x0[4] + box.matrix() * s.cast<double>() - x0[3];
        const Eigen::Vector3i now_s = s + Eigen::Vector3i(&jumps[12]) - Eigen::Vector3i(&jumps[9]);
        const Eigen::Vector3d now = x[4] + box.matrix() * now_s.cast<double>() - x[3];
        EXPECT_LE((now - recorded).norm(), 0.2 + 1e-9);
    }
}

// The rule with a cutoff per pair: skin is every pair's margin, cutoff the largest pair
// cutoff, and a compressed box spends eps * cutoff of the skin.
TEST(DisplacementTracker, ThresholdWithAStrainedBox) {
    std::mt19937_64 rng(7);
    const Eigen::Matrix3d h0 = tricell::testing::random_box_matrix(rng, 6, 8, 0.5);
    const Box box0 = Box::from_columns(h0);
    const auto x0 = random_points(rng, box0, 20);
    DisplacementTracker tracker;
    tracker.record(box0, x0);
    const double skin = 0.6, cutoff = 4.0, f = 0.02;
    const Box box = Box::from_columns(h0 / (1 + f));
    std::vector<Eigen::Vector3d> x;
    for (const auto& r : x0) {
        x.push_back(r / (1 + f));
    }
    const double budget = 0.5 * (skin - f * cutoff);
    EXPECT_NEAR(tracker.budget(box, skin, cutoff), budget, 1e-12);
    // Displacements count in the build frame: a move d in the compressed box is (1 + f) d.
    const Eigen::Vector3d dir = Eigen::Vector3d(1, 2, -2).normalized() / (1 + f);
    x[5] += 0.999 * budget * dir;
    EXPECT_NEAR(tracker.max_displacement(box, x), 0.999 * budget, 1e-12);
    EXPECT_FALSE(tracker.needs_rebuild(box, x, skin, cutoff));
    x[5] += 0.002 * budget * dir;
    EXPECT_TRUE(tracker.needs_rebuild(box, x, skin, cutoff));
    std::vector<std::int32_t> jumps(3 * x.size());
    EXPECT_FALSE(tracker.jumps_since_record(box, x, skin, cutoff, jumps.data()));
    // Expansion costs nothing.
    EXPECT_DOUBLE_EQ(tracker.budget(Box::from_columns(h0 * 1.1), skin, cutoff), skin / 2);
}

TEST(DisplacementTracker, CountPeriodicityAndBadPositions) {
    const Box box = Box::from_parameters(6, 6, 6, 90, 90, 90);
    std::vector<Eigen::Vector3d> x{{1, 1, 1}, {2, 2, 2}};
    DisplacementTracker tracker;
    tracker.record(box, x);
    EXPECT_TRUE(tracker.recorded());
    EXPECT_EQ(tracker.atom_count(), 2u);
    const Box slab = Box::from_parameters(6, 6, 6, 90, 90, 90, Periodicity{{true, true, false}});
    EXPECT_TRUE(tracker.needs_rebuild(slab, x, 1.0, 1.0));
    EXPECT_LT(tracker.budget(slab, 1.0, 1.0), 0);
    x.emplace_back(3, 3, 3);
    EXPECT_TRUE(tracker.needs_rebuild(box, x, 1.0, 1.0));
    x[2].y() = std::numeric_limits<double>::quiet_NaN();
    EXPECT_THROW_MSG(tracker.needs_rebuild(box, x, 1.0, 1.0), InvalidArgument,
                     "position 2 is not finite");
    EXPECT_THROW_MSG(tracker.record(box, x), InvalidArgument, "position 2 is not finite");
    EXPECT_FALSE(tracker.recorded());
    tracker.record(box, std::vector<Eigen::Vector3d>{{1, 1, 1}});
    tracker.reset();
    EXPECT_FALSE(tracker.recorded());
}

} // namespace
