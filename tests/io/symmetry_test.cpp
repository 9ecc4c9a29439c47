// spglib through tricell::io: the space group of every fixture is the one its CIF declares,
// Niggli reduction keeps the lattice, and the error branches.
#include <cmath>
#include <regex>
#include <string>

#include <gtest/gtest.h>

#include <Eigen/LU>

#include <tricell/error.hpp>
#include <tricell/io/symmetry.hpp>

#include "../support/expect_throw_msg.hpp"
#include "support/fixtures.hpp"

namespace {

class FixtureSymmetry : public ::testing::TestWithParam<std::string> {};

// The declared number, except for the two primitive cells written in P 1: spglib finds the
// symmetry of the crystal, Fm-3m and Fd-3m.
TEST_P(FixtureSymmetry, SpaceGroupIsTheDeclaredOne) {
    const std::string path = tricell::test::fixtures_dir() + "/structures/" + GetParam() + ".cif";
    std::smatch match;
    const std::string text = tricell::test::read_text(path);
    ASSERT_TRUE(
        std::regex_search(text, match, std::regex("_symmetry_Int_Tables_number\\s+(\\d+)")));
    int declared = std::stoi(match[1]);
    if (GetParam() == "cu_fcc_primitive") {
        declared = 225;
    } else if (GetParam() == "si_diamond_primitive") {
        declared = 227;
    }
    const tricell::io::Structure s = tricell::io::read_structure(path);
    const tricell::io::SpaceGroupInfo info = tricell::io::find_space_group(s, 1e-3);
    EXPECT_EQ(info.number, declared) << info.international;
    EXPECT_FALSE(info.international.empty());
    EXPECT_FALSE(info.hall.empty());
}

std::string test_name(const ::testing::TestParamInfo<std::string>& param) {
    return param.param;
}

INSTANTIATE_TEST_SUITE_P(All, FixtureSymmetry, ::testing::ValuesIn(tricell::test::fixture_names()),
                         test_name);

TEST(SpaceGroup, OccupancyDistinguishesSites) {
    // Two atoms of one element at (0,0,0) and (1/2,1/2,1/2): body-centred when equal, primitive
    // cubic when one is half occupied.
    tricell::io::Structure s;
    s.box = tricell::Box::from_parameters(3, 3, 3, 90, 90, 90);
    s.species = {"Fe", "Fe"};
    s.positions = {Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(1.5, 1.5, 1.5)};
    s.occupancies = {1, 1};
    s.labels = {"Fe1", "Fe1"};
    EXPECT_EQ(tricell::io::find_space_group(s).number, 229); // Im-3m
    s.occupancies = {1, 0.5};
    EXPECT_EQ(tricell::io::find_space_group(s).number, 221); // Pm-3m
}

TEST(SpaceGroup, Errors) {
    tricell::io::Structure s;
    s.box = tricell::Box::from_parameters(3, 3, 3, 90, 90, 90);
    EXPECT_THROW_MSG(tricell::io::find_space_group(s), tricell::InvalidArgument,
                     "the space group needs at least one atom");
    s.species = {"Fe"};
    s.positions = {Eigen::Vector3d(0, 0, 0)};
    s.occupancies = {1};
    s.labels = {"Fe"};
    EXPECT_THROW_MSG(tricell::io::find_space_group(s, 0), tricell::InvalidArgument,
                     "symprec must be > 0 (got 0)");
    s.box = tricell::Box::from_parameters(3, 3, 3, 90, 90, 90,
                                          tricell::Periodicity{{{true, true, false}}});
    EXPECT_THROW_MSG(tricell::io::find_space_group(s), tricell::InvalidArgument,
                     "the space group needs a box periodic along a, b and c");
    EXPECT_THROW_MSG(tricell::io::niggli_reduce(s.box), tricell::InvalidArgument,
                     "Niggli reduction needs a box periodic along a, b and c");
    EXPECT_THROW_MSG(
        tricell::io::niggli_reduce(tricell::Box::from_parameters(3, 3, 3, 90, 90, 90), -1),
        tricell::InvalidArgument, "the Niggli tolerance must be > 0 (got -1)");
}

TEST(Niggli, ReducesASkewedCellToTheSameLattice) {
    // The orthorhombic 3 x 4 x 5 lattice in a skewed basis: rows (a, 2a + b, -a + 3b + c).
    Eigen::Matrix3d rows;
    rows << 3, 0, 0, 6, 4, 0, -3, 12, 5;
    const tricell::Box box = tricell::Box::from_rows(rows);
    const tricell::Box reduced = tricell::io::niggli_reduce(box);
    // Same lattice: H_reduced = H M with M integer and |det M| = 1.
    const Eigen::Matrix3d m = box.inverse() * reduced.matrix();
    EXPECT_TRUE(m.isApprox(m.array().round().matrix(), 1e-9)) << m;
    EXPECT_NEAR(std::abs(m.determinant()), 1, 1e-9);
    const tricell::LatticeParameters p = reduced.parameters();
    EXPECT_LE(p.a, p.b + 1e-9);
    EXPECT_LE(p.b, p.c + 1e-9);
    EXPECT_NEAR(p.a, 3, 1e-9);
    EXPECT_NEAR(p.b, 4, 1e-9);
    EXPECT_NEAR(p.c, 5, 1e-9);
    EXPECT_NEAR(p.alpha, 90, 1e-9);
    EXPECT_NEAR(p.beta, 90, 1e-9);
    EXPECT_NEAR(p.gamma, 90, 1e-9);
}

TEST(Niggli, PrimitiveFccStaysAtSixtyDegrees) {
    const tricell::Box box = tricell::Box::from_parameters(2.55, 2.55, 2.55, 60, 60, 60);
    const tricell::LatticeParameters p = tricell::io::niggli_reduce(box).parameters();
    EXPECT_NEAR(p.a, 2.55, 1e-9);
    EXPECT_NEAR(p.alpha, 60, 1e-9);
    EXPECT_NEAR(p.beta, 60, 1e-9);
    EXPECT_NEAR(p.gamma, 60, 1e-9);
}

TEST(Spglib, Version) {
    EXPECT_EQ(tricell::io::spglib_version().rfind("2.", 0), 0u);
}

} // namespace
