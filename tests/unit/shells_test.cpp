// compute_neighbors at several cutoffs against a separate compute_neighbors per cutoff: the
// prefix of each cutoff holds the same (i, j, S) with the identical d and D, full and half,
// sorted or not, over random triclinic systems with every mix of periodic axes; and the
// refusals.
#include <algorithm>
#include <random>

#include <gtest/gtest.h>

#include <tricell/analysis/shells.hpp>
#include <tricell/error.hpp>

#include "support/brute_force.hpp"
#include "support/expect_throw_msg.hpp"
#include "support/random_systems.hpp"

namespace {

using tricell::InvalidArgument;
using tricell::NeighborList;
using tricell::NeighborOptions;
using tricell::ShellNeighborList;

#ifndef TRICELL_PROPERTY_CASES
#define TRICELL_PROPERTY_CASES 400
#endif

using Entry =
    std::tuple<std::uint32_t, std::uint32_t, int, int, int, double, double, double, double>;

// Entries [begin, end) of a list with every quantity stored, sorted.
std::vector<Entry> entries(const NeighborList& list, std::size_t begin, std::size_t end) {
    std::vector<Entry> out;
    for (std::size_t k = begin; k < end; ++k) {
        const tricell::Shift s = list.shift(k);
        const Eigen::Vector3d d = list.vector(k);
        out.emplace_back(list.i()[k], list.j()[k], s[0], s[1], s[2], list.distances()[k], d[0],
                         d[1], d[2]);
    }
    std::sort(out.begin(), out.end());
    return out;
}

TEST(ShellNeighborList, EachPrefixIsTheListAtItsCutoff_RandomSystems) {
    for (std::uint64_t seed = 1; seed <= TRICELL_PROPERTY_CASES / 2; ++seed) {
        SCOPED_TRACE(seed);
        const tricell::testing::RandomSystem sys = tricell::testing::random_system(seed);
        std::mt19937_64 rng(seed);
        std::uniform_real_distribution<double> u(0.05, 1.0);
        std::vector<double> cutoffs(1 + rng() % 4);
        for (double& c : cutoffs) {
            c = sys.cutoff * u(rng);
        }
        std::sort(cutoffs.begin(), cutoffs.end());
        cutoffs.erase(std::unique(cutoffs.begin(), cutoffs.end()), cutoffs.end());
        NeighborOptions options;
        options.half = rng() % 2 == 0;
        options.sorted = rng() % 2 == 0;
        options.quantities.vectors = true;
        const ShellNeighborList shells =
            tricell::compute_neighbors(sys.box(), sys.positions, cutoffs, options);
        ASSERT_EQ(shells.cutoffs, cutoffs);
        ASSERT_EQ(shells.offsets.size(), cutoffs.size() + 1);
        EXPECT_EQ(shells.offsets.front(), 0u);
        EXPECT_EQ(shells.offsets.back(), shells.pairs.size());
        EXPECT_TRUE(shells.pairs.offsets().empty());
        for (std::size_t k = 0; k < cutoffs.size(); ++k) {
            SCOPED_TRACE(k);
            NeighborOptions single = options;
            single.cutoff = cutoffs[k];
            const NeighborList separate =
                tricell::compute_neighbors(sys.box(), sys.positions, single);
            ASSERT_EQ(shells.count(k), separate.size());
            EXPECT_EQ(entries(shells.pairs, 0, shells.count(k)),
                      entries(separate, 0, separate.size()));
            // Shell k holds cutoffs[k - 1] <= d < cutoffs[k], in search order within the shell.
            for (std::size_t p = shells.offsets[k]; p < shells.offsets[k + 1]; ++p) {
                const double d = shells.pairs.distances()[p];
                EXPECT_LT(d, cutoffs[k]);
                EXPECT_TRUE(k == 0 || d >= cutoffs[k - 1]);
                if (options.sorted && p > shells.offsets[k]) {
                    const auto key = [&](std::size_t q) {
                        const tricell::Shift s = shells.pairs.shift(q);
                        return std::make_tuple(shells.pairs.i()[q], shells.pairs.j()[q], s[0], s[1],
                                               s[2]);
                    };
                    EXPECT_LT(key(p - 1), key(p));
                }
            }
        }
    }
}

TEST(ShellNeighborList, KeepsOnlyTheQuantitiesAskedFor) {
    const tricell::testing::RandomSystem sys = tricell::testing::random_system(3);
    NeighborOptions options;
    options.quantities.distances = false;
    options.quantities.shifts = false;
    const ShellNeighborList shells =
        tricell::compute_neighbors(sys.box(), sys.positions, {0.5, sys.cutoff}, options);
    EXPECT_TRUE(shells.pairs.distances().empty());
    EXPECT_TRUE(shells.pairs.shifts().empty());
    EXPECT_EQ(shells.pairs.j().size(), shells.pairs.size());
    EXPECT_EQ(shells.count(1), shells.pairs.size());
}

TEST(ShellNeighborList, Refusals) {
    const std::vector<Eigen::Vector3d> x = {{0, 0, 0}, {1, 0, 0}};
    const tricell::Box box = tricell::Box::from_columns(3 * Eigen::Matrix3d::Identity());
    NeighborOptions options;
    EXPECT_THROW_MSG(tricell::compute_neighbors(box, x, std::vector<double>{}, options),
                     InvalidArgument, "cutoffs must hold at least one cutoff (got none)");
    EXPECT_THROW_MSG(tricell::compute_neighbors(box, x, {1.0, -2.0}, options), InvalidArgument,
                     "cutoffs[1] must be finite and > 0 (got -2)");
    EXPECT_THROW_MSG(tricell::compute_neighbors(box, x, {1.5, 1.5}, options), InvalidArgument,
                     "cutoffs must increase strictly, but cutoffs[1] = 1.5 follows "
                     "cutoffs[0] = 1.5");
    options.cutoff = 2;
    EXPECT_THROW_MSG(tricell::compute_neighbors(box, x, {1.0, 2.0}, options), InvalidArgument,
                     "NeighborOptions::cutoff must stay 0 when a list of cutoffs is given "
                     "(got 2)");
    options.cutoff = 0;
    options.radii = {1, 1};
    EXPECT_THROW_MSG(tricell::compute_neighbors(box, x, {1.0, 2.0}, options), InvalidArgument,
                     "several cutoffs cannot be combined with NeighborOptions::radii");
}

} // namespace
