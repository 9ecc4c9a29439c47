// The `tricell` command on a large MD-like frame: every command finishes in time proportional
// to its input. The suite writes a random periodic frame of 10^5 atoms at liquid argon's
// density and an fcc crystal of 1372 atoms as extended XYZ into a fresh directory of the build
// tree, then runs each command on them. ctest's TIMEOUT (tests/cli/CMakeLists.txt) is the time
// limit; `info` must say that it skipped spglib's space-group search, whose time grows as
// atoms^2, and run it when --symmetry-max-atoms asks.
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include <gtest/gtest.h>

#include "run_command.hpp"

namespace {

namespace fs = std::filesystem;

using Result = tricell::test::CommandResult;

// Atoms of the random frame, and liquid argon's number density (atoms per cubic Angstrom).
constexpr std::size_t large_atoms = 100'000;
constexpr double density = 0.021;

// A portable generator (the same frame with every standard library): 64-bit LCG, top 53 bits.
class Uniform {
  public:
    double next() {
        state_ = state_ * 6364136223846793005ULL + 1442695040888963407ULL;
        return double(state_ >> 11) * 0x1p-53;
    }

  private:
    std::uint64_t state_ = 20261203;
};

void write_xyz_header(std::ofstream& out, std::size_t n, double length) {
    char lattice[160];
    std::snprintf(lattice, sizeof lattice, "Lattice=\"%.6f 0 0 0 %.6f 0 0 0 %.6f\"", length, length,
                  length);
    out << n << "\n" << lattice << " Properties=species:S:1:pos:R:3 pbc=\"T T T\"\n";
}

class LargeFrame : public ::testing::Test {
  protected:
    static void SetUpTestSuite() {
        // A directory of its own per process: ctest runs the tests of this suite in parallel.
        std::string pattern = std::string(TRICELL_LARGE_DIR) + "/cli-large-XXXXXX";
        fs::create_directories(TRICELL_LARGE_DIR);
        ASSERT_NE(::mkdtemp(pattern.data()), nullptr);
        dir_ = pattern;

        const std::size_t n = large_atoms;
        const double length = std::cbrt(double(n) / density);
        std::ofstream random(dir_ + "/random.xyz");
        write_xyz_header(random, n, length);
        Uniform uniform;
        char row[96];
        for (std::size_t k = 0; k < n; ++k) {
            const double x = uniform.next() * length, y = uniform.next() * length,
                         z = uniform.next() * length;
            std::snprintf(row, sizeof row, "Ar %.6f %.6f %.6f\n", x, y, z);
            random << row;
        }
        ASSERT_TRUE(random.good());

        // fcc argon, 7 x 7 x 7 conventional cells: above the default --symmetry-max-atoms.
        const int m = 7;
        const double a = 5.26;
        const double basis[4][3] = {{0, 0, 0}, {0.5, 0.5, 0}, {0.5, 0, 0.5}, {0, 0.5, 0.5}};
        std::ofstream crystal(dir_ + "/fcc.xyz");
        write_xyz_header(crystal, std::size_t(4 * m * m * m), a * m);
        for (int i = 0; i < m; ++i) {
            for (int j = 0; j < m; ++j) {
                for (int l = 0; l < m; ++l) {
                    for (const auto& b : basis) {
                        std::snprintf(row, sizeof row, "Ar %.6f %.6f %.6f\n", (i + b[0]) * a,
                                      (j + b[1]) * a, (l + b[2]) * a);
                        crystal << row;
                    }
                }
            }
        }
        ASSERT_TRUE(crystal.good());
    }
    static void TearDownTestSuite() { fs::remove_all(dir_); }

    // Runs `tricell ARGS` in the suite's directory and reports its wall time.
    static Result run(const std::string& args) {
        const auto start = std::chrono::steady_clock::now();
        Result result = tricell::test::run_command(TRICELL_CLI, args, dir_, dir_);
        const std::chrono::duration<double> took = std::chrono::steady_clock::now() - start;
        std::printf("tricell %s: %.2f s\n", args.c_str(), took.count());
        return result;
    }

    static std::string line_of(const std::string& text, const std::string& key) {
        const std::size_t at = text.find("\n" + key + ": ");
        if (at == std::string::npos) {
            return "";
        }
        const std::size_t end = text.find('\n', at + 1);
        return text.substr(at + 1, end - at - 1);
    }

    static std::string dir_;
};

std::string LargeFrame::dir_;

const std::string atoms = std::to_string(large_atoms);

TEST_F(LargeFrame, InfoOnABundledCrystalReportsTheSpaceGroup) {
    const Result r = run("info '" + tricell::test::source_dir() + "/examples/data/quartz.cif'");
    ASSERT_EQ(r.status, 0) << r.err;
    EXPECT_EQ(line_of(r.out, "space group"), "space group: P3_221 (154), symprec 0.001");
}

TEST_F(LargeFrame, InfoSkipsTheSpaceGroupSearchAndSaysWhy) {
    const Result r = run("info random.xyz");
    ASSERT_EQ(r.status, 0) << r.err;
    EXPECT_EQ(r.err, "");
    EXPECT_EQ(line_of(r.out, "atoms"), "atoms: " + atoms);
    EXPECT_EQ(line_of(r.out, "space group"),
              "space group: skipped: " + atoms +
                  " atoms, more than --symmetry-max-atoms 1000 (0 = no limit; spglib's time "
                  "grows as atoms^2)");
    EXPECT_NE(line_of(r.out, "niggli cell"), "");
    EXPECT_EQ(line_of(r.out, "occupancy"), "occupancy: all sites fully occupied");
}

TEST_F(LargeFrame, InfoSearchesAboveTheDefaultWhenAsked) {
    Result r = run("info fcc.xyz");
    ASSERT_EQ(r.status, 0) << r.err;
    EXPECT_EQ(line_of(r.out, "space group"),
              "space group: skipped: 1372 atoms, more than --symmetry-max-atoms 1000 (0 = no "
              "limit; spglib's time grows as atoms^2)");
    for (const char* limit : {"0", "1372"}) {
        r = run(std::string("info fcc.xyz --symmetry-max-atoms ") + limit);
        ASSERT_EQ(r.status, 0) << r.err;
        EXPECT_EQ(line_of(r.out, "space group"), "space group: Fm-3m (225), symprec 0.001")
            << limit;
    }
    r = run("info fcc.xyz --symmetry-max-atoms 1371");
    ASSERT_EQ(r.status, 0) << r.err;
    EXPECT_NE(line_of(r.out, "space group").find("skipped: 1372 atoms"), std::string::npos);
}

TEST_F(LargeFrame, Neighbors) {
    const Result r = run("neighbors random.xyz --cutoff 5 --output pairs.tsv");
    ASSERT_EQ(r.status, 0) << r.err;
    EXPECT_GT(fs::file_size(dir_ + "/pairs.tsv"), std::uintmax_t(large_atoms));
}

TEST_F(LargeFrame, NeighborsNearest) {
    const Result r = run("neighbors random.xyz --nearest 12 --output nearest.tsv");
    ASSERT_EQ(r.status, 0) << r.err;
    EXPECT_GT(fs::file_size(dir_ + "/nearest.tsv"), std::uintmax_t(12 * large_atoms));
}

TEST_F(LargeFrame, Rdf) {
    const Result r = run("rdf random.xyz --rmax 10 --bins 100");
    ASSERT_EQ(r.status, 0) << r.err;
    EXPECT_EQ(r.out.rfind("# r g n", 0), 0u) << r.out.substr(0, 80);
}

TEST_F(LargeFrame, Coordination) {
    const Result r = run("coordination random.xyz --cutoff 4");
    ASSERT_EQ(r.status, 0) << r.err;
    EXPECT_GT(r.out.size(), std::size_t(large_atoms));
}

TEST_F(LargeFrame, Bench) {
    const Result r = run("bench random.xyz --cutoff 5 --repeat 1");
    ASSERT_EQ(r.status, 0) << r.err;
    EXPECT_NE(r.out.find("pairs"), std::string::npos) << r.out;
}

} // namespace
