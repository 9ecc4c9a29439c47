// The octree backend's own corner cases (the typed property suite covers the general ones):
// atoms it cannot separate (coincident, or closer than the depth limit resolves), one atom per
// leaf, and what it reports about itself.
#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "support/brute_force.hpp"
#include "tricell/neighbor_list.hpp"

using tricell::Box;
using tricell::NeighborOptions;
using tricell::SearchBackend;
using tricell::testing::PairMap;

namespace {

NeighborOptions octree(double cutoff, std::size_t leaf_size, bool half) {
    NeighborOptions o;
    o.cutoff = cutoff;
    o.backend = SearchBackend::octree;
    o.leaf_size = leaf_size;
    o.half = half;
    o.quantities.vectors = true;
    return o;
}

void expect_brute_force(const Box& box, const std::vector<Eigen::Vector3d>& x, double cutoff,
                        std::size_t leaf_size) {
    const PairMap expected = tricell::testing::brute_force_pairs(box, x, cutoff);
    const PairMap full = tricell::testing::to_map(
        tricell::compute_neighbors(box, x, octree(cutoff, leaf_size, false)));
    const PairMap half = tricell::testing::to_map(
        tricell::compute_neighbors(box, x, octree(cutoff, leaf_size, true)));
    auto same = [](const PairMap& a, const PairMap& b) {
        ASSERT_EQ(a.size(), b.size());
        for (const auto& [key, value] : a) {
            const auto found = b.find(key);
            ASSERT_NE(found, b.end());
            EXPECT_NEAR(found->second.distance, value.distance, 1e-12);
        }
    };
    same(expected, full);
    same(tricell::testing::canonical_half(full), half);
}

} // namespace

TEST(Octree, CoincidentAtomsShareALeaf_LeafSizeOne) {
    for (std::uint64_t seed = 0; seed < 20; ++seed) {
        SCOPED_TRACE(seed);
        std::mt19937_64 rng(seed);
        std::uniform_real_distribution<double> u(0, 6);
        const Box box = Box::from_parameters(6, 7, 6.5, 80, 95, 105);
        std::vector<Eigen::Vector3d> x;
        const Eigen::Vector3d spot(u(rng), u(rng), u(rng));
        for (int k = 0; k < 30; ++k) {
            x.push_back(k % 3 == 0 ? spot : Eigen::Vector3d(u(rng), u(rng), u(rng)));
        }
        expect_brute_force(box, x, 2.5 + double(seed % 4), 1);
    }
}

TEST(Octree, AtomsCloserThanTheDepthLimitResolves_OpenBox) {
    // Gaps halving down to 2^-60: the tree stops splitting at its depth limit and the leaves
    // there hold more than leaf_size atoms; the pairs are still exact.
    const Box box =
        Box::from_columns(Eigen::Matrix3d::Identity() * 3, tricell::Periodicity::none());
    std::vector<Eigen::Vector3d> x;
    for (int k = 0; k < 60; ++k) {
        x.emplace_back(std::ldexp(1.0, -k), 0.5, 0.25 * (k % 2));
    }
    expect_brute_force(box, x, 0.3, 1);
}

TEST(Octree, ReportsItsLeaves) {
    std::mt19937_64 rng(3);
    std::uniform_real_distribution<double> u(0, 20);
    std::vector<Eigen::Vector3d> x(1000);
    for (auto& r : x) {
        r = Eigen::Vector3d(u(rng), u(rng), u(rng));
    }
    const Box box = Box::from_parameters(20, 20, 20, 90, 90, 90);
    for (const std::size_t leaf_size : {1, 4, 16, 64}) {
        tricell::NeighborSearch search;
        search.build(box, x, octree(3, leaf_size, false));
        const tricell::SearchInfo info = search.info();
        EXPECT_EQ(info.backend, SearchBackend::octree);
        EXPECT_EQ(info.work_units, info.stored_cells);
        EXPECT_GE(info.stored_cells, (x.size() + leaf_size - 1) / leaf_size);
        EXPECT_LE(info.stored_cells, x.size());
    }
}
