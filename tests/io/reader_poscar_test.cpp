// The POSCAR/CONTCAR reader: scale factors, Direct and Cartesian, Selective dynamics, element
// names, and every error branch with its message and line.
#include <cmath>
#include <string>

#include <gtest/gtest.h>

#include <tricell/error.hpp>
#include <tricell/io/structure.hpp>

#include "../support/expect_throw_msg.hpp"

namespace {

using tricell::ParseError;
using tricell::io::parse_structure;
using tricell::io::Structure;

Structure poscar(const std::string& text) {
    return parse_structure(text, "POSCAR");
}

std::string header(const std::string& scale = "1.0") {
    return "cubic test\n" + scale + "\n4 0 0\n0 5 0\n1 0 6\n";
}

TEST(PoscarReader, ReadsDirectCoordinatesInFileOrder) {
    const Structure s = poscar(header() + "Na Cl\n1 2\nDirect\n0 0 0\n0.5 0.5 0.5\n0.5 0 0\n");
    ASSERT_EQ(s.size(), 3u);
    EXPECT_EQ(s.species, (std::vector<std::string>{"Na", "Cl", "Cl"}));
    EXPECT_EQ(s.labels, s.species);
    EXPECT_EQ(s.occupancies, (std::vector<double>{1, 1, 1}));
    // Rows a = (4,0,0), b = (0,5,0), c = (1,0,6): (0.5, 0.5, 0.5) is (2.5, 2.5, 3).
    EXPECT_TRUE(s.positions[1].isApprox(Eigen::Vector3d(2.5, 2.5, 3), 1e-14));
    EXPECT_TRUE(s.box.vector(2).isApprox(Eigen::Vector3d(1, 0, 6), 1e-14));
    EXPECT_EQ(s.box.periodicity(), tricell::Periodicity::all());
    EXPECT_EQ(s.source, "POSCAR");
}

TEST(PoscarReader, ScalesLatticeAndCartesianCoordinates) {
    const Structure s = poscar(header("2.0") + "Si\n1\ncartesian\n1 1 1\n");
    EXPECT_TRUE(s.box.vector(0).isApprox(Eigen::Vector3d(8, 0, 0), 1e-14));
    EXPECT_TRUE(s.positions[0].isApprox(Eigen::Vector3d(2, 2, 2), 1e-14));
    const Structure k = poscar(header("2.0") + "Si\n1\nKartesian\n1 1 1\n");
    EXPECT_TRUE(k.positions[0].isApprox(Eigen::Vector3d(2, 2, 2), 1e-14));
}

TEST(PoscarReader, NegativeScaleIsTheVolume) {
    const Structure s = poscar(header("-960") + "Si\n1\nDirect\n0.5 0 0\n"); // volume 120 * 8
    EXPECT_NEAR(s.box.volume(), 960, 1e-9);
    EXPECT_NEAR(s.positions[0][0], 4, 1e-12);
}

TEST(PoscarReader, ThreeScaleFactorsScaleTheComponents) {
    const Structure s = poscar(header("1 2 3") + "Si\n1\nCartesian\n1 1 1\n");
    EXPECT_TRUE(s.box.vector(2).isApprox(Eigen::Vector3d(1, 0, 18), 1e-14));
    EXPECT_TRUE(s.positions[0].isApprox(Eigen::Vector3d(1, 2, 3), 1e-14));
}

TEST(PoscarReader, SelectiveDynamicsFlagsAndPotcarSuffixesAreIgnored) {
    const Structure s = poscar(header() + "Fe_pv O/abc123  # comment\n1 1\nSelective dynamics\n"
                                          "Direct\n0 0 0 T T F\n0.5 0.5 0.5 F F F ! O\n"
                                          "\n0 0 0\n0 0 0\n");
    EXPECT_EQ(s.species, (std::vector<std::string>{"Fe", "O"}));
    EXPECT_EQ(s.labels, (std::vector<std::string>{"Fe_pv", "O/abc123"}));
    EXPECT_EQ(s.size(), 2u);
}

TEST(PoscarReader, AcceptsCrlfLineEndings) {
    const Structure s =
        poscar("c\r\n1.0\r\n4 0 0\r\n0 5 0\r\n0 0 6\r\nSi\r\n1\r\nD\r\n0 0 0.5\r\n");
    EXPECT_TRUE(s.positions[0].isApprox(Eigen::Vector3d(0, 0, 3), 1e-15));
}

TEST(PoscarReaderErrors, EmptyFile) {
    EXPECT_THROW_MSG(poscar(""), ParseError, "POSCAR: file is empty, expected a POSCAR");
    EXPECT_THROW_MSG(poscar("\n \n"), ParseError, "POSCAR: file is empty");
}

TEST(PoscarReaderErrors, TruncatedHeader) {
    EXPECT_THROW_MSG(poscar("comment\n1.0\n4 0 0\n"), ParseError,
                     "POSCAR:4: unexpected end of file, expected a lattice vector");
    EXPECT_THROW_MSG(poscar(header()), ParseError,
                     "POSCAR:6: unexpected end of file, expected the element names");
    EXPECT_THROW_MSG(poscar(header() + "Si\n1\n"), ParseError,
                     "POSCAR:8: unexpected end of file, expected 'Direct' or 'Cartesian'");
}

TEST(PoscarReaderErrors, ScaleFactor) {
    EXPECT_THROW_MSG(poscar(header("x") + "Si\n1\nDirect\n0 0 0\n"), ParseError,
                     "POSCAR:2: expected the scale factor (a non-zero number), got 'x'");
    EXPECT_THROW_MSG(poscar(header("0") + "Si\n1\nDirect\n0 0 0\n"), ParseError,
                     "POSCAR:2: expected the scale factor (a non-zero number), got '0'");
    EXPECT_THROW_MSG(poscar(header("1 2") + "Si\n1\nDirect\n0 0 0\n"), ParseError,
                     "POSCAR:2: expected the scale factor (one number, or three), got 2 fields");
    EXPECT_THROW_MSG(poscar(header("1 -2 3") + "Si\n1\nDirect\n0 0 0\n"), ParseError,
                     "POSCAR:2: expected three positive scale factors, got '-2'");
}

TEST(PoscarReaderErrors, Lattice) {
    EXPECT_THROW_MSG(poscar("c\n1\n4 0 0\n0 5\n0 0 6\nSi\n1\nDirect\n0 0 0\n"), ParseError,
                     "POSCAR:4: expected 3 numbers for lattice vector b, got 2 fields");
    EXPECT_THROW_MSG(poscar("c\n1\n4 0 0\n0 5 0\n0 0 six\nSi\n1\nDirect\n0 0 0\n"), ParseError,
                     "POSCAR:5: expected a number in lattice vector c, got 'six'");
    EXPECT_THROW_MSG(poscar("c\n1\n4 0 0\n0 5 0\n4 5 0\nSi\n1\nDirect\n0 0 0\n"), ParseError,
                     "POSCAR:3: invalid lattice: box is singular or nearly flat");
    EXPECT_THROW_MSG(poscar("c\n-10\n4 0 0\n0 5 0\n4 5 0\nSi\n1\nDirect\n0 0 0\n"), ParseError,
                     "POSCAR:3: cannot scale to volume 10: the lattice vectors are coplanar");
}

TEST(PoscarReaderErrors, ElementsAndCounts) {
    EXPECT_THROW_MSG(poscar(header() + "1 2\nDirect\n0 0 0\n"), ParseError,
                     "POSCAR:6: expected element names (VASP 5 format), got '1'; VASP 4 files "
                     "without names are not supported");
    EXPECT_THROW_MSG(poscar(header() + "Si Qx\n1 1\nDirect\n0 0 0\n0 0 0\n"), ParseError,
                     "POSCAR:6: unknown element 'Qx', expected element symbols such as 'Si'");
    EXPECT_THROW_MSG(poscar(header() + "Si O\n1\nDirect\n0 0 0\n"), ParseError,
                     "POSCAR:7: expected 2 atom counts (one per element), got 1");
    EXPECT_THROW_MSG(poscar(header() + "Si\n-1\nDirect\n"), ParseError,
                     "POSCAR:7: expected the number of Si atoms (an integer >= 0), got '-1'");
    EXPECT_THROW_MSG(poscar(header() + "Si\n1.5\nDirect\n"), ParseError,
                     "POSCAR:7: expected the number of Si atoms (an integer >= 0), got '1.5'");
    EXPECT_THROW_MSG(poscar(header() + "Si\n99999999999\nDirect\n"), ParseError,
                     "POSCAR:7: atom count 99999999999 is larger than the file can hold");
}

TEST(PoscarReaderErrors, CoordinateMode) {
    EXPECT_THROW_MSG(poscar(header() + "Si\n1\nFractional\n0 0 0\n"), ParseError,
                     "POSCAR:8: expected 'Direct' or 'Cartesian', got 'Fractional'");
    EXPECT_THROW_MSG(poscar(header() + "Si\n1\nSelective\n\n0 0 0\n"), ParseError,
                     "POSCAR:9: expected 'Direct' or 'Cartesian', got an empty line");
}

TEST(PoscarReaderErrors, Positions) {
    EXPECT_THROW_MSG(poscar(header() + "Si O\n2 1\nDirect\n0 0 0\n0.5 0.5 0.5\n"), ParseError,
                     "POSCAR:11: file ends after 2 of 3 atom positions");
    EXPECT_THROW_MSG(poscar(header() + "Si\n2\nDirect\n0 0 0\n0.5 0.5\n"), ParseError,
                     "POSCAR:10: expected 3 coordinates for atom 1, got 2");
    EXPECT_THROW_MSG(poscar(header() + "Si\n2\nDirect\n0 0 0\n0.5 nan 0.5\n"), ParseError,
                     "POSCAR:10: expected a number for coordinate 2 of atom 1, got 'nan'");
    EXPECT_THROW_MSG(poscar(header() + "Si\n2\nDirect\n0 0 0\n0.5 0 1e308\n"), ParseError,
                     "POSCAR:10: atom 1 is too far away: its coordinates times the lattice are "
                     "not finite numbers");
    EXPECT_THROW_MSG(poscar(header("2.0") + "Si\n1\nCartesian\n-1e308 0 0\n"), ParseError,
                     "POSCAR:9: atom 0 is too far away: its coordinates times the scale are not "
                     "finite numbers");
}

} // namespace
