// The CIF reader: cell, sites, symmetry operators or names, expansion order, special positions,
// occupancies, and every error branch with its message and line.
#include <cmath>
#include <string>

#include <gtest/gtest.h>

#include <tricell/error.hpp>
#include <tricell/io/structure.hpp>

#include "../support/expect_throw_msg.hpp"

namespace {

using tricell::ParseError;
using tricell::io::parse_structure;
using tricell::io::ReadOptions;
using tricell::io::Structure;

Structure cif(const std::string& text, const ReadOptions& options = {}) {
    return parse_structure(text, "test.cif", options);
}

Eigen::Vector3d fractional(const Structure& s, std::size_t k) {
    return s.box.to_fractional(tricell::Cartesian(s.positions[k]));
}

// Line numbers: data_ 1, cell 2-7; then ops() takes 8-11 and the sites loop starts at 8 or 12,
// with its rows from 14 or 18.
std::string cell(const std::string& a = "5", const std::string& beta = "90") {
    return "data_test\n"
           "_cell_length_a " +
           a +
           "\n"
           "_cell_length_b 6\n"
           "_cell_length_c 7\n"
           "_cell_angle_alpha 90\n"
           "_cell_angle_beta " +
           beta +
           "\n"
           "_cell_angle_gamma 90\n";
}

std::string ops(const std::string& a = "x,y,z", const std::string& b = "-x,-y,-z") {
    return "loop_\n_symmetry_equiv_pos_as_xyz\n'" + a + "'\n'" + b + "'\n";
}

const char* const sites_header = "loop_\n"
                                 "_atom_site_label\n"
                                 "_atom_site_type_symbol\n"
                                 "_atom_site_fract_x\n"
                                 "_atom_site_fract_y\n"
                                 "_atom_site_fract_z\n";

TEST(CifReader, ReadsCellSitesAndLabels) {
    const Structure s = cif(cell() + ops("x,y,z", "x,y,z") + sites_header +
                            "Na1 Na 0.1 0.2 0.3\nCl1 Cl 0.5 0.5 0.5\n");
    ASSERT_EQ(s.size(), 2u);
    EXPECT_EQ(s.species, (std::vector<std::string>{"Na", "Cl"}));
    EXPECT_EQ(s.labels, (std::vector<std::string>{"Na1", "Cl1"}));
    EXPECT_EQ(s.occupancies, (std::vector<double>{1.0, 1.0}));
    EXPECT_EQ(s.source, "test.cif");
    const tricell::LatticeParameters p = s.box.parameters();
    EXPECT_NEAR(p.a, 5, 1e-12);
    EXPECT_NEAR(p.b, 6, 1e-12);
    EXPECT_NEAR(p.c, 7, 1e-12);
    EXPECT_NEAR(p.beta, 90, 1e-12);
    EXPECT_TRUE(s.positions[0].isApprox(Eigen::Vector3d(0.5, 1.2, 2.1), 1e-12));
    EXPECT_EQ(s.box.periodicity(), tricell::Periodicity::all());
}

TEST(CifReader, ExpandsRowByRowInOperatorOrderAndMergesSpecialPositions) {
    // Inversion: a general site gives two images, a site on an inversion centre one.
    const Structure s = cif(cell() + ops() + sites_header +
                            "A1 Na 0.1 0.2 0.3\nB1 Cl 0.5 0 0.5\nC1 K 0.2 0.3 0.4\n");
    ASSERT_EQ(s.size(), 5u);
    EXPECT_EQ(s.labels, (std::vector<std::string>{"A1", "A1", "B1", "C1", "C1"}));
    EXPECT_TRUE(fractional(s, 0).isApprox(Eigen::Vector3d(0.1, 0.2, 0.3), 1e-12));
    EXPECT_TRUE(fractional(s, 1).isApprox(Eigen::Vector3d(0.9, 0.8, 0.7), 1e-12));
    EXPECT_TRUE(fractional(s, 2).isApprox(Eigen::Vector3d(0.5, 0, 0.5), 1e-12));
    EXPECT_TRUE(fractional(s, 4).isApprox(Eigen::Vector3d(0.8, 0.7, 0.6), 1e-12));
}

TEST(CifReader, WrapsImagesIntoTheUnitInterval) {
    const Structure s =
        cif(cell() + ops("x,y,z", "x+1,y-2,z+1/2") + sites_header + "A1 Na -0.25 1.0 0.75\n");
    ASSERT_EQ(s.size(), 2u);
    for (std::size_t k = 0; k < s.size(); ++k) {
        const Eigen::Vector3d f = fractional(s, k);
        EXPECT_TRUE((f.array() >= -1e-15).all() && (f.array() < 1).all()) << f.transpose();
    }
    EXPECT_TRUE(fractional(s, 0).isApprox(Eigen::Vector3d(0.75, 0, 0.75), 1e-12));
    EXPECT_NEAR(fractional(s, 1)[2], 0.25, 1e-12);
}

TEST(CifReader, MergeDistanceDecidesWhetherRoundedSpecialPositionsMerge) {
    // 0.3333, 0.6667 on a 3-fold axis of a hexagonal cell: images 1e-4 apart in fractions.
    const std::string text = "data_h\n_cell_length_a 9\n_cell_length_b 9\n_cell_length_c 5\n"
                             "_cell_angle_alpha 90\n_cell_angle_beta 90\n_cell_angle_gamma 120\n"
                             "loop_\n_symmetry_equiv_pos_as_xyz\nx,y,z\n-y,x-y,z\n-x+y,-x,z\n" +
                             std::string(sites_header) + "Ca1 Ca 0.3333 0.6667 0.1\n";
    EXPECT_EQ(cif(text).size(), 1u);
    ReadOptions strict;
    strict.merge_distance = 1e-6;
    EXPECT_EQ(cif(text, strict).size(), 3u);
    strict.merge_distance = -1;
    EXPECT_THROW_MSG(cif(text, strict), tricell::InvalidArgument,
                     "merge_distance must be finite and >= 0 (got -1)");
}

TEST(CifReader, RefusesACellNarrowerThanTwiceTheMergeDistance) {
    // 0.015 Angstrom across a: images of one site could merge through many translates.
    const std::string text = "data_t\n_cell_length_a 0.015\n_cell_length_b 1000\n"
                             "_cell_length_c 1000\n_cell_angle_alpha 90\n_cell_angle_beta 90\n"
                             "_cell_angle_gamma 90\n_symmetry_space_group_name_H-M 'F m -3 m'\n" +
                             std::string(sites_header) + "Si1 Si 0.013 0.171 0.297\n";
    EXPECT_THROW_MSG(cif(text), tricell::ParseError,
                     "the cell is 0.015 Angstrom wide across a, not more than twice "
                     "ReadOptions::merge_distance = 0.01");
    ReadOptions fine;
    fine.merge_distance = 1e-4; // a site in general position: 192 images, none merged
    EXPECT_EQ(cif(text, fine).size(), 192u);
    // One operator merges nothing, so the width does not matter.
    EXPECT_EQ(cif("data_t\n_cell_length_a 0.015\n_cell_length_b 1\n_cell_length_c 1\n"
                  "_cell_angle_alpha 90\n_cell_angle_beta 90\n_cell_angle_gamma 90\n" +
                  std::string(sites_header) + "Si1 Si 0.1 0.2 0.3\n")
                  .size(),
              1u);
}

TEST(CifReader, PrefersTheOperatorLoopOverTheName) {
    const Structure s = cif(cell() + "_symmetry_space_group_name_H-M 'P 1'\n" + ops() +
                            sites_header + "A1 Na 0.1 0.2 0.3\n");
    EXPECT_EQ(s.size(), 2u);
    const Structure t = cif(cell() + "loop_\n_space_group_symop_operation_xyz\nx,y,z\n-x,-y,-z\n" +
                            sites_header + "A1 Na 0.1 0.2 0.3\n");
    EXPECT_EQ(t.size(), 2u);
}

TEST(CifReader, UsesTheHermannMauguinSymbolWithoutOperators) {
    const Structure s = cif(cell("5.64") + "_symmetry_space_group_name_H-M 'F m -3 m'\n" +
                            sites_header + "Na1 Na 0 0 0\nCl1 Cl 0.5 0.5 0.5\n");
    ASSERT_EQ(s.size(), 8u);
    EXPECT_EQ(s.species[3], "Na");
    EXPECT_EQ(s.species[4], "Cl");
    const Structure t =
        cif(cell() + "_space_group_name_H-M_alt 'P -1'\n" + sites_header + "A1 Na 0.1 0.2 0.3\n");
    EXPECT_EQ(t.size(), 2u);
}

TEST(CifReader, UsesTheHallSymbol) {
    const Structure s =
        cif(cell() + "_space_group_name_Hall '-P 1'\n" + sites_header + "A1 Na 0.1 0.2 0.3\n");
    EXPECT_EQ(s.size(), 2u);
}

TEST(CifReader, WithoutSymmetryIsP1) {
    EXPECT_EQ(cif(cell() + sites_header + "A1 Na 0.1 0.2 0.3\n").size(), 1u);
    EXPECT_EQ(
        cif(cell() + "_space_group_IT_number 1\n" + sites_header + "A1 Na 0.1 0.2 0.3\n").size(),
        1u);
}

TEST(CifReader, ReadsUncertaintiesQuotesAndOccupancies) {
    const Structure s = cif(cell("'5.000(3)'") + ops("x,y,z", "x,y,z") +
                            "loop_\n_atom_site_label\n_atom_site_type_symbol\n_atom_site_fract_x\n"
                            "_atom_site_fract_y\n_atom_site_fract_z\n_atom_site_occupancy\n"
                            "Fe1 Fe2+ 0.1(2) 0.2 0.3 0.942(5)\nO1 O2- 0.5 0.5 0.5 ?\n");
    ASSERT_EQ(s.size(), 2u);
    EXPECT_NEAR(s.box.parameters().a, 5, 1e-12);
    EXPECT_EQ(s.species, (std::vector<std::string>{"Fe", "O"}));
    EXPECT_EQ(s.occupancies, (std::vector<double>{0.942, 1.0}));
}

TEST(CifReader, TakesTheElementFromTheLabelWithoutTypeSymbol) {
    const Structure s = cif(cell() + "loop_\n_atom_site_label\n_atom_site_fract_x\n"
                                     "_atom_site_fract_y\n_atom_site_fract_z\n"
                                     "Ca1 0 0 0\nOH 0.5 0.5 0.5\nSI2 0.2 0.2 0.2\n");
    EXPECT_EQ(s.species, (std::vector<std::string>{"Ca", "O", "Si"}));
}

TEST(CifReader, UsesTheFirstBlockWithAtomSites) {
    const Structure s =
        cif("data_global\n_journal_year 1999\n" + cell() + sites_header + "A1 Mg 0.1 0.2 0.3\n");
    EXPECT_EQ(s.species, (std::vector<std::string>{"Mg"}));
}

// ---- errors -------------------------------------------------------------------------------

TEST(CifReaderErrors, EmptyFile) {
    EXPECT_THROW_MSG(cif(""), ParseError, "test.cif: file is empty, expected a CIF data block");
    EXPECT_THROW_MSG(cif("  \n\n"), ParseError, "test.cif: file is empty");
}

TEST(CifReaderErrors, NoDataBlock) {
    EXPECT_THROW_MSG(cif("# just a comment\n"), ParseError,
                     "test.cif: no data block, expected a CIF data block (data_NAME)");
}

TEST(CifReaderErrors, SyntaxErrorsCarryTheirLine) {
    EXPECT_THROW_MSG(cif("_cell_length_a 5\n"), ParseError,
                     "test.cif:1: CIF syntax error: expected block header (data_)");
    EXPECT_THROW_MSG(cif(cell() + "_chemical_name 'unterminated\n"), ParseError,
                     "test.cif:8: CIF syntax error: unterminated 'string'");
    EXPECT_THROW_MSG(cif(cell() + "_chemical_name 'a' 'b'\n"), ParseError,
                     "test.cif:8: CIF syntax error: unexpected ''b'', expected a tag (_name) with "
                     "its value, loop_ with its tags, or data_NAME");
    EXPECT_THROW_MSG(cif(cell() + "loop_\n"), ParseError,
                     "test.cif:9: CIF syntax error: unexpected end of file, expected a tag");
}

TEST(CifReader, AcceptsCrlfLineEndings) {
    std::string text = cell() + ops() + sites_header + "A1 Na 0.1 0.2 0.3\n";
    for (std::size_t k = text.find('\n'); k != std::string::npos; k = text.find('\n', k + 2)) {
        text.insert(k, "\r");
    }
    EXPECT_EQ(cif(text).size(), 2u);
}

TEST(CifReaderErrors, IncompleteLoopRowIsATruncatedFile) {
    EXPECT_THROW_MSG(cif(cell() + sites_header + "A1 Na 0.1 0.2 0.3\nB1 Cl 0.5\n"), ParseError,
                     "test.cif:15: incomplete loop row: the loop of _atom_site_label has 5 tags "
                     "but its last row has 3 values (truncated file or missing value?)");
}

TEST(CifReaderErrors, LoopWithoutValuesAtTheEndOfTheFile) {
    // The cif fuzzer's find: a cell length given as a tag of an empty loop was read as row 0.
    EXPECT_THROW_MSG(cif("data_test\nloop_\n_atom_site_label\n_cell_length_a\n"), ParseError,
                     "test.cif:2: the loop of _atom_site_label has no values");
    EXPECT_THROW_MSG(cif(cell() + sites_header), ParseError,
                     "test.cif:8: the loop of _atom_site_label has no values");
}

TEST(CifReaderErrors, MissingCell) {
    std::string text = cell() + sites_header + "A1 Na 0.1 0.2 0.3\n";
    text.replace(text.find("_cell_angle_beta 90\n"), 20, "");
    EXPECT_THROW_MSG(cif(text), ParseError,
                     "test.cif:1: _cell_angle_beta is missing in data_test, expected the cell "
                     "(_cell_length_a/b/c, _cell_angle_alpha/beta/gamma)");
}

TEST(CifReaderErrors, NonNumericCell) {
    EXPECT_THROW_MSG(cif(cell("five") + sites_header + "A1 Na 0 0 0\n"), ParseError,
                     "test.cif:2: _cell_length_a must be a number, got 'five'");
    EXPECT_THROW_MSG(cif(cell("5(x)") + sites_header + "A1 Na 0 0 0\n"), ParseError,
                     "test.cif:2: _cell_length_a must be a number, got '5(x)'");
    EXPECT_THROW_MSG(cif(cell("?") + sites_header + "A1 Na 0 0 0\n"), ParseError,
                     "test.cif:2: _cell_length_a is unknown (?), expected a number");
}

TEST(CifReaderErrors, CellOutOfRange) {
    EXPECT_THROW_MSG(cif(cell("-5") + sites_header + "A1 Na 0 0 0\n"), ParseError,
                     "test.cif:2: _cell_length_a must be > 0, got -5");
    EXPECT_THROW_MSG(cif(cell("5", "190") + sites_header + "A1 Na 0 0 0\n"), ParseError,
                     "test.cif:6: _cell_angle_beta must be between 0 and 180 degrees, got 190");
    // alpha + beta = gamma: a flat cell.
    std::string flat = cell("5", "60");
    flat.replace(flat.find("_cell_angle_alpha 90"), 20, "_cell_angle_alpha 60");
    flat.replace(flat.find("_cell_angle_gamma 90"), 20, "_cell_angle_gamma 120");
    EXPECT_THROW_MSG(cif(flat + sites_header + "A1 Na 0 0 0\n"), ParseError,
                     "test.cif:2: invalid cell: ");
}

TEST(CifReaderErrors, CellTooLargeForDoubles) {
    std::string huge = cell("1.7e308");
    huge.replace(huge.find("_cell_length_b 6"), 16, "_cell_length_b 1.7e308");
    huge.replace(huge.find("_cell_angle_gamma 90"), 20, "_cell_angle_gamma 60");
    EXPECT_THROW_MSG(cif(huge + sites_header + "A1 Na 0.9 0.9 0\n"), ParseError,
                     "test.cif:2: invalid cell: box is too large: |a|, |b|, |c| = 1.7e+308");
}

TEST(CifReaderErrors, MissingAtomSites) {
    EXPECT_THROW_MSG(cif(cell()), ParseError,
                     "test.cif:1: _atom_site_fract_x is missing in data_test, expected the atom "
                     "sites");
    EXPECT_THROW_MSG(cif(cell() +
                         "loop_\n_atom_site_label\n_atom_site_fract_x\n_atom_site_fract_z\n"
                         "A1 0 0\n"),
                     ParseError,
                     "test.cif:12: _atom_site_fract_y is missing, expected it next to "
                     "_atom_site_fract_x");
    EXPECT_THROW_MSG(cif(cell() +
                         "loop_\n_atom_site_label\n_atom_site_fract_x\n_atom_site_fract_y\n"
                         "A1 0 0\nloop_\n_atom_site_fract_z\n0\n"),
                     ParseError,
                     "test.cif:15: _atom_site_fract_z must be in the same loop as "
                     "_atom_site_fract_x");
}

TEST(CifReaderErrors, NonNumericCoordinateNamesSiteAndLine) {
    EXPECT_THROW_MSG(cif(cell() + sites_header + "A1 Na 0.1 0.2 0.3\nB1 Cl 0.5 half 0.5\n"),
                     ParseError,
                     "test.cif:15: _atom_site_fract_y of site 'B1' must be a number, "
                     "got 'half'");
    EXPECT_THROW_MSG(cif(cell() + sites_header + "A1 Na 0.1 0.2\n.\n"), ParseError,
                     "test.cif:15: _atom_site_fract_z of site 'A1' is unknown (.), expected a "
                     "number");
}

TEST(CifReaderErrors, Occupancy) {
    EXPECT_THROW_MSG(cif(cell() +
                         "loop_\n_atom_site_label\n_atom_site_fract_x\n_atom_site_fract_y\n"
                         "_atom_site_fract_z\n_atom_site_occupancy\nNa1 0 0 0 1.5\n"),
                     ParseError,
                     "test.cif:14: _atom_site_occupancy of site 'Na1' must be between 0 and 1, "
                     "got 1.5");
}

TEST(CifReaderErrors, UnknownElement) {
    EXPECT_THROW_MSG(cif(cell() + sites_header + "Q1 Qq 0 0 0\n"), ParseError,
                     "test.cif:14: cannot tell the element of site 'Q1' from "
                     "_atom_site_type_symbol 'Qq' or _atom_site_label");
}

TEST(CifReaderErrors, BadSymmetryOperators) {
    EXPECT_THROW_MSG(cif(cell() + ops("x,y,z", "x,y") + sites_header + "A1 Na 0 0 0\n"), ParseError,
                     "test.cif:11: invalid symmetry operator 'x,y' (expected exactly two commas "
                     "in triplet), expected a triplet such as '-y, x-y, z+1/3'");
    EXPECT_THROW_MSG(cif(cell() + ops("x,y,z", "x,x,z") + sites_header + "A1 Na 0 0 0\n"),
                     ParseError,
                     "test.cif:11: symmetry operator 'x,x,z' is not a crystallographic operation: "
                     "its rotation part has determinant 0, expected 1 or -1");
    EXPECT_THROW_MSG(cif(cell() + ops("x,y,z", "x/2,y,z") + sites_header + "A1 Na 0 0 0\n"),
                     ParseError, "its rotation part is not an integer matrix");
    EXPECT_THROW_MSG(
        cif(cell() + ops("x,y,z", "x+99999999999,y,z") + sites_header + "A1 Na 0 0 0\n"),
        ParseError, "test.cif:11: invalid symmetry operator");
}

TEST(CifReaderErrors, UnknownSpaceGroup) {
    EXPECT_THROW_MSG(
        cif(cell() + "_symmetry_space_group_name_H-M 'X 9 9'\n" + sites_header + "A1 Na 0 0 0\n"),
        ParseError,
        "test.cif:8: unknown space group 'X 9 9', expected an H-M symbol such as "
        "'P 21/c' or the operators in a _symmetry_equiv_pos_as_xyz loop");
    EXPECT_THROW_MSG(
        cif(cell() + "_space_group_name_Hall 'Q 9'\n" + sites_header + "A1 Na 0 0 0\n"), ParseError,
        "test.cif:8: invalid Hall symbol 'Q 9'");
    EXPECT_THROW_MSG(
        cif(cell() + "_symmetry_Int_Tables_number 14\n" + sites_header + "A1 Na 0 0 0\n"),
        ParseError,
        "test.cif:8: only the space-group number (14) is given, which does not fix "
        "the setting");
}

TEST(CifReaderErrors, DuplicateAndValuelessTags) {
    EXPECT_THROW_MSG(cif(cell() + "_cell_length_a 6\n" + sites_header + "A1 Na 0 0 0\n"),
                     ParseError,
                     "test.cif:8: duplicate tag _cell_length_a (first given on line 2)");
    EXPECT_THROW_MSG(cif(cell() + "_chemical_name\n" + sites_header + "A1 Na 0 0 0\n"), ParseError,
                     "test.cif:8: _chemical_name has no value");
}

} // namespace
