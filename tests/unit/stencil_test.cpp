#include <random>
#include <set>

#include <gtest/gtest.h>

#include "support/random_boxes.hpp"
#include "tricell/stencil.hpp"

using tricell::Box;
using tricell::CellGrid;
using tricell::CellOffset;
using tricell::Stencil;

namespace {
CellGrid grid_for(const Box& box, double radius, double k) {
    tricell::GridOptions o;
    o.search_radius = radius;
    o.cells_per_cutoff = k;
    o.max_cells = 1 << 20;
    return CellGrid(box, o, Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero());
}
} // namespace

TEST(Stencil, CubicUnitReachKeepsAll27AndHalfHas14) {
    const Box box = Box::from_parameters(9, 9, 9, 90, 90, 90);
    const CellGrid grid = grid_for(box, 3.0, 1);
    EXPECT_EQ(Stencil::full(grid, box, 3.0).size(), 27u);
    const Stencil half = Stencil::half(grid, box, 3.0);
    EXPECT_EQ(half.size(), 14u); // own cell + 13
    EXPECT_EQ(half.offsets().front(), (CellOffset{{0, 0, 0}}));
}

TEST(Stencil, PrunesCornersByRealClosestApproach) {
    // Three cells per cutoff (h = 2, cutoff 6): reach 3, 343 offsets. Offset (3, 3, 3) leaves a
    // gap of 2 cells along each axis, 4 sqrt(3) > 6, and is pruned; (3, 3, 2) leaves exactly
    // sqrt(16 + 16 + 4) = 6, not below the cutoff, and is pruned too; (3, 2, 2) is kept.
    const Box box = Box::from_parameters(30, 30, 30, 90, 90, 90);
    const CellGrid grid = grid_for(box, 6.0, 3);
    ASSERT_EQ(grid.reach()[0], 3);
    const Stencil full = Stencil::full(grid, box, 6.0);
    EXPECT_LT(full.size(), 343u);
    const std::set<CellOffset> kept(full.offsets().begin(), full.offsets().end());
    EXPECT_EQ(kept.count(CellOffset{{3, 3, 3}}), 0u);
    EXPECT_EQ(kept.count(CellOffset{{-3, 3, 2}}), 0u);
    EXPECT_EQ(kept.count(CellOffset{{3, 0, 0}}), 1u);
    EXPECT_EQ(kept.count(CellOffset{{3, -2, 2}}), 1u);
}

TEST(Stencil, HalfIsExactlyOneOfEachOppositePair) {
    std::mt19937_64 rng(5);
    for (int trial = 0; trial < 50; ++trial) {
        SCOPED_TRACE(trial);
        const Box box = Box::from_columns(tricell::testing::random_box_matrix(rng, 3, 12, 1.5));
        const double radius = 2.0 + trial * 0.1;
        const CellGrid grid = grid_for(box, radius, 1 + trial % 3);
        const Stencil full = Stencil::full(grid, box, radius);
        const Stencil half = Stencil::half(grid, box, radius);
        const std::set<CellOffset> f(full.offsets().begin(), full.offsets().end());
        std::set<CellOffset> reconstructed;
        for (const CellOffset& d : half.offsets()) {
            reconstructed.insert(d);
            reconstructed.insert(CellOffset{{-d[0], -d[1], -d[2]}});
        }
        EXPECT_EQ(reconstructed, f);
        EXPECT_EQ(half.size(), (full.size() + 1) / 2);
        for (const CellOffset& d : full.offsets()) {
            EXPECT_EQ(f.count(CellOffset{{-d[0], -d[1], -d[2]}}), 1u) << "pruning not symmetric";
        }
    }
}

TEST(ClosestApproach, MatchesDenseSamplingOfTheBox) {
    std::mt19937_64 rng(11);
    std::uniform_real_distribution<double> u(-2, 2), extent(0, 1.5);
    for (int trial = 0; trial < 600; ++trial) {
        SCOPED_TRACE(trial);
        const Eigen::Matrix3d h = tricell::testing::random_box_matrix(rng, 1, 3, 2);
        Eigen::Vector3d lower(u(rng), u(rng), u(rng));
        // Fixed extents first, then random ones, flat along an axis one time in ten.
        Eigen::Vector3d size(0.5, 0.7, 0.3);
        if (trial >= 200) {
            size = Eigen::Vector3d(extent(rng), extent(rng), extent(rng));
            if (trial % 10 == 0) {
                size[trial % 3] = 0;
            }
        }
        const Eigen::Vector3d upper = lower + size;
        const double exact = tricell::closest_approach_sq(h, lower, upper);
        double sampled = 1e300;
        const int steps = 24;
        for (int a = 0; a <= steps; ++a) {
            for (int b = 0; b <= steps; ++b) {
                for (int c = 0; c <= steps; ++c) {
                    const Eigen::Vector3d t(double(a) / steps, double(b) / steps,
                                            double(c) / steps);
                    const Eigen::Vector3d p = lower.array() + t.array() * (upper - lower).array();
                    sampled = std::min(sampled, (h * p).squaredNorm());
                }
            }
        }
        EXPECT_LE(exact, sampled + 1e-12);      // never above any point of the box
        EXPECT_GE(exact, sampled * 0.9 - 0.05); // and close to the sampled minimum
    }
}

TEST(ClosestApproach, BoxWithinRadiusAgreesWithTheExactDistance) {
    std::mt19937_64 rng(12);
    std::uniform_real_distribution<double> u(-3, 3), extent(0, 1.5), radius(0.1, 6);
    int near = 0, far = 0;
    for (int trial = 0; trial < 5000; ++trial) {
        SCOPED_TRACE(trial);
        const Eigen::Matrix3d h = tricell::testing::random_box_matrix(rng, 1, 3, 2);
        const Eigen::Matrix3d gram = h.transpose() * h;
        const Eigen::Vector3d edges = h.colwise().norm().transpose();
        const Eigen::Vector3d lower(u(rng), u(rng), u(rng));
        const Eigen::Vector3d upper =
            lower + Eigen::Vector3d(extent(rng), extent(rng), extent(rng));
        const double r = radius(rng);
        const double exact = std::sqrt(tricell::closest_approach_sq(h, gram, lower, upper));
        if (std::abs(exact - r) < 1e-9 * r) {
            continue; // on the boundary either answer is within rounding
        }
        const bool within = tricell::box_within_radius(h, gram, edges, lower, upper, r);
        EXPECT_EQ(within, exact < r) << "closest approach " << exact << ", radius " << r;
        (within ? near : far) += 1;
    }
    EXPECT_GT(near, 500); // both answers are exercised
    EXPECT_GT(far, 500);
}

TEST(Stencil, CheapPruningKeepsASupersetOfExactPruning) {
    std::mt19937_64 rng(9);
    for (int trial = 0; trial < 30; ++trial) {
        SCOPED_TRACE(trial);
        const Box box = Box::from_columns(tricell::testing::random_box_matrix(rng, 1, 4, 1.0));
        const double radius = 3.0 + trial * 0.2;
        const CellGrid grid = grid_for(box, radius, 1);
        const Stencil exact = Stencil::full(grid, box, radius, true);
        const Stencil cheap = Stencil::full(grid, box, radius, false);
        const std::set<CellOffset> e(exact.offsets().begin(), exact.offsets().end());
        const std::set<CellOffset> c(cheap.offsets().begin(), cheap.offsets().end());
        for (const CellOffset& d : e) {
            EXPECT_EQ(c.count(d), 1u);
        }
        EXPECT_GE(c.size(), e.size());
    }
}
