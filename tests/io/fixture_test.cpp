// The fixtures against pymatgen (fixtures/reference, written by scripts/make-fixtures.py):
// (a) our CIF expansion is pymatgen's expanded structure, as a set of (element, fractional
//     position mod 1, occupancy) with equal atom counts, for every fixture;
// (b) tricell::compute_neighbors on pymatgen's own structure (its lattice rows and Cartesian
//     positions) gives pymatgen's full neighbour list pair for pair (i, j, S), distances equal
//     to 1e-9, skipping pairs with |d - r| < 1e-6 (pymatgen keeps d <= r + 1e-8), for every
//     fixture and both cutoffs.
#include <cmath>
#include <map>
#include <set>
#include <string>
#include <tuple>

#include <gtest/gtest.h>

#include <tricell/io/structure.hpp>
#include <tricell/neighbor_list.hpp>

#include "support/fixtures.hpp"

namespace {

using tricell::test::fixture_names;

class Fixture : public ::testing::TestWithParam<std::string> {};

std::string test_name(const ::testing::TestParamInfo<std::string>& info) {
    return info.param;
}

// Periodic distance between fractional positions, in fractions (max over axes).
double fractional_gap(const Eigen::Vector3d& s, const Eigen::Vector3d& t) {
    Eigen::Vector3d d = s - t;
    for (int k = 0; k < 3; ++k) {
        d[k] -= std::round(d[k]);
    }
    return d.cwiseAbs().maxCoeff();
}

TEST(Fixtures, AllTwentyOneArePresent) {
    EXPECT_EQ(fixture_names().size(), 21u);
}

TEST_P(Fixture, CifExpansionEqualsPymatgen) {
    const std::string name = GetParam();
    const tricell::io::Structure ours =
        tricell::io::read_structure(tricell::test::fixtures_dir() + "/structures/" + name + ".cif");
    const tricell::test::ReferenceStructure theirs = tricell::test::read_reference_structure(name);
    ASSERT_EQ(ours.size(), theirs.symbols.size());

    // Same lattice parameters (the Cartesian frames differ, the fractional coordinates do not).
    const tricell::LatticeParameters p = ours.box.parameters();
    const tricell::LatticeParameters q = tricell::Box::from_rows(theirs.rows).parameters();
    EXPECT_NEAR(p.a, q.a, 1e-9);
    EXPECT_NEAR(p.b, q.b, 1e-9);
    EXPECT_NEAR(p.c, q.c, 1e-9);
    EXPECT_NEAR(p.alpha, q.alpha, 1e-9);
    EXPECT_NEAR(p.beta, q.beta, 1e-9);
    EXPECT_NEAR(p.gamma, q.gamma, 1e-9);

    // Every one of our atoms is wrapped into [0, 1) ...
    std::vector<Eigen::Vector3d> fractional;
    for (const Eigen::Vector3d& x : ours.positions) {
        fractional.push_back(ours.box.to_fractional(tricell::Cartesian(x)));
        EXPECT_TRUE((fractional.back().array() > -1e-12).all() &&
                    (fractional.back().array() < 1 + 1e-12).all())
            << fractional.back().transpose();
    }
    // ... and matches exactly one of pymatgen's, same element and occupancy.
    std::vector<bool> used(ours.size(), false);
    for (std::size_t k = 0; k < theirs.symbols.size(); ++k) {
        std::size_t match = ours.size();
        for (std::size_t m = 0; m < ours.size(); ++m) {
            if (!used[m] && ours.species[m] == theirs.symbols[k] &&
                fractional_gap(fractional[m], theirs.fractional[k]) < 1e-9) {
                match = m;
                break;
            }
        }
        ASSERT_LT(match, ours.size()) << "pymatgen site " << k << " " << theirs.symbols[k] << " "
                                      << theirs.fractional[k].transpose() << " not found";
        used[match] = true;
        EXPECT_DOUBLE_EQ(ours.occupancies[match], theirs.occupancies[k]);
    }
}

TEST_P(Fixture, NeighborListsEqualPymatgen) {
    const std::string name = GetParam();
    const tricell::test::ReferenceStructure structure =
        tricell::test::read_reference_structure(name);
    const tricell::Box box = tricell::Box::from_rows(structure.rows);
    const auto lists = tricell::test::reference_lists(name);
    ASSERT_EQ(lists.size(), 2u);
    for (const auto& [file, cutoff] : lists) {
        SCOPED_TRACE(file);
        using Key = std::tuple<std::uint32_t, std::uint32_t, int, int, int>;
        std::map<Key, double> expected;
        for (const tricell::test::ReferencePair& p : tricell::test::read_reference_pairs(file)) {
            if (std::abs(p.distance - cutoff) >= 1e-6) {
                expected[{p.i, p.j, p.shift[0], p.shift[1], p.shift[2]}] = p.distance;
            }
        }
        ASSERT_FALSE(expected.empty());

        tricell::NeighborOptions options;
        options.cutoff = cutoff;
        options.sorted = true;
        options.quantities.vectors = true;
        const tricell::NeighborList list =
            tricell::compute_neighbors(box, structure.cartesian, options);
        std::map<Key, double> actual;
        for (std::size_t k = 0; k < list.size(); ++k) {
            const double d = list.distances()[k];
            if (std::abs(d - cutoff) >= 1e-6) {
                const tricell::Shift s = list.shift(k);
                const bool fresh =
                    actual.emplace(Key{list.i()[k], list.j()[k], s[0], s[1], s[2]}, d).second;
                EXPECT_TRUE(fresh) << "duplicate pair " << list.i()[k] << " " << list.j()[k];
            }
        }
        EXPECT_EQ(actual.size(), expected.size());
        std::size_t missing = 0;
        for (const auto& [key, d] : expected) {
            const auto found = actual.find(key);
            if (found == actual.end()) {
                if (++missing <= 5) {
                    ADD_FAILURE() << "missing pair " << std::get<0>(key) << " " << std::get<1>(key)
                                  << " (" << std::get<2>(key) << " " << std::get<3>(key) << " "
                                  << std::get<4>(key) << ") d=" << d;
                }
                continue;
            }
            EXPECT_NEAR(found->second, d, 1e-9);
        }
        EXPECT_EQ(missing, 0u);
        for (const auto& [key, d] : actual) {
            EXPECT_TRUE(expected.count(key))
                << "extra pair " << std::get<0>(key) << " " << std::get<1>(key) << " d=" << d;
        }
    }
}

INSTANTIATE_TEST_SUITE_P(All, Fixture, ::testing::ValuesIn(fixture_names()), test_name);

} // namespace
