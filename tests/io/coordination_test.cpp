// Coordination numbers with one cutoff and with per-element-pair cutoffs.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include <tricell/error.hpp>
#include <tricell/io/coordination.hpp>

#include "../support/brute_force.hpp"
#include "../support/expect_throw_msg.hpp"
#include "../support/random_systems.hpp"
#include "support/fixtures.hpp"

namespace {

using tricell::io::BondCutoff;
using tricell::io::CoordinationOptions;

tricell::io::Structure quartz() {
    return tricell::io::read_structure(tricell::test::fixtures_dir() +
                                       "/structures/alpha_quartz.cif");
}

TEST(Coordination, QuartzWithOneCutoff) {
    const tricell::io::Structure s = quartz();
    CoordinationOptions options;
    options.cutoff = 2.0;
    const auto c = tricell::io::coordination(s, options);
    ASSERT_EQ(c.size(), 9u);
    for (std::size_t k = 0; k < c.size(); ++k) {
        EXPECT_EQ(c[k].count, s.species[k] == "Si" ? 4u : 2u) << k;
        EXPECT_NEAR(c[k].nearest, 1.6046315549099557, 1e-9);
    }
}

// A cutoff whose list would not fit in max_pairs is refused by the search before it allocates.
TEST(Coordination, MaxPairsRefusesAHugeSearch) {
    CoordinationOptions options;
    options.cutoff = 1e4; // ~4e12 pairs for 9 atoms in 113 A^3
    try {
        tricell::io::coordination(quartz(), options);
        ADD_FAILURE() << "expected InvalidArgument";
    } catch (const tricell::InvalidArgument& e) {
        EXPECT_NE(std::string(e.what()).find("cutoff 10000 would give about"), std::string::npos)
            << e.what();
    }
    options.cutoff = 3;
    options.max_pairs = 50;
    EXPECT_THROW(tricell::io::coordination(quartz(), options), tricell::InvalidArgument);
    options.max_pairs = 0; // no limit
    EXPECT_EQ(tricell::io::coordination(quartz(), options).size(), 9u);
}

TEST(Coordination, PairCutoffsOverrideTheDefault) {
    const tricell::io::Structure s = quartz();
    CoordinationOptions options;
    options.bonds = {BondCutoff{"o", "SI", 1.7}};
    auto c = tricell::io::coordination(s, options);
    EXPECT_EQ(c[0].count, 4u); // Si: four O, no Si-Si bond without a cutoff for it
    EXPECT_EQ(c[3].count, 2u);
    // O-O at 2.6 A: six O neighbours per O once O-O counts.
    options.bonds.push_back(BondCutoff{"O", "O", 2.7});
    c = tricell::io::coordination(s, options);
    EXPECT_EQ(c[0].count, 4u);
    EXPECT_EQ(c[3].count, 8u);
    // A default cutoff of 3.2 adds Si-Si (3.06 A), while Si-O and O-O keep their own cutoffs.
    options.cutoff = 3.2;
    c = tricell::io::coordination(s, options);
    EXPECT_EQ(c[0].count, 8u);
    EXPECT_EQ(c[3].count, 8u);
}

TEST(Coordination, AtomWithoutNeighboursHasNanNearest) {
    tricell::io::Structure s;
    s.box = tricell::Box::from_parameters(10, 10, 10, 90, 90, 90);
    s.species = {"Ar"};
    s.positions = {Eigen::Vector3d(1, 1, 1)};
    s.occupancies = {1};
    s.labels = {"Ar"};
    CoordinationOptions options;
    options.cutoff = 3;
    const auto c = tricell::io::coordination(s, options);
    EXPECT_EQ(c[0].count, 0u);
    EXPECT_TRUE(std::isnan(c[0].nearest));
    EXPECT_TRUE(std::isnan(c[0].mean));
}

// Count, shortest and mean bond of every atom against the brute-force list, over random boxes
// (skewed, mixed periodicity, cutoffs beyond the cell, atoms far outside) with one cutoff for
// every pair. Distances agree to rounding (1e-10 of the largest coordinate); an atom with a
// pair that close to the cutoff may count it or not, and is skipped.
TEST(Coordination, MatchesBruteForceOnRandomSystems) {
    for (std::uint64_t seed = 1; seed <= 60; ++seed) {
        SCOPED_TRACE(seed);
        const tricell::testing::RandomSystem system = tricell::testing::random_system(seed);
        tricell::io::Structure s;
        s.box = system.box();
        s.positions = system.positions;
        s.species.assign(s.positions.size(), "Ar");
        s.labels.assign(s.positions.size(), "Ar");
        s.occupancies.assign(s.positions.size(), 1.0);
        CoordinationOptions options;
        options.cutoff = system.cutoff;
        const auto c = tricell::io::coordination(s, options);
        const auto pairs =
            tricell::testing::brute_force_pairs(s.box, system.positions, system.cutoff);
        double tol = 1e-10;
        for (const Eigen::Vector3d& x : s.positions) {
            tol = std::max(tol, 1e-10 * x.cwiseAbs().maxCoeff());
        }
        std::vector<std::size_t> count(s.size(), 0);
        std::vector<double> sum(s.size(), 0.0), nearest(s.size(), INFINITY);
        std::vector<bool> borderline(s.size(), false);
        for (const auto& [key, value] : pairs) {
            const std::size_t i = std::get<0>(key);
            borderline[i] = borderline[i] || system.cutoff - value.distance <= tol;
            ++count[i];
            sum[i] += value.distance;
            nearest[i] = std::min(nearest[i], value.distance);
        }
        ASSERT_EQ(c.size(), s.size());
        for (std::size_t k = 0; k < s.size(); ++k) {
            if (borderline[k]) {
                continue;
            }
            EXPECT_EQ(c[k].count, count[k]) << k;
            if (count[k] == 0) {
                EXPECT_TRUE(std::isnan(c[k].nearest) && std::isnan(c[k].mean)) << k;
            } else {
                EXPECT_NEAR(c[k].nearest, nearest[k], tol) << k;
                EXPECT_NEAR(c[k].mean, sum[k] / double(count[k]), tol) << k;
            }
        }
    }
}

TEST(Coordination, Errors) {
    const tricell::io::Structure s = quartz();
    CoordinationOptions options;
    EXPECT_THROW_MSG(tricell::io::coordination(s, options), tricell::InvalidArgument,
                     "no cutoff: give a cutoff for all pairs or per-element-pair bond cutoffs");
    options.cutoff = -1;
    EXPECT_THROW_MSG(options.validate(), tricell::InvalidArgument,
                     "cutoff must be finite and >= 0 (got -1)");
    options.cutoff = 0;
    options.bonds = {BondCutoff{"Si", "Qq", 2}};
    EXPECT_THROW_MSG(options.validate(), tricell::InvalidArgument,
                     "bond Si-Qq: unknown element 'Qq'");
    options.bonds = {BondCutoff{"Si", "O", 0}};
    EXPECT_THROW_MSG(options.validate(), tricell::InvalidArgument,
                     "bond Si-O: cutoff must be > 0 (got 0)");
    options.bonds = {BondCutoff{"Si", "O", 2}, BondCutoff{"o", "si", 1.8}};
    EXPECT_THROW_MSG(options.validate(), tricell::InvalidArgument, "bond O-Si is given twice");
}

} // namespace
