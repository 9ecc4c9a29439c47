// nearest_neighbors against a brute force over every image (random triclinic systems with every
// mix of periodic axes, k beyond N, atoms far outside the box, coincident atoms), exact ties of
// perfect crystals broken by (j, S), the same result for every backend and thread count, and the
// refusals.
#include <cmath>
#include <random>
#include <set>

#include <gtest/gtest.h>

#include <tricell/analysis/nearest.hpp>
#include <tricell/error.hpp>

#include "support/analysis_oracles.hpp"
#include "support/expect_throw_msg.hpp"
#include "support/random_systems.hpp"

namespace {

using tricell::Box;
using tricell::InvalidArgument;
using tricell::nearest_neighbors;
using tricell::NearestNeighbors;
using tricell::Periodicity;
using tricell::testing::brute_force_candidates;

#ifndef TRICELL_PROPERTY_CASES
#define TRICELL_PROPERTY_CASES 400
#endif

// The result is the k nearest: every entry is a real candidate with the brute-force distance,
// the order is (d, j, S) on the library's distances, nothing repeats, and every candidate
// clearly closer than the k-th is present. Where no two brute-force distances are within
// rounding of each other, the entries are exactly the brute force's first k.
void expect_k_nearest(const Box& box, const std::vector<Eigen::Vector3d>& x, std::size_t k,
                      const NearestNeighbors& got) {
    ASSERT_EQ(got.k, k);
    ASSERT_EQ(got.j.size(), x.size() * k);
    ASSERT_EQ(got.shifts.size(), 3 * x.size() * k);
    ASSERT_EQ(got.distances.size(), x.size() * k);
    double scale = 1;
    for (const auto& p : x) {
        scale = std::max(scale, p.cwiseAbs().maxCoeff());
    }
    const double tol = 1e-10 * scale;
    const auto all = brute_force_candidates(box, x, k, 1.0);
    for (std::size_t i = 0; i < x.size(); ++i) {
        SCOPED_TRACE(i);
        std::map<std::tuple<std::uint32_t, int, int, int>, double> oracle;
        for (const auto& c : all[i]) {
            oracle[{c.j, c.s[0], c.s[1], c.s[2]}] = c.d;
        }
        std::set<std::tuple<std::uint32_t, int, int, int>> seen;
        for (std::size_t e = 0; e < k; ++e) {
            const std::size_t at = i * k + e;
            const tricell::Shift s = got.shift(at);
            const auto key = std::make_tuple(got.j[at], s[0], s[1], s[2]);
            EXPECT_TRUE(seen.insert(key).second) << "entry " << e << " repeats";
            const auto found = oracle.find(key);
            if (found == oracle.end()) {
                // Beyond the oracle's radius: recompute.
                const Eigen::Vector3d d = x[got.j[at]] - x[i] + box.matrix() * s.cast<double>();
                EXPECT_NEAR(got.distances[at], d.norm(), tol) << "entry " << e;
            } else {
                EXPECT_NEAR(got.distances[at], found->second, tol) << "entry " << e;
            }
            if (e > 0) {
                const std::size_t prev = at - 1;
                const auto l =
                    std::make_tuple(got.distances[prev], got.j[prev], got.shifts[3 * prev],
                                    got.shifts[3 * prev + 1], got.shifts[3 * prev + 2]);
                const auto r = std::make_tuple(got.distances[at], got.j[at], s[0], s[1], s[2]);
                EXPECT_LT(l, r) << "entries " << e - 1 << " and " << e << " out of order";
            }
        }
        const double kth = got.distances[i * k + k - 1];
        bool separated = true;
        for (std::size_t e = 0; e < all[i].size(); ++e) {
            const auto& c = all[i][e];
            if (c.d < kth - tol) {
                EXPECT_TRUE(seen.count({c.j, c.s[0], c.s[1], c.s[2]}))
                    << "candidate " << c.j << " at " << c.d << " is missing";
            }
            if (e > 0 && e <= k && all[i][e].d - all[i][e - 1].d < tol) {
                separated = false;
            }
        }
        if (separated) {
            for (std::size_t e = 0; e < k; ++e) {
                EXPECT_EQ(got.j[i * k + e], all[i][e].j) << "entry " << e;
            }
        }
    }
}

TEST(NearestNeighbors, MatchesBruteForce_RandomSystems) {
    for (std::uint64_t seed = 1; seed <= TRICELL_PROPERTY_CASES / 4; ++seed) {
        SCOPED_TRACE(seed);
        tricell::testing::RandomSystem sys = tricell::testing::random_system(seed);
        if (sys.positions.size() > 80) {
            sys.positions.resize(80); // the oracle is quadratic
        }
        std::mt19937_64 rng(seed);
        const std::size_t n = sys.positions.size();
        const Box box = sys.box();
        std::size_t k = 1 + rng() % 12;
        if (!sys.pbc.any()) {
            if (n < 2) {
                continue;
            }
            k = 1 + rng() % (n - 1);
        } else if (n > 0 && rng() % 3 == 0) {
            k = n + 1 + rng() % (2 * n + 3); // more than N: images
        }
        SCOPED_TRACE(sys.kind + ", k " + std::to_string(k) + ", N " + std::to_string(n));
        const NearestNeighbors got = nearest_neighbors(box, sys.positions, k);
        expect_k_nearest(box, sys.positions, k, got);
    }
}

TEST(NearestNeighbors, TiesOfAPerfectCrystalBreakByJThenShift) {
    // Simple cubic, one atom per cell, 2 x 2 x 2 supercell: 6 neighbours at distance 1, each of
    // the 3 other atoms along an axis twice (S and its opposite), in (j, S) order.
    std::vector<Eigen::Vector3d> x;
    for (int a = 0; a < 2; ++a) {
        for (int b = 0; b < 2; ++b) {
            for (int c = 0; c < 2; ++c) {
                x.emplace_back(a, b, c);
            }
        }
    }
    const Box box = Box::from_columns(2 * Eigen::Matrix3d::Identity());
    const NearestNeighbors got = nearest_neighbors(box, x, 6);
    // Atom 0 at the origin: j = 1 (0,0,1) at S = (0,0,-1) and (0,0,0); j = 2 (0,1,0); j = 4.
    const std::vector<std::uint32_t> j = {1, 1, 2, 2, 4, 4};
    const std::vector<std::int32_t> s = {0, 0, -1, 0, 0, 0, 0, -1, 0, 0, 0, 0, -1, 0, 0, 0, 0, 0};
    EXPECT_EQ(std::vector<std::uint32_t>(got.j.begin(), got.j.begin() + 6), j);
    EXPECT_EQ(std::vector<std::int32_t>(got.shifts.begin(), got.shifts.begin() + 18), s);
    for (std::size_t e = 0; e < 6 * x.size(); ++e) {
        EXPECT_EQ(got.distances[e], 1.0);
    }
    // One atom, k = 26 > N: its own images, 6 + 12 + 8 of them, sorted by d then S.
    const std::vector<Eigen::Vector3d> one = {{0.25, 0.25, 0.25}};
    const NearestNeighbors images =
        nearest_neighbors(Box::from_columns(Eigen::Matrix3d::Identity()), one, 26);
    EXPECT_EQ(images.shift(0), tricell::Shift(-1, 0, 0));
    EXPECT_EQ(images.shift(5), tricell::Shift(1, 0, 0));
    EXPECT_EQ(images.shift(25), tricell::Shift(1, 1, 1));
    EXPECT_EQ(images.distances[6], std::sqrt(2.0));
}

TEST(NearestNeighbors, SameResultWithEveryBackendAndThreads) {
    for (std::uint64_t seed = 500; seed < 540; ++seed) {
        SCOPED_TRACE(seed);
        const tricell::testing::RandomSystem sys = tricell::testing::random_system(seed);
        const std::size_t n = sys.positions.size();
        if (!sys.pbc.any() && n < 6) {
            continue;
        }
        const std::size_t k = sys.pbc.any() ? 7 : 5;
        const NearestNeighbors reference = nearest_neighbors(sys.box(), sys.positions, k);
        for (const auto backend : tricell::search_backends()) {
            for (const int threads : {1, 2}) {
                const NearestNeighbors got =
                    nearest_neighbors(sys.box(), sys.positions, k, {threads, backend});
                EXPECT_EQ(got.j, reference.j) << tricell::backend_name(backend);
                EXPECT_EQ(got.shifts, reference.shifts);
                EXPECT_EQ(got.distances, reference.distances);
            }
        }
    }
}

TEST(NearestNeighbors, ClusteredAtomsInAHugeOpenBox) {
    // Two tight clusters far apart in a box whose volume says nothing about the density: the
    // radius grows from a poor estimate until every atom has k.
    std::mt19937_64 rng(7);
    std::uniform_real_distribution<double> u(0, 1);
    std::vector<Eigen::Vector3d> x;
    for (int i = 0; i < 60; ++i) {
        x.emplace_back(u(rng), u(rng), u(rng));
        x.emplace_back(500 + u(rng), 800 + u(rng), 300 + u(rng));
    }
    const Box box = Box::from_columns(1000 * Eigen::Matrix3d::Identity(), Periodicity::none());
    for (const std::size_t k : {1, 5, 59, 60, 119}) {
        SCOPED_TRACE(k);
        expect_k_nearest(box, x, k, nearest_neighbors(box, x, k));
    }
}

TEST(NearestNeighbors, Refusals) {
    const std::vector<Eigen::Vector3d> x = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    const Box open = Box::from_columns(3 * Eigen::Matrix3d::Identity(), Periodicity::none());
    EXPECT_THROW_MSG(nearest_neighbors(open, x, 0), InvalidArgument,
                     "nearest_neighbors: k must be >= 1 (got 0)");
    EXPECT_THROW_MSG(nearest_neighbors(open, x, 3), InvalidArgument,
                     "k = 3 neighbours per atom need at least k + 1 atoms in a system open "
                     "along every axis (got N = 3)");
    EXPECT_EQ(nearest_neighbors(open, x, 2).j.size(), 6u);
    const Box slab =
        Box::from_columns(3 * Eigen::Matrix3d::Identity(), Periodicity{{{true, false, false}}});
    EXPECT_EQ(nearest_neighbors(slab, x, 10).j.size(), 30u); // images along a
    const NearestNeighbors none = nearest_neighbors(open, std::vector<Eigen::Vector3d>{}, 4);
    EXPECT_EQ(none.k, 4u);
    EXPECT_TRUE(none.j.empty());
    const std::vector<Eigen::Vector3d> bad = {{0, 0, 0}, {1, std::nan(""), 0}};
    EXPECT_THROW_MSG(nearest_neighbors(Box::from_columns(Eigen::Matrix3d::Identity()), bad, 2),
                     InvalidArgument, "position 1 is not finite");
}

} // namespace
