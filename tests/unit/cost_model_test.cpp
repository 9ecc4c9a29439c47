// The cost model's formulas (lib/policy/cost_model.hpp), each against its definition.
#include <cmath>
#include <limits>
#include <numeric>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "policy/cost_model.hpp"

namespace {

using tricell::SearchBackend;

TEST(CostModel, RegionWorkOfOneCellIsItsOccupancyWork) {
    const tricell::OccupancyCosts costs{3, 5, 2};
    for (const double n : {0.0, 1.0, 4.0, 17.0}) {
        tricell::OccupancyMoments m;
        m.add(n);
        EXPECT_DOUBLE_EQ(tricell::region_work(m, 27, costs), tricell::occupancy_work(n, 27, costs))
            << n;
    }
}

TEST(CostModel, RegionWorkGrowsWithTheSecondMomentAtTheSameAtoms) {
    // The same 8 atoms in 4 cells: clustered costs more than spread evenly (E[n^2] grows).
    tricell::OccupancyMoments even, clustered;
    for (const double n : {2.0, 2.0, 2.0, 2.0}) {
        even.add(n);
    }
    for (const double n : {8.0, 0.0, 0.0, 0.0}) {
        clustered.add(n);
    }
    EXPECT_EQ(even.atoms, clustered.atoms);
    EXPECT_DOUBLE_EQ(even.mean_sq(), 4.0);
    EXPECT_DOUBLE_EQ(clustered.mean_sq(), 16.0);
    EXPECT_GT(tricell::region_work(clustered, 27), tricell::region_work(even, 27));
}

TEST(CostModel, ExpectedPairsIsTheDensityOverTheSphere) {
    EXPECT_DOUBLE_EQ(tricell::expected_pairs(10, 100, 4), 10.0 * 10.0 / 100.0 * 4.0);
    EXPECT_EQ(tricell::expected_pairs(0, 100, 4), 0);
    EXPECT_EQ(tricell::expected_pairs(10, 0, 4), 0);
    EXPECT_EQ(tricell::expected_pairs(10, std::nan(""), 4), 0);
}

TEST(CostModel, SplitWorkCoversEveryUnitInOrderWithBalancedChunks) {
    std::mt19937 rng(7);
    for (int trial = 0; trial < 200; ++trial) {
        SCOPED_TRACE(trial);
        std::vector<double> work(1 + rng() % 300);
        for (double& w : work) {
            w = double(rng() % 100);
        }
        const std::size_t parts = 1 + rng() % 16;
        const std::vector<std::size_t> bounds = tricell::split_work(work, parts);
        ASSERT_GE(bounds.size(), 2u);
        EXPECT_EQ(bounds.front(), 0u);
        EXPECT_EQ(bounds.back(), work.size());
        EXPECT_LE(bounds.size() - 1, parts);
        const double total = std::accumulate(work.begin(), work.end(), 0.0);
        const double largest = *std::max_element(work.begin(), work.end());
        for (std::size_t c = 0; c + 1 < bounds.size(); ++c) {
            ASSERT_LT(bounds[c], bounds[c + 1]);
            const double chunk = std::accumulate(work.begin() + std::ptrdiff_t(bounds[c]),
                                                 work.begin() + std::ptrdiff_t(bounds[c + 1]), 0.0);
            // A chunk closes at the first unit that reaches its share: at most a share plus the
            // largest unit.
            EXPECT_LE(chunk, total / double(parts) + largest + 1e-9);
        }
    }
}

TEST(CostModel, DirectForFewAtomsInCellsNarrowerThanTheCutoff) {
    const double inf = std::numeric_limits<double>::infinity();
    EXPECT_TRUE(tricell::choose_direct(12, inf, 1));
    EXPECT_FALSE(tricell::choose_direct(13, inf, 1));
    EXPECT_TRUE(tricell::choose_direct(12, 1.9, 1));  // past half the width
    EXPECT_FALSE(tricell::choose_direct(12, 2.1, 1)); // not even half
    EXPECT_TRUE(tricell::choose_direct(32, 0.9, 1));  // past the whole width
    EXPECT_FALSE(tricell::choose_direct(32, 1.1, 1));
    EXPECT_FALSE(tricell::choose_direct(33, 0.1, 1));
}

TEST(CostModel, DenseGridWhileTheCellsFitTheCap) {
    EXPECT_EQ(tricell::choose_grid_backend(100, 100), SearchBackend::dense);
    EXPECT_EQ(tricell::choose_grid_backend(101, 100), SearchBackend::hash);
}

TEST(CostModel, GridAlwaysCheaperMatchesAScanOfTheCostsPerAtom) {
    for (const SearchBackend grid : {SearchBackend::dense, SearchBackend::hash}) {
        for (const double cutoff : {1.0, 5.0}) {
            bool cheaper = true;
            for (double x = 1e-6; x <= 16; x *= 1.1) {
                const double rho = x / (cutoff * cutoff * cutoff);
                cheaper = cheaper && tricell::grid_cost_per_atom(grid, rho, cutoff) <
                                         tricell::octree_cost_per_atom(rho, cutoff);
            }
            EXPECT_EQ(tricell::grid_always_cheaper(grid, cutoff), cheaper)
                << tricell::backend_name(grid) << " rc " << cutoff;
        }
    }
}

TEST(CostModel, OctreeCrossoverIsAVolumeFraction) {
    // Octree costs that win at low density and lose at high density give 0 < f* < 1; f* is the
    // fraction where both totals are equal.
    tricell::OctreeCosts costs;
    costs.octree[0] = 100;
    const double rc = 5, rho_hi = 0.05, rho_lo = 1e-5;
    const double f = tricell::octree_crossover(SearchBackend::hash, rho_hi, rho_lo, rc, costs);
    ASSERT_GT(f, 0);
    ASSERT_LT(f, 1);
    auto total = [&](bool octree) {
        auto u = [&](double rho) {
            return octree ? tricell::octree_cost_per_atom(rho, rc, costs)
                          : tricell::grid_cost_per_atom(SearchBackend::hash, rho, rc, costs);
        };
        return f * rho_hi * u(rho_hi) + (1 - f) * rho_lo * u(rho_lo);
    };
    EXPECT_NEAR(total(true), total(false), 1e-9 * total(false));
}

TEST(CostModel, StencilCellsOfTheIdealisedGrid) {
    EXPECT_EQ(tricell::stencil_cells(1), 27u);
    EXPECT_EQ(tricell::stencil_cells(2), 125u);
    EXPECT_EQ(tricell::octree_leaf_size(), 16u);
}

} // namespace
