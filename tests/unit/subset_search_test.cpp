// Pairs of a subset (NeighborOptions::query): on random systems, every backend, full and half,
// one and several threads, uniform and per-atom cutoffs, against the brute-force oracle
// restricted to the query and against the same backend's full search restricted to it (d and D
// bit for bit); a query of every point gives the ordinary list bit for bit; the distance tests
// are those of the query's pairs.
#include <algorithm>
#include <cstdint>
#include <cstring>
#include <numeric>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "support/brute_force.hpp"
#include "support/expect_throw_msg.hpp"
#include "support/random_systems.hpp"
#include "tricell/error.hpp"
#include "tricell/neighbor_list.hpp"

#ifndef TRICELL_PROPERTY_CASES
#define TRICELL_PROPERTY_CASES 400
#endif

using tricell::NeighborList;
using tricell::NeighborOptions;
using tricell::SearchBackend;
using namespace tricell::testing;

namespace {

// What a subset list must hold, from the full list `full` (as a map) and the query flags: full,
// the pairs with i in the query; half, those with j outside it or in the canonical orientation.
PairMap restricted(const PairMap& full, const std::vector<bool>& in_query, bool half) {
    PairMap out;
    const PairMap canonical = canonical_half(full);
    for (const auto& [key, value] : full) {
        const auto i = std::get<0>(key);
        const auto j = std::get<1>(key);
        if (in_query[i] && (!half || !in_query[j] || canonical.count(key) != 0)) {
            out.emplace(key, value);
        }
    }
    return out;
}

bool same_bits(double a, double b) {
    return std::memcmp(&a, &b, sizeof a) == 0;
}

} // namespace

TEST(SubsetSearch, RandomSystemsEveryBackendAgainstOracleAndRestrictedFullSearch) {
    for (std::uint64_t seed = 1; seed <= TRICELL_PROPERTY_CASES / 4; ++seed) {
        SCOPED_TRACE(seed);
        const RandomSystem sys = random_system(seed);
        const tricell::Box box = sys.box();
        const std::size_t n = sys.positions.size();
        std::mt19937_64 rng(seed * 7919);
        // A random query in random order: sometimes empty or every point.
        std::vector<std::uint32_t> all(n);
        std::iota(all.begin(), all.end(), 0u);
        std::shuffle(all.begin(), all.end(), rng);
        const int pick = int(seed % 8);
        const std::size_t count = pick == 0 ? 0 : pick == 1 ? n : std::size_t(rng() % (n + 1));
        std::vector<std::uint32_t> query(all.begin(), all.begin() + std::ptrdiff_t(count));
        std::vector<bool> in_query(n, false);
        for (std::uint32_t q : query) {
            in_query[q] = true;
        }
        std::vector<double> radii;
        PairMap oracle;
        if (seed % 5 == 4) { // per-atom radii
            std::uniform_real_distribution<double> r(0, sys.cutoff / 2);
            for (std::size_t k = 0; k < n; ++k) {
                radii.push_back(r(rng));
            }
            oracle = brute_force_pairs(box, sys.positions, sys.cutoff,
                                       [&](auto i, auto j) { return radii[i] + radii[j]; });
        } else {
            oracle = brute_force_pairs(box, sys.positions, sys.cutoff);
        }
        for (SearchBackend backend : tricell::search_backends()) {
            for (bool half : {false, true}) {
                SCOPED_TRACE(std::string(tricell::backend_name(backend)) +
                             (half ? " half" : " full"));
                NeighborOptions o;
                o.cutoff = radii.empty() ? sys.cutoff : 0;
                o.radii = radii;
                o.backend = backend;
                o.quantities.vectors = true;
                o.threads = seed % 3 == 0 ? 3 : 1;
                NeighborList whole;
                o.half = false;
                tricell::compute_neighbors(box, sys.positions, o, whole);
                o.half = half;
                o.query = query;
                NeighborList subset;
                tricell::compute_neighbors(box, sys.positions, o, subset);
                const PairMap got = to_map(subset);
                ASSERT_EQ(got.size(), subset.size()) << "a pair listed twice";
                const PairMap expected = restricted(oracle, in_query, half);
                ASSERT_EQ(got.size(), expected.size());
                const PairMap from_full = restricted(to_map(whole), in_query, half);
                ASSERT_EQ(from_full.size(), expected.size());
                for (const auto& [key, value] : got) {
                    const auto e = expected.find(key);
                    ASSERT_NE(e, expected.end()) << "a pair the oracle does not have";
                    EXPECT_NEAR(value.distance, e->second.distance, 1e-9 * (1 + value.distance));
                    const auto f = from_full.find(key);
                    ASSERT_NE(f, from_full.end());
                    EXPECT_TRUE(same_bits(value.distance, f->second.distance));
                    for (int c = 0; c < 3; ++c) {
                        EXPECT_TRUE(same_bits(value.vector[c], f->second.vector[c]));
                    }
                }
            }
        }
    }
}

TEST(SubsetSearch, QueryOfEveryPointIsTheOrdinaryListBitForBit) {
    for (std::uint64_t seed = 1; seed <= 12; ++seed) {
        SCOPED_TRACE(seed);
        const RandomSystem sys = random_system(seed);
        for (bool half : {false, true}) {
            NeighborOptions o;
            o.cutoff = sys.cutoff;
            o.half = half;
            o.quantities.vectors = true;
            const NeighborList plain = tricell::compute_neighbors(sys.box(), sys.positions, o);
            std::vector<std::uint32_t> every(sys.positions.size());
            std::iota(every.rbegin(), every.rend(), 0u); // any order
            o.query = every;
            const NeighborList query = tricell::compute_neighbors(sys.box(), sys.positions, o);
            ASSERT_EQ(plain.size(), query.size());
            EXPECT_TRUE(std::equal(plain.i().begin(), plain.i().end(), query.i().begin()));
            EXPECT_TRUE(std::equal(plain.j().begin(), plain.j().end(), query.j().begin()));
            EXPECT_EQ(std::memcmp(plain.vectors().data(), query.vectors().data(),
                                  plain.vectors().size() * sizeof(double)),
                      0);
        }
    }
}

TEST(SubsetSearch, SortedOffsetsCoverEveryPoint) {
    const RandomSystem sys = random_system(7);
    NeighborOptions o;
    o.cutoff = sys.cutoff;
    o.sorted = true;
    o.query = std::vector<std::uint32_t>{3, 1};
    const NeighborList list = tricell::compute_neighbors(sys.box(), sys.positions, o);
    ASSERT_EQ(list.offsets().size(), sys.positions.size() + 1);
    for (std::size_t k = 0; k < list.size(); ++k) {
        EXPECT_TRUE(list.i()[k] == 1 || list.i()[k] == 3);
    }
    EXPECT_EQ(list.offsets()[1], 0u);
    EXPECT_EQ(list.offsets()[4], list.size());
}

TEST(SubsetSearch, TestsFollowTheQueryNotEveryPoint) {
    // 4000 uniform points, a query of 1 in 10: the distance tests of the subset search (the
    // work model's count) are about a tenth of the full search's, on every backend; a query of
    // the atoms of one half of the box, about a quarter on the backends that bin space.
    std::mt19937_64 rng(42);
    std::uniform_real_distribution<double> unit(0, 20);
    std::vector<Eigen::Vector3d> x(4000);
    for (auto& p : x) {
        p = Eigen::Vector3d(unit(rng), unit(rng), unit(rng));
    }
    const tricell::Box box = tricell::Box::from_parameters(20, 20, 20, 90, 90, 90);
    std::vector<std::uint32_t> query;
    for (std::uint32_t k = 0; k < x.size(); k += 10) {
        query.push_back(k);
    }
    std::vector<std::uint32_t> half_box;
    for (std::uint32_t k = 0; k < x.size(); ++k) {
        if (x[k].x() < 10) {
            half_box.push_back(k);
        }
    }
    for (const SearchBackend backend : tricell::search_backends()) {
        SCOPED_TRACE(tricell::backend_name(backend));
        NeighborOptions o;
        o.cutoff = 2.5;
        o.backend = backend;
        const auto tests = [&](const NeighborOptions& options) {
            tricell::NeighborSearch search;
            search.build(box, x, options);
            const tricell::UnitWork work = search.unit_work();
            return std::accumulate(work.measured.begin(), work.measured.end(), 0.0);
        };
        // The full list as a query of every atom but one: the same scan as the subsets' (a query
        // of every atom is the ordinary search, whose range kernel leaves out cells whose atoms
        // lie beyond the cutoff: the ratios below would be those of two different scans).
        std::vector<std::uint32_t> every(x.size() - 1);
        std::iota(every.begin(), every.end(), 0u);
        o.query = every;
        const double full = tests(o);
        o.query = query;
        o.half = true;
        const double subset = tests(o);
        EXPECT_LT(subset, 0.15 * full);
        EXPECT_GT(subset, 0.05 * full);
        // The atoms of one half of the box (as a rank's own atoms): a half subset list scans the
        // half stencil, so about a quarter of the full search's tests, not a half. The direct
        // backend has no stencil: each of the q query atoms meets every atom, the pairs inside
        // the query once, q^2 / 2 + q (N - q) of N^2, about 3/8 for q = N / 2.
        o.query = half_box;
        const double region = tests(o);
        const bool direct = backend == SearchBackend::direct;
        EXPECT_LT(region, (direct ? 0.45 : 0.33) * full);
        EXPECT_GT(region, (direct ? 0.33 : 0.2) * full);
    }
}

TEST(SubsetSearch, BadQueryNamesTheIndex) {
    const std::vector<Eigen::Vector3d> x{{0, 0, 0}, {1, 0, 0}, {2, 0, 0}};
    const tricell::Box box = tricell::Box::from_parameters(5, 5, 5, 90, 90, 90);
    NeighborOptions o;
    o.cutoff = 1.5;
    o.query = std::vector<std::uint32_t>{0, 3};
    EXPECT_THROW_MSG(tricell::compute_neighbors(box, x, o), tricell::InvalidArgument,
                     "query[1] is 3, not the index of one of the 3 positions");
    o.query = std::vector<std::uint32_t>{2, 0, 2};
    EXPECT_THROW_MSG(tricell::compute_neighbors(box, x, o), tricell::InvalidArgument,
                     "query[2] is 2, which the query already holds");
    o.query = std::vector<std::uint32_t>{};
    EXPECT_TRUE(tricell::compute_neighbors(box, x, o).empty());
}
