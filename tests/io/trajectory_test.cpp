// io::FrameReader: every frame of a multi-frame extended XYZ file equals parse_structure() of
// that frame's text alone; errors name the file, the line in the whole file and the frame.
#include <cstdio>
#include <fstream>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include <tricell/error.hpp>
#include <tricell/io/structure.hpp>
#include <tricell/io/trajectory.hpp>

#include "../support/expect_throw_msg.hpp"

namespace {

using tricell::ParseError;
using tricell::io::FrameReader;
using tricell::io::parse_structure;
using tricell::io::Structure;

// A file under the build tree's temporary directory, removed at the end of the test.
class TempFile {
  public:
    TempFile(const std::string& name, const std::string& text)
        : path_(::testing::TempDir() + name) {
        std::ofstream(path_, std::ios::binary) << text;
    }
    ~TempFile() { std::remove(path_.c_str()); }
    const std::string& path() const { return path_; }

  private:
    std::string path_;
};

void expect_same(const Structure& got, const Structure& want) {
    ASSERT_EQ(got.size(), want.size());
    EXPECT_EQ(got.species, want.species);
    EXPECT_EQ(got.labels, want.labels);
    EXPECT_EQ(got.occupancies, want.occupancies);
    EXPECT_EQ(got.source, want.source);
    for (std::size_t k = 0; k < got.size(); ++k) {
        EXPECT_EQ(got.positions[k], want.positions[k]) << "atom " << k;
    }
    EXPECT_EQ(got.box.matrix(), want.box.matrix());
    EXPECT_EQ(got.box.periodicity(), want.box.periodicity());
}

// A random frame: 0 to 12 atoms, a random triclinic lattice (or none: an open system), random
// periodicity, extra columns, CRLF or LF endings.
std::string random_frame(std::mt19937_64& rng) {
    std::uniform_real_distribution<double> u(-1, 1);
    std::uniform_int_distribution<int> atoms(0, 12);
    std::bernoulli_distribution coin(0.5);
    const char* elements[] = {"H", "O", "Si", "Ar", "fe", "8"};
    const std::string end = coin(rng) ? "\r\n" : "\n";
    const int n = atoms(rng);
    std::ostringstream out;
    out.precision(17);
    out << n << end;
    const bool lattice = coin(rng);
    const bool forces = coin(rng);
    if (lattice) {
        out << "Lattice=\"" << 5 + u(rng) << " 0 0 " << u(rng) << ' ' << 6 + u(rng) << " 0 "
            << u(rng) << ' ' << u(rng) << ' ' << 7 + u(rng) << "\" pbc=\""
            << (coin(rng) ? 'T' : 'F') << ' ' << (coin(rng) ? 'T' : 'F') << " T\" ";
    }
    out << (forces ? "Properties=species:S:1:pos:R:3:forces:R:3" : "energy=-1.5") << end;
    for (int k = 0; k < n; ++k) {
        out << elements[rng() % 6] << ' ' << 10 * u(rng) << ' ' << 10 * u(rng) << ' '
            << 10 * u(rng);
        if (forces) {
            out << " 0.1 0.2 0.3";
        }
        out << end;
    }
    return out.str();
}

TEST(FrameReader, EveryFrameEqualsParseStructureOfItsText_RandomFiles) {
    for (std::uint64_t seed = 1; seed <= 60; ++seed) {
        SCOPED_TRACE(seed);
        std::mt19937_64 rng(seed);
        std::vector<std::string> frames(1 + rng() % 6);
        std::string text;
        for (std::string& frame : frames) {
            frame = random_frame(rng);
            text += frame;
        }
        text += std::string(rng() % 3, '\n'); // blank lines after the last frame are ignored
        const TempFile file("trajectory_random.xyz", text);
        FrameReader reader(file.path());
        Structure frame;
        for (std::size_t k = 0; k < frames.size(); ++k) {
            SCOPED_TRACE(k);
            ASSERT_TRUE(reader.next(frame));
            expect_same(frame, parse_structure(frames[k], file.path()));
            EXPECT_EQ(reader.frames_read(), k + 1);
        }
        EXPECT_FALSE(reader.next(frame));
        EXPECT_FALSE(reader.next(frame));
        EXPECT_EQ(reader.frames_read(), frames.size());
    }
}

TEST(FrameReader, ReadsTheBundledArgonTrajectory) {
    const std::string path = std::string(TRICELL_SOURCE_DIR) + "/examples/data/argon.xyz";
    std::ifstream in(path);
    std::stringstream whole;
    whole << in.rdbuf();
    // The frames as text, cut by their atom counts.
    std::vector<std::string> texts;
    std::string line;
    while (std::getline(whole, line)) {
        const int n = std::stoi(line);
        std::string frame = line + '\n';
        for (int k = 0; k < n + 1 && std::getline(whole, line); ++k) {
            frame += line + '\n';
        }
        texts.push_back(frame);
    }
    ASSERT_EQ(texts.size(), 10u);
    FrameReader reader(path);
    Structure frame;
    for (const std::string& text : texts) {
        ASSERT_TRUE(reader.next(frame));
        EXPECT_EQ(frame.size(), 256u);
        expect_same(frame, parse_structure(text, path));
    }
    EXPECT_FALSE(reader.next(frame));
    EXPECT_EQ(reader.frames_read(), 10u);
}

TEST(FrameReader, OtherFormatsAreOneFrame) {
    const std::string path = std::string(TRICELL_SOURCE_DIR) + "/examples/data/POSCAR";
    FrameReader reader(path);
    Structure frame;
    ASSERT_TRUE(reader.next(frame));
    expect_same(frame, tricell::io::read_structure(path));
    EXPECT_FALSE(reader.next(frame));
    EXPECT_EQ(reader.frames_read(), 1u);
}

TEST(FrameReader, ErrorsNameTheLineInTheFileAndTheFrame) {
    const std::string good = "2\nLattice=\"4 0 0 0 4 0 0 0 4\"\nAr 0 0 0\nAr 1 1 1\n";
    {
        // Frame 2's second atom (line 13) has an unknown element.
        const TempFile file("trajectory_bad.xyz", good + good + "2\n\nAr 0 0 0\nQq 1 1 1\n");
        FrameReader reader(file.path());
        Structure frame;
        ASSERT_TRUE(reader.next(frame));
        ASSERT_TRUE(reader.next(frame));
        EXPECT_THROW_MSG(reader.next(frame), ParseError,
                         file.path() + ":12: unknown element 'Qq' for atom 1");
        try {
            reader.next(frame);
            FAIL() << "next() after an error must throw again";
        } catch (const ParseError& e) {
            EXPECT_EQ(e.line(), 12u);
            EXPECT_NE(e.message().find("(frame 2)"), std::string::npos) << e.what();
        }
        EXPECT_EQ(reader.frames_read(), 2u);
        EXPECT_EQ(frame.size(), 2u); // the frame of the failed call is untouched
    }
    {
        const TempFile file("trajectory_short.xyz", good + "3\n\nAr 0 0 0\n");
        FrameReader reader(file.path());
        Structure frame;
        ASSERT_TRUE(reader.next(frame));
        EXPECT_THROW_MSG(reader.next(frame), ParseError,
                         file.path() + ":8: file ends after 1 of 3 atom lines (frame 1)");
    }
    {
        const TempFile file("trajectory_blank.xyz", good + "\n" + good);
        FrameReader reader(file.path());
        Structure frame;
        ASSERT_TRUE(reader.next(frame));
        EXPECT_THROW_MSG(reader.next(frame), ParseError,
                         file.path() + ":5: expected the number of atoms (an integer >= 0), got "
                                       "an empty line (frame 1)");
    }
    {
        const TempFile file("trajectory_count.xyz", good + "many\n\n");
        FrameReader reader(file.path());
        Structure frame;
        ASSERT_TRUE(reader.next(frame));
        EXPECT_THROW_MSG(reader.next(frame), ParseError, ":5: expected the number of atoms");
    }
    {
        tricell::io::ReadOptions options;
        options.max_atoms = 1;
        const TempFile file("trajectory_limit.xyz", good);
        FrameReader reader(file.path(), options);
        Structure frame;
        EXPECT_THROW_MSG(reader.next(frame), ParseError,
                         ":1: the file has 2 atoms, more than ReadOptions::max_atoms = 1 "
                         "(frame 0)");
    }
    {
        const TempFile file("trajectory_empty.xyz", "\n\n");
        FrameReader reader(file.path());
        Structure frame;
        EXPECT_THROW_MSG(reader.next(frame), ParseError, "file is empty");
    }
    EXPECT_THROW_MSG(FrameReader(::testing::TempDir() + "no_such_file.xyz"), ParseError,
                     "no_such_file.xyz: cannot open file");
    EXPECT_THROW_MSG(FrameReader("trajectory.dcd"), ParseError, "unknown file extension");
}

} // namespace
