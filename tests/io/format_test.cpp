// Format detection, file access errors, element symbols and formulas.
#include <filesystem>
#include <fstream>
#include <string>

#include <gtest/gtest.h>

#include <tricell/error.hpp>
#include <tricell/io/structure.hpp>

#include "../support/expect_throw_msg.hpp"
#include "support/fixtures.hpp"

namespace {

using tricell::io::Format;
using tricell::io::format_from_name;

TEST(Format, FromFileName) {
    EXPECT_EQ(format_from_name("quartz.cif"), Format::cif);
    EXPECT_EQ(format_from_name("dir.d/QUARTZ.CIF"), Format::cif);
    EXPECT_EQ(format_from_name("a.xyz"), Format::xyz);
    EXPECT_EQ(format_from_name("a.extxyz"), Format::xyz);
    EXPECT_EQ(format_from_name("POSCAR"), Format::poscar);
    EXPECT_EQ(format_from_name("run/CONTCAR"), Format::poscar);
    EXPECT_EQ(format_from_name("POSCAR_relaxed"), Format::poscar);
    EXPECT_EQ(format_from_name("si.vasp"), Format::poscar);
    EXPECT_EQ(format_from_name("si.poscar"), Format::poscar);
}

TEST(Format, UnknownExtensionIsAParseError) {
    EXPECT_THROW_MSG(format_from_name("data/structure.txt"), tricell::ParseError,
                     "data/structure.txt: unknown file extension '.txt', expected *.cif, *.xyz, "
                     "*.extxyz, *.vasp, *.poscar, POSCAR or CONTCAR (or give the format "
                     "explicitly)");
    EXPECT_THROW_MSG(format_from_name("structure"), tricell::ParseError,
                     "structure: no file extension, expected *.cif");
    EXPECT_THROW_MSG(tricell::io::read_structure("missing.pdb"), tricell::ParseError,
                     "missing.pdb: unknown file extension '.pdb'");
}

TEST(Format, ByName) {
    EXPECT_EQ(tricell::io::parse_format("CIF"), Format::cif);
    EXPECT_EQ(tricell::io::parse_format("extxyz"), Format::xyz);
    EXPECT_EQ(tricell::io::parse_format("vasp"), Format::poscar);
    EXPECT_STREQ(tricell::io::format_name(Format::poscar), "poscar");
    EXPECT_THROW_MSG(tricell::io::parse_format("pdb"), tricell::InvalidArgument,
                     "unknown format 'pdb', expected cif, xyz, extxyz, poscar or vasp");
}

TEST(Format, ExplicitFormatOverridesTheName) {
    tricell::io::ReadOptions options;
    options.format = Format::xyz;
    const auto s = tricell::io::parse_structure("1\n\nHe 0 0 0\n", "atoms.txt", options);
    EXPECT_EQ(s.species, (std::vector<std::string>{"He"}));
}

TEST(ReadStructure, ReadsFiles) {
    const auto s =
        tricell::io::read_structure(tricell::test::source_dir() + "/examples/data/quartz.cif");
    EXPECT_EQ(s.size(), 9u);
    EXPECT_EQ(s.source, tricell::test::source_dir() + "/examples/data/quartz.cif");
}

TEST(ReadStructure, MissingFileAndDirectory) {
    EXPECT_THROW_MSG(tricell::io::read_structure("/nonexistent/x.cif"), tricell::ParseError,
                     "/nonexistent/x.cif: cannot open file (No such file or directory)");
    const std::string dir = std::filesystem::temp_directory_path().string() + "/tricell-dir.cif";
    std::filesystem::create_directories(dir);
    EXPECT_THROW_MSG(tricell::io::read_structure(dir), tricell::ParseError,
                     dir + ": cannot read: is a directory, expected a file");
    std::filesystem::remove(dir);
}

TEST(ElementSymbol, CanonicalCaseAndNumbers) {
    using tricell::io::element_symbol;
    EXPECT_EQ(element_symbol("si"), "Si");
    EXPECT_EQ(element_symbol("SI"), "Si");
    EXPECT_EQ(element_symbol("O"), "O");
    EXPECT_EQ(element_symbol("14"), "");
    EXPECT_EQ(element_symbol("14", true), "Si");
    EXPECT_EQ(element_symbol("0", true), "");
    EXPECT_EQ(element_symbol("Xx"), "");
    EXPECT_EQ(element_symbol("X"), "");
    EXPECT_EQ(element_symbol("Si1"), "");
    EXPECT_EQ(element_symbol(""), "");
}

TEST(Formula, HillOrderWeightedByOccupancy) {
    tricell::io::Structure s;
    s.species = {"O", "Si", "O", "H", "C", "H"};
    s.occupancies = {1, 1, 1, 1, 1, 1};
    EXPECT_EQ(tricell::io::formula(s), "C H2 O2 Si");
    s.species = {"O", "Si", "O", "H", "Fe", "H"};
    s.occupancies = {1, 1, 1, 0.5, 0.942, 0.5};
    EXPECT_EQ(tricell::io::formula(s), "Fe0.942 H O2 Si");
    EXPECT_DOUBLE_EQ(tricell::io::occupied_count(s), 4.942);
}

} // namespace
