// The (extended) XYZ reader: Lattice, pbc, Properties, open systems, and every error branch
// with its message and line.
#include <string>

#include <gtest/gtest.h>

#include <tricell/error.hpp>
#include <tricell/io/structure.hpp>

#include "../support/expect_throw_msg.hpp"

namespace {

using tricell::ParseError;
using tricell::Periodicity;
using tricell::io::parse_structure;
using tricell::io::Structure;

Structure xyz(const std::string& text) {
    return parse_structure(text, "test.xyz");
}

TEST(XyzReader, ReadsAseExtendedXyz) {
    const Structure s = xyz("2\nLattice=\"4 0 0 1 5 0 0 0 6\" Properties=species:S:1:pos:R:3:"
                            "forces:R:3 energy=-1.5 pbc=\"T T F\"\n"
                            "Si 0 0 0 0.1 0.2 0.3\nO 1 2 3 0 0 0\n");
    ASSERT_EQ(s.size(), 2u);
    EXPECT_EQ(s.species, (std::vector<std::string>{"Si", "O"}));
    EXPECT_TRUE(s.positions[1].isApprox(Eigen::Vector3d(1, 2, 3), 1e-15));
    EXPECT_TRUE(s.box.vector(1).isApprox(Eigen::Vector3d(1, 5, 0), 1e-15));
    EXPECT_EQ(s.box.periodicity(), (Periodicity{{{true, true, false}}}));
}

TEST(XyzReader, FindsColumnsFromPropertiesInAnyOrder) {
    const Structure s = xyz("1\nproperties=id:I:1:pos:R:3:Z:I:1:species:S:1 "
                            "lattice=\"3 0 0 0 3 0 0 0 3\"\n7 1.5 2.5 0.5 8 fe\n");
    EXPECT_EQ(s.species, (std::vector<std::string>{"Fe"}));
    EXPECT_EQ(s.labels, (std::vector<std::string>{"fe"}));
    EXPECT_TRUE(s.positions[0].isApprox(Eigen::Vector3d(1.5, 2.5, 0.5), 1e-15));
    EXPECT_EQ(s.box.periodicity(), Periodicity::all()); // Lattice without pbc
}

TEST(XyzReader, PlainXyzIsAnOpenSystemInAFrameAroundTheAtoms) {
    const Structure s = xyz("3\nwater, free text with = and \"quotes\"\n"
                            "O 0 0 0.1173\nH 0 0.7572 -0.4692\n1 0 -0.7572 -0.4692\n");
    EXPECT_EQ(s.species, (std::vector<std::string>{"O", "H", "H"}));
    EXPECT_EQ(s.box.periodicity(), Periodicity::none());
    // Extent + 1 along x, y, z.
    EXPECT_TRUE(s.box.perpendicular_widths().isApprox(Eigen::Vector3d(1, 2.5144, 1.5865), 1e-12));
    EXPECT_TRUE(s.positions[2].isApprox(Eigen::Vector3d(0, -0.7572, -0.4692), 1e-15));
}

TEST(XyzReader, ReadsOnlyTheFirstFrame) {
    const Structure s = xyz("1\n\nH 0 0 0\n2\n\nH 0 0 0\nH 1 0 0\n");
    EXPECT_EQ(s.size(), 1u);
    EXPECT_EQ(xyz("0\nnothing\n").size(), 0u);
}

TEST(XyzReader, AcceptsCrlfLineEndings) {
    const Structure s = xyz("1\r\nLattice=\"3 0 0 0 3 0 0 0 3\"\r\nAr 1 2 3\r\n");
    EXPECT_TRUE(s.positions[0].isApprox(Eigen::Vector3d(1, 2, 3), 1e-15));
    EXPECT_EQ(s.box.periodicity(), Periodicity::all());
}

TEST(XyzReaderErrors, EmptyFile) {
    EXPECT_THROW_MSG(xyz(""), ParseError, "test.xyz: file is empty, expected an XYZ file");
}

TEST(XyzReaderErrors, AtomCount) {
    EXPECT_THROW_MSG(xyz("three\n\nH 0 0 0\n"), ParseError,
                     "test.xyz:1: expected the number of atoms (an integer >= 0), got 'three'");
    EXPECT_THROW_MSG(xyz("-1\n\n"), ParseError,
                     "test.xyz:1: expected the number of atoms (an integer >= 0), got '-1'");
    EXPECT_THROW_MSG(xyz("2\n"), ParseError,
                     "test.xyz:2: unexpected end of file, expected the comment line");
}

TEST(XyzReaderErrors, Truncated) {
    EXPECT_THROW_MSG(xyz("3\ncomment\nH 0 0 0\n"), ParseError,
                     "test.xyz:4: file ends after 1 of 3 atom lines");
}

TEST(XyzReaderErrors, Lattice) {
    EXPECT_THROW_MSG(xyz("1\nLattice=\"1 0 0 0 1 0\"\nH 0 0 0\n"), ParseError,
                     "test.xyz:2: Lattice must hold 9 numbers (a, b, c as rows), got 6");
    EXPECT_THROW_MSG(xyz("1\nLattice=\"1 0 0 0 1 0 0 0 x\"\nH 0 0 0\n"), ParseError,
                     "test.xyz:2: expected a number in Lattice, got 'x'");
    EXPECT_THROW_MSG(xyz("1\nLattice=\"1 0 0 0 1 0 0 0 1\nH 0 0 0\n"), ParseError,
                     "test.xyz:2: unterminated quote in the value of lattice");
    EXPECT_THROW_MSG(xyz("1\nLattice=\"1 0 0 2 0 0 0 0 1\"\nH 0 0 0\n"), ParseError,
                     "test.xyz:2: invalid box: box is singular or nearly flat");
}

TEST(XyzReaderErrors, Pbc) {
    EXPECT_THROW_MSG(xyz("1\nLattice=\"1 0 0 0 1 0 0 0 1\" pbc=\"T T\"\nH 0 0 0\n"), ParseError,
                     "test.xyz:2: pbc must be three of T/F (as in pbc=\"T T F\"), got 'T T'");
    EXPECT_THROW_MSG(xyz("1\npbc=\"T T T\"\nH 0 0 0\n"), ParseError,
                     "test.xyz:2: pbc has a periodic axis but there is no Lattice");
}

TEST(XyzReaderErrors, Properties) {
    EXPECT_THROW_MSG(xyz("1\nProperties=species:S:1:pos:R\nH 0 0 0\n"), ParseError,
                     "test.xyz:2: Properties must be name:type:count triples, got "
                     "'species:S:1:pos:R'");
    EXPECT_THROW_MSG(xyz("1\nProperties=species:S:1:pos:Q:3\nH 0 0 0\n"), ParseError,
                     "test.xyz:2: Properties must be name:type:count triples with type S, R, I "
                     "or L and a count >= 1, got 'pos:Q:3'");
    EXPECT_THROW_MSG(xyz("1\nProperties=species:S:1:pos:R:2\nH 0 0\n"), ParseError,
                     "test.xyz:2: Properties: pos must be pos:R:3, got 'pos:R:2'");
    EXPECT_THROW_MSG(xyz("1\nProperties=species:R:1:pos:R:3\nH 0 0 0\n"), ParseError,
                     "test.xyz:2: Properties: species must be species:S:1, got 'species:R:1'");
    EXPECT_THROW_MSG(xyz("1\nProperties=species:S:1:positions:R:3\nH 0 0 0\n"), ParseError,
                     "test.xyz:2: Properties has no pos:R:3 column, got "
                     "'species:S:1:positions:R:3'");
}

TEST(XyzReaderErrors, AtomLines) {
    EXPECT_THROW_MSG(xyz("2\n\nH 0 0 0\nH 0 0\n"), ParseError,
                     "test.xyz:4: expected 4 columns (Properties=species:S:1:pos:R:3) for atom 1, "
                     "got 3");
    EXPECT_THROW_MSG(xyz("2\n\nH 0 0 0\nH 0 y 0\n"), ParseError,
                     "test.xyz:4: expected a number for coordinate 2 of atom 1, got 'y'");
    EXPECT_THROW_MSG(xyz("1\n\nXx 0 0 0\n"), ParseError,
                     "test.xyz:3: unknown element 'Xx' for atom 0, expected an element symbol or "
                     "atomic number");
    EXPECT_THROW_MSG(xyz("1\n\n200 0 0 0\n"), ParseError, "test.xyz:3: unknown element '200'");
}

} // namespace

TEST(XyzReaderErrors, ControlCharactersOfTheCommentLineLeaveTheMessageOnOneLine) {
    // A carriage return and a vertical tab inside a quoted Properties value (xyz_fuzzer): the
    // message shows them as spaces.
    EXPECT_THROW_MSG(xyz("1\nProperties=\"species:S:1:pos:R:3:\rfo\v:S:1\"\nC 0 0 0\n"), ParseError,
                     "test.xyz:3: expected 5 columns (Properties=species:S:1:pos:R:3: fo :S:1) "
                     "for atom 0, got 4");
}
