// Truncated files never crash a reader: every prefix of every fixture and sample file cut at a
// line boundary (and, for the small samples, at every byte) either parses or throws a
// tricell::ParseError. Any other exception, or a crash, fails.
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include <tricell/error.hpp>
#include <tricell/io/structure.hpp>

#include "support/fixtures.hpp"

namespace {

// Parses every prefix of `text` ending at the given cut points; counts the outcomes.
void check_prefixes(const std::string& text, const std::string& name,
                    const std::vector<std::size_t>& cuts, std::size_t& parsed,
                    std::size_t& rejected) {
    for (std::size_t cut : cuts) {
        const std::string prefix = text.substr(0, cut);
        try {
            tricell::io::parse_structure(prefix, name);
            ++parsed;
        } catch (const tricell::ParseError& e) {
            ++rejected;
            EXPECT_EQ(std::string(e.what()).rfind(name + ":", 0), 0u) << e.what();
            EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos) << e.what();
        } catch (const std::exception& e) {
            ADD_FAILURE() << name << " cut at byte " << cut << ": not a ParseError: " << e.what();
        }
    }
}

std::vector<std::size_t> line_cuts(const std::string& text) {
    std::vector<std::size_t> cuts{0};
    for (std::size_t k = 0; k < text.size(); ++k) {
        if (text[k] == '\n') {
            cuts.push_back(k + 1);
        }
    }
    return cuts;
}

TEST(Truncation, EveryFixtureCutAtEveryLine) {
    for (const std::string& name : tricell::test::fixture_names()) {
        const std::string text = tricell::test::read_text(tricell::test::fixtures_dir() +
                                                          "/structures/" + name + ".cif");
        std::size_t parsed = 0, rejected = 0;
        check_prefixes(text, name + ".cif", line_cuts(text), parsed, rejected);
        EXPECT_GT(rejected, 0u) << name;
        EXPECT_GT(parsed, 0u) << name; // at least the whole file
    }
}

TEST(Truncation, SamplesCutAtEveryByte) {
    const std::string data = tricell::test::source_dir() + "/tests/io/data/";
    for (const char* file : {"quartz.cif", "si.vasp", "water.xyz", "graphene.extxyz"}) {
        const std::string text = tricell::test::read_text(data + file);
        std::vector<std::size_t> cuts;
        for (std::size_t k = 0; k <= text.size(); ++k) {
            cuts.push_back(k);
        }
        std::size_t parsed = 0, rejected = 0;
        check_prefixes(text, file, cuts, parsed, rejected);
        EXPECT_GT(rejected, 0u) << file;
    }
}

TEST(Truncation, PoscarVariantsCutAtEveryLine) {
    const std::string text = "Fe O, selective, Cartesian\n-120\n4 0 0\n0 5 0\n1 0 6\nFe_pv O\n2 1\n"
                             "Selective dynamics\nCartesian\n0 0 0 T T T\n1 1 1 F F F\n"
                             "2 2 2 T F T\n\n0 0 0\n0 0 0\n0 0 0\n";
    std::size_t parsed = 0, rejected = 0;
    check_prefixes(text, "CONTCAR", line_cuts(text), parsed, rejected);
    EXPECT_GT(rejected, 0u);
    EXPECT_GT(parsed, 0u);
}

} // namespace
