// Resource limits of the readers: a file that claims more atoms than ReadOptions::max_atoms, or
// more than it can hold, and a CIF whose symmetry expansion would explode, are refused with a
// message naming the value before the atoms are read (hostile input never crashes).
#include <string>

#include <gtest/gtest.h>

#include <tricell/error.hpp>
#include <tricell/io/structure.hpp>

#include "../support/expect_throw_msg.hpp"

namespace {

using tricell::ParseError;
using tricell::io::parse_structure;
using tricell::io::ReadOptions;

ReadOptions at_most(std::size_t atoms) {
    ReadOptions options;
    options.max_atoms = atoms;
    return options;
}

const char* const poscar_three = "cubic\n1.0\n4 0 0\n0 4 0\n0 0 4\nNa Cl\n1 2\nDirect\n"
                                 "0 0 0\n0.5 0.5 0.5\n0.5 0 0\n";

TEST(ReaderLimits, PoscarCountAboveMaxAtoms) {
    EXPECT_EQ(parse_structure(poscar_three, "POSCAR", at_most(3)).size(), 3u);
    EXPECT_EQ(parse_structure(poscar_three, "POSCAR", at_most(0)).size(), 3u); // no limit
    EXPECT_THROW_MSG(parse_structure(poscar_three, "POSCAR", at_most(2)), ParseError,
                     "POSCAR:7: the file has 3 atoms, more than ReadOptions::max_atoms = 2");
}

TEST(ReaderLimits, PoscarClaimingABillionAtoms) {
    EXPECT_THROW_MSG(
        parse_structure("x\n1.0\n1 0 0\n0 1 0\n0 0 1\nSi\n1000000000\nDirect\n0 0 0\n", "POSCAR"),
        ParseError, "POSCAR:7: atom count 1000000000 is larger than the file can hold");
}

TEST(ReaderLimits, XyzCountAboveMaxAtoms) {
    const std::string two = "2\n\nH 0 0 0\nH 0 0 1\n";
    EXPECT_EQ(parse_structure(two, "test.xyz", at_most(2)).size(), 2u);
    EXPECT_THROW_MSG(parse_structure(two, "test.xyz", at_most(1)), ParseError,
                     "test.xyz:1: the file has 2 atoms, more than ReadOptions::max_atoms = 1");
    EXPECT_THROW_MSG(
        parse_structure("1000000000\nLattice=\"1 0 0 0 1 0 0 0 1\"\nSi 0 0 0\n", "test.xyz"),
        ParseError,
        "test.xyz:1: the file has 1000000000 atoms, more than ReadOptions::max_atoms "
        "= 10000000");
}

std::string cif_with_ops(const std::vector<std::string>& ops, int sites) {
    std::string text = "data_t\n_cell_length_a 50\n_cell_length_b 50\n_cell_length_c 50\n"
                       "_cell_angle_alpha 90\n_cell_angle_beta 90\n_cell_angle_gamma 90\n"
                       "loop_\n_symmetry_equiv_pos_as_xyz\n";
    for (const std::string& op : ops) {
        text += "'" + op + "'\n";
    }
    text += "loop_\n_atom_site_label\n_atom_site_fract_x\n_atom_site_fract_y\n"
            "_atom_site_fract_z\n";
    for (int k = 0; k < sites; ++k) {
        text += "Si" + std::to_string(k) + " 0.1 0.2 " + std::to_string(0.001 * k) + "\n";
    }
    return text;
}

// x + i/24, y + j/24, z: 576 distinct pure translations.
std::vector<std::string> translations(int count) {
    std::vector<std::string> ops;
    for (int k = 0; k < count; ++k) {
        ops.push_back("x+" + std::to_string(k % 24) + "/24,y+" + std::to_string(k / 24) + "/24,z");
    }
    return ops;
}

TEST(ReaderLimits, CifRepeatedOperatorsCountOnce) {
    const std::vector<std::string> ops(1000, "x,y,z");
    EXPECT_EQ(parse_structure(cif_with_ops(ops, 3), "t.cif").size(), 3u);
    EXPECT_EQ(parse_structure(cif_with_ops({"x,y,z", "x+1,y,z-1"}, 1), "t.cif").size(), 1u);
}

TEST(ReaderLimits, CifWithMoreOperatorsThanAnySpaceGroup) {
    EXPECT_EQ(parse_structure(cif_with_ops(translations(192), 1), "t.cif").size(), 192u);
    EXPECT_THROW_MSG(parse_structure(cif_with_ops(translations(193), 1), "t.cif"), ParseError,
                     "t.cif:202: more than 192 distinct symmetry operators, more than any space "
                     "group has");
}

TEST(ReaderLimits, CifExpansionAboveMaxAtoms) {
    EXPECT_EQ(parse_structure(cif_with_ops(translations(4), 5), "t.cif", at_most(20)).size(), 20u);
    EXPECT_THROW_MSG(parse_structure(cif_with_ops(translations(4), 5), "t.cif", at_most(19)),
                     ParseError,
                     "t.cif:19: the symmetry expansion of 5 sites by 4 operators could give 20 "
                     "atoms, more than ReadOptions::max_atoms = 19");
}

} // namespace
