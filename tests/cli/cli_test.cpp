// The `tricell` command, run as a program: golden outputs of every command (tests/cli/golden;
// rewrite them with TRICELL_UPDATE_GOLDEN=1 after a deliberate change and review the diff),
// malformed inputs and usage errors (message and exit status), and --output writing its file
// completely or not at all. Commands run in tests/io/data with relative file names, so that
// messages and outputs do not depend on where the repository lives.
#include <sys/stat.h>
#include <sys/wait.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "run_command.hpp"

namespace {

namespace fs = std::filesystem;

using Result = tricell::test::CommandResult;

std::string data_dir() {
    return tricell::test::source_dir() + "/tests/io/data";
}
std::string golden_dir() {
    return tricell::test::source_dir() + "/tests/cli/golden";
}

class Cli : public ::testing::Test {
  protected:
    static void SetUpTestSuite() {
        std::string pattern = (fs::temp_directory_path() / "tricell-cli-XXXXXX").string();
        ASSERT_NE(::mkdtemp(pattern.data()), nullptr);
        scratch_ = pattern;
    }
    static void TearDownTestSuite() { fs::remove_all(scratch_); }

    // A fresh empty directory for one test's --output files.
    static std::string output_dir(const std::string& name) {
        const fs::path dir = fs::path(scratch_) / name;
        fs::remove_all(dir);
        fs::create_directories(dir);
        return dir.string();
    }

    static std::vector<std::string> listing(const std::string& dir) {
        std::vector<std::string> names;
        for (const auto& entry : fs::directory_iterator(dir)) {
            names.push_back(entry.path().filename().string());
        }
        std::sort(names.begin(), names.end());
        return names;
    }

    // Runs `tricell ARGS` in tests/io/data.
    static Result run(const std::string& args) {
        return tricell::test::run_command(TRICELL_CLI, args, data_dir(), scratch_);
    }

    static std::string scratch_;
};

std::string Cli::scratch_;

// Length of a number starting at s[k] (0 when none starts there). A number must not continue a
// word ("Si3" is text), so that formulas and labels compare as text.
std::size_t number_at(const std::string& s, std::size_t k) {
    if (k > 0 && (std::isalnum(static_cast<unsigned char>(s[k - 1])) || s[k - 1] == '_' ||
                  s[k - 1] == '.')) {
        return 0;
    }
    const char c = s[k];
    if (!(std::isdigit(static_cast<unsigned char>(c)) || c == '-' || c == '+' || c == '.')) {
        return 0;
    }
    const char* begin = s.c_str() + k;
    char* end = nullptr;
    std::strtod(begin, &end);
    return end > begin && std::isdigit(static_cast<unsigned char>(end[-1]))
               ? std::size_t(end - begin)
               : 0;
}

// Text equal except that numbers may differ by 1e-10 (absolute or relative): the last bits of a
// vector may change with the engine's arithmetic, the meaning may not.
bool same_output(const std::string& a, const std::string& b, std::string& where) {
    std::size_t i = 0, j = 0;
    while (i < a.size() && j < b.size()) {
        const std::size_t la = number_at(a, i), lb = number_at(b, j);
        if (la > 0 && lb > 0) {
            const double x = std::strtod(a.c_str() + i, nullptr);
            const double y = std::strtod(b.c_str() + j, nullptr);
            if (std::abs(x - y) > 1e-10 * std::max(1.0, std::max(std::abs(x), std::abs(y)))) {
                where = "numbers differ: " + a.substr(i, la) + " vs " + b.substr(j, lb);
                return false;
            }
            i += la;
            j += lb;
        } else if (a[i] == b[j]) {
            ++i;
            ++j;
        } else {
            where = "text differs at: '" + a.substr(i, 40) + "' vs '" + b.substr(j, 40) + "'";
            return false;
        }
    }
    if (i != a.size() || j != b.size()) {
        where = "lengths differ";
        return false;
    }
    return true;
}

void expect_golden(const std::string& name, const std::string& actual) {
    const std::string path = golden_dir() + "/" + name;
    if (std::getenv("TRICELL_UPDATE_GOLDEN") != nullptr) {
        std::ofstream(path, std::ios::binary) << actual;
        return;
    }
    ASSERT_TRUE(fs::exists(path)) << path << " is missing (run with TRICELL_UPDATE_GOLDEN=1)";
    const std::string expected = tricell::test::read_text(path);
    std::string where;
    EXPECT_TRUE(same_output(expected, actual, where))
        << "golden " << name << ": " << where << "\n--- actual ---\n"
        << actual;
}

void expect_success_golden(const Result& r, const std::string& golden) {
    EXPECT_EQ(r.status, 0) << r.err;
    EXPECT_EQ(r.err, "");
    expect_golden(golden, r.out);
}

// ---- golden outputs -----------------------------------------------------------------------

TEST_F(Cli, NeighborsTsv) {
    expect_success_golden(run("neighbors quartz.cif --cutoff 1.7 --sorted"),
                          "neighbors_quartz.tsv");
}

TEST_F(Cli, NeighborsHalfCsv) {
    expect_success_golden(run("neighbors quartz.cif --cutoff=1.7 --sorted --half --format csv"),
                          "neighbors_quartz_half.csv");
}

// --verify writes the same table and one verdict line on stderr (status 3 would be a mismatch).
TEST_F(Cli, NeighborsVerify) {
    struct Case {
        const char* args;
        const char* golden;
        const char* verdict;
    };
    const Case cases[] = {
        {"neighbors quartz.cif --cutoff 1.7 --sorted --verify", "neighbors_quartz.tsv",
         "tricell: verify: ok: 24 entries match 24 pairs of brute force (full list)\n"},
        {"neighbors quartz.cif --cutoff=1.7 --sorted --half --format csv --verify --threads 2",
         "neighbors_quartz_half.csv",
         "tricell: verify: ok: 12 entries match 12 pairs of brute force (half list)\n"},
        {"neighbors graphene.extxyz --cutoff 1.5 --sorted --verify", "neighbors_graphene.tsv",
         nullptr},
        {"neighbors water.xyz --cutoff 1.6 --sorted --verify", "neighbors_water.tsv", nullptr},
    };
    for (const Case& c : cases) {
        SCOPED_TRACE(c.args);
        const Result r = run(c.args);
        EXPECT_EQ(r.status, 0) << r.err;
        expect_golden(c.golden, r.out);
        if (c.verdict != nullptr) {
            EXPECT_EQ(r.err, c.verdict);
        } else {
            EXPECT_EQ(r.err.rfind("tricell: verify: ok: ", 0), 0u) << r.err;
        }
    }
    // Many images of a small cell: still brute force, still ok.
    const Result big = run("neighbors si.vasp --cutoff 9 --half --verify --output " +
                           output_dir("verify") + "/si.tsv");
    EXPECT_EQ(big.status, 0) << big.err;
    EXPECT_EQ(big.err.rfind("tricell: verify: ok: ", 0), 0u) << big.err;
}

TEST_F(Cli, NeighborsJsonFromPoscar) {
    expect_success_golden(run("neighbors si.vasp --cutoff 2.5 --sorted --format json"),
                          "neighbors_si.json");
}

TEST_F(Cli, NeighborsOfASlabAndOfAMolecule) {
    expect_success_golden(run("neighbors graphene.extxyz --cutoff 1.5 --sorted"),
                          "neighbors_graphene.tsv");
    expect_success_golden(run("neighbors water.xyz --cutoff 1.6 --sorted"), "neighbors_water.tsv");
}

TEST_F(Cli, Info) {
    expect_success_golden(run("info quartz.cif"), "info_quartz.txt");
    expect_success_golden(run("info wustite.cif --symprec 1e-4"), "info_wustite.txt");
    expect_success_golden(run("info water.xyz"), "info_water.txt");
    expect_success_golden(run("info structure.txt --input-format cif"), "info_structure_txt.txt");
}

TEST_F(Cli, Coordination) {
    expect_success_golden(run("coordination quartz.cif --cutoff 2"), "coordination_quartz.tsv");
    expect_success_golden(run("coordination quartz.cif --bond Si-O=1.7 --bond O-O=2.7"),
                          "coordination_quartz_bonds.tsv");
}

TEST_F(Cli, CoordinationSummary) {
    expect_success_golden(run("coordination quartz.cif --bond Si-O=1.7 --bond O-O=2.7 --summary"),
                          "coordination_quartz_summary.tsv");
}

// The k nearest neighbours, in every format.
TEST_F(Cli, NeighborsNearest) {
    expect_success_golden(run("neighbors quartz.cif --nearest 5"), "nearest_quartz.tsv");
    expect_success_golden(run("neighbors si.vasp --nearest 20 --format csv"), "nearest_si.csv");
    expect_success_golden(run("neighbors water.xyz --nearest 2 --format json"),
                          "nearest_water.json");
}

// The k nearest are the k shortest entries of the full list at a cutoff that holds more than
// k per atom: each listed (j, S) is in the list with the same distance (to rounding: the two
// searches may round the last bit differently), nearest first, and no entry left out is
// shorter than the k-th.
TEST_F(Cli, NeighborsNearestAgreesWithTheCutoffList) {
    const std::size_t k = 7, atoms = 9;
    const Result nearest = run("neighbors quartz.cif --nearest 7");
    const Result all = run("neighbors quartz.cif --cutoff 4");
    ASSERT_EQ(nearest.status, 0);
    ASSERT_EQ(all.status, 0);
    using Key = std::tuple<long, long, long, long, long>; // i, j, S
    const auto rows = [](const std::string& text) {
        std::vector<std::pair<Key, double>> out;
        std::istringstream lines(text);
        std::string line;
        std::getline(lines, line);
        while (std::getline(lines, line)) {
            std::istringstream f(line);
            long i, j, a, b, c;
            double d;
            f >> i >> j >> a >> b >> c >> d;
            out.emplace_back(Key{i, j, a, b, c}, d);
        }
        return out;
    };
    std::map<Key, double> listed;
    std::vector<std::size_t> per_atom(atoms, 0);
    for (const auto& [key, d] : rows(all.out)) {
        listed[key] = d;
        ++per_atom[std::size_t(std::get<0>(key))];
    }
    const auto chosen = rows(nearest.out);
    ASSERT_EQ(chosen.size(), atoms * k);
    std::set<Key> taken;
    for (std::size_t e = 0; e < chosen.size(); ++e) {
        const auto& [key, d] = chosen[e];
        SCOPED_TRACE(e);
        EXPECT_EQ(std::size_t(std::get<0>(key)), e / k);
        ASSERT_EQ(listed.count(key), 1u);
        EXPECT_NEAR(listed[key], d, 1e-12);
        if (e % k > 0) {
            EXPECT_GE(d, chosen[e - 1].second);
        }
        taken.insert(key);
    }
    for (const auto& [key, d] : listed) {
        const std::size_t i = std::size_t(std::get<0>(key));
        ASSERT_GT(per_atom[i], k); // the cutoff holds more than k: the k-th is inside
        if (taken.count(key) == 0) {
            EXPECT_GE(d, chosen[i * k + k - 1].second - 1e-12);
        }
    }
}

// g(r) over the frames of the bundled argon trajectory, total and partial, in every format.
TEST_F(Cli, Rdf) {
    expect_success_golden(run("rdf ../../../examples/data/argon.xyz --rmax 10 --bins 20"),
                          "rdf_argon.tsv");
    expect_success_golden(run("rdf ../../../examples/data/argon.xyz --rmax 6 --bins 6 --pair "
                              "Ar-Ar --format json --threads 2"),
                          "rdf_argon.json");
    expect_success_golden(run("rdf quartz.cif --rmax 4 --bins 8 --pair Si-O --pair O-O --format "
                              "csv"),
                          "rdf_quartz.csv");
}

// rmax beyond the cell: with every image, g(r) of a crystal keeps its peaks and n(r) keeps
// growing like the volume (ASE refuses rmax above half the cell height here).
TEST_F(Cli, RdfBeyondTheCell) {
    const Result r = run("rdf si.vasp --rmax 12 --bins 24");
    ASSERT_EQ(r.status, 0) << r.err;
    std::istringstream lines(r.out);
    std::string line;
    std::getline(lines, line);
    EXPECT_EQ(line, "# r g n");
    double last_n = -1, r_value = 0, g = 0, n = 0;
    std::size_t rows = 0;
    while (lines >> r_value >> g >> n) {
        EXPECT_GE(n, last_n);
        last_n = n;
        ++rows;
    }
    EXPECT_EQ(rows, 24u);
    EXPECT_GT(last_n, 100); // about 4/3 pi 12^3 * 8 / 5.43^3 = 360 neighbours within 12 A
}

TEST_F(Cli, Help) {
    expect_success_golden(run("--help"), "help.txt");
    expect_success_golden(run("rdf --help"), "help_rdf.txt");
    expect_success_golden(run("neighbors --help"), "help_neighbors.txt");
    expect_success_golden(run("info -h"), "help_info.txt");
    expect_success_golden(run("coordination --help"), "help_coordination.txt");
    const Result version = run("--version");
    EXPECT_EQ(version.status, 0);
    EXPECT_EQ(version.out.rfind("tricell ", 0), 0u);
}

TEST_F(Cli, NeighborsTsvRealsReadBackExactlyAndMatchTheirVectors) {
    const Result r = run("neighbors quartz.cif --cutoff 3.5");
    ASSERT_EQ(r.status, 0);
    std::istringstream lines(r.out);
    std::string line;
    std::getline(lines, line);
    EXPECT_EQ(line, "# i j Sa Sb Sc d Dx Dy Dz");
    std::size_t pairs = 0;
    while (std::getline(lines, line)) {
        std::istringstream fields(line);
        std::vector<std::string> f;
        for (std::string w; std::getline(fields, w, '\t');) {
            f.push_back(w);
        }
        ASSERT_EQ(f.size(), 9u) << line;
        double real[4];
        for (int k = 0; k < 4; ++k) {
            // The shortest text of the double it reads back as (to_chars, general format).
            const std::string& text = f[5 + std::size_t(k)];
            real[k] = std::strtod(text.c_str(), nullptr);
            char again[32];
            *std::to_chars(again, again + sizeof again, real[k], std::chars_format::general).ptr =
                '\0';
            EXPECT_EQ(text, again);
        }
        EXPECT_NEAR(std::sqrt(real[1] * real[1] + real[2] * real[2] + real[3] * real[3]), real[0],
                    1e-12);
        EXPECT_LT(real[0], 3.5);
        ++pairs;
    }
    EXPECT_GT(pairs, 50u);
}

// Tables formatted on several threads (blocks of 32768 rows) are the same text as on one.
TEST_F(Cli, ThreadsNeverChangeTheText) {
    const Result rows = run("neighbors si.vasp --cutoff 80 --half --format csv");
    ASSERT_GT(std::count(rows.out.begin(), rows.out.end(), '\n'), 2 * 32768); // several blocks
    for (const std::string command :
         {"neighbors si.vasp --cutoff 80 --sorted", "neighbors si.vasp --cutoff 80 --format json",
          "neighbors si.vasp --cutoff 80 --half --format csv",
          "neighbors quartz.cif --nearest 9000 --format json"}) {
        SCOPED_TRACE(command);
        const Result one = run(command + " --threads 1");
        ASSERT_EQ(one.status, 0) << one.err;
        for (const char* threads : {"2", "3", "0"}) {
            SCOPED_TRACE(threads);
            EXPECT_TRUE(run(command + " --threads " + threads).out == one.out);
        }
    }
}

// ---- malformed inputs ---------------------------------------------------------------------

struct BadInput {
    const char* file;
    const char* message;
};

const BadInput bad_inputs[] = {
    {"empty.cif", "tricell: empty.cif: file is empty, expected a CIF data block (data_NAME)\n"},
    {"truncated.cif",
     "tricell: truncated.cif:43: incomplete loop row: the loop of _atom_site_label has 7 tags but "
     "its last row has 4 values (truncated file or missing value?)\n"},
    {"missing_cell.cif",
     "tricell: missing_cell.cif:14: _cell_angle_beta is missing in data_alpha_quartz, expected "
     "the cell (_cell_length_a/b/c, _cell_angle_alpha/beta/gamma)\n"},
    {"non_numeric.cif", "tricell: non_numeric.cif:42: _atom_site_fract_y of site 'Si1' must be a "
                        "number, got 'zero'\n"},
    {"structure.txt", "tricell: structure.txt: unknown file extension '.txt', expected *.cif, "
                      "*.xyz, *.extxyz, *.vasp, *.poscar, POSCAR or CONTCAR (or give the format "
                      "explicitly)\n"},
    {"no_such_file.cif", "tricell: no_such_file.cif: cannot open file (No such file or "
                         "directory)\n"},
};

TEST_F(Cli, MalformedInputsFailWithOneLineAndStatus1) {
    for (const BadInput& bad : bad_inputs) {
        for (const std::string command :
             {"neighbors FILE --cutoff 3", "info FILE", "coordination FILE --cutoff 2"}) {
            std::string args = command;
            args.replace(args.find("FILE"), 4, bad.file);
            SCOPED_TRACE(args);
            const Result r = run(args);
            EXPECT_EQ(r.status, 1);
            EXPECT_EQ(r.out, "");
            EXPECT_EQ(r.err, bad.message);
        }
    }
}

TEST_F(Cli, EmptyPoscarAndXyz) {
    const std::string dir = output_dir("empty");
    std::ofstream(dir + "/POSCAR").flush();
    std::ofstream(dir + "/empty.xyz") << "\n";
    Result r = run("info " + dir + "/POSCAR");
    EXPECT_EQ(r.status, 1);
    EXPECT_EQ(r.err, "tricell: " + dir +
                         "/POSCAR: file is empty, expected a POSCAR (comment, "
                         "scale factor, lattice vectors, element names, counts, positions)\n");
    r = run("info " + dir + "/empty.xyz");
    EXPECT_EQ(r.status, 1);
    EXPECT_EQ(r.err, "tricell: " + dir +
                         "/empty.xyz: file is empty, expected an XYZ file (number "
                         "of atoms, comment line, one line per atom)\n");
}

// ---- usage and value errors ---------------------------------------------------------------

struct BadCommand {
    const char* args;
    int status;
    const char* message;
};

const BadCommand bad_commands[] = {
    {"frobnicate x.cif", 2,
     "tricell: unknown command 'frobnicate', expected neighbors, info, coordination, rdf or bench "
     "(see tricell --help)\n"},
    {"neighbors --cutoff 3", 2,
     "tricell: neighbors: missing FILE (see tricell neighbors --help)\n"},
    {"neighbors quartz.cif", 2,
     "tricell: neighbors: missing --cutoff R or --nearest K (see tricell neighbors --help)\n"},
    {"neighbors quartz.cif --cutoff", 2,
     "tricell: neighbors: --cutoff needs a value (see tricell neighbors --help)\n"},
    {"neighbors quartz.cif --cutoff abc", 2,
     "tricell: neighbors: --cutoff expects a number, got 'abc' (see tricell neighbors --help)\n"},
    {"neighbors quartz.cif --cutoff 3 --frob", 2,
     "tricell: neighbors: unknown option '--frob' (see tricell neighbors --help)\n"},
    {"neighbors quartz.cif other.cif --cutoff 3", 2,
     "tricell: neighbors: unexpected argument 'other.cif' (see tricell neighbors --help)\n"},
    {"neighbors quartz.cif --cutoff 3 --format xml", 2,
     "tricell: neighbors: --format must be tsv, csv or json, got 'xml' (see tricell neighbors "
     "--help)\n"},
    {"neighbors quartz.cif --cutoff 3 --half=yes", 2,
     "tricell: neighbors: --half takes no value (see tricell neighbors --help)\n"},
    {"neighbors quartz.cif --cutoff 3 --input-format pdb", 2,
     "tricell: neighbors: --input-format: unknown format 'pdb', expected cif, xyz, extxyz, poscar "
     "or vasp (see tricell neighbors --help)\n"},
    {"info", 2, "tricell: info: missing FILE (see tricell info --help)\n"},
    {"info quartz.cif --symprec x", 2,
     "tricell: info: --symprec expects a number, got 'x' (see tricell info --help)\n"},
    {"info quartz.cif --symmetry-max-atoms -1", 2,
     "tricell: info: --symmetry-max-atoms must be a whole number in [0, 10000000], got '-1' (see "
     "tricell info --help)\n"},
    {"info quartz.cif --symmetry-max-atoms", 2,
     "tricell: info: --symmetry-max-atoms needs a value (see tricell info --help)\n"},
    {"coordination quartz.cif", 2,
     "tricell: coordination: missing --cutoff R or --bond A-B=R (see tricell coordination "
     "--help)\n"},
    {"coordination quartz.cif --bond SiO=2", 2,
     "tricell: coordination: --bond expects A-B=R such as Si-O=1.8, got 'SiO=2' (see tricell "
     "coordination --help)\n"},
    {"coordination quartz.cif --bond Si-O=two", 2,
     "tricell: coordination: --bond expects A-B=R with a number R, got 'Si-O=two' (see tricell "
     "coordination --help)\n"},
    {"neighbors quartz.cif --cutoff 3 --max-pairs -1", 2,
     "tricell: neighbors: --max-pairs must be a whole number in [0, 2^53], got '-1' (see tricell "
     "neighbors --help)\n"},
    {"coordination quartz.cif --cutoff 3 --max-pairs 2.5", 2,
     "tricell: coordination: --max-pairs must be a whole number in [0, 2^53], got '2.5' (see "
     "tricell coordination --help)\n"},
    {"bench quartz.cif --cutoff 3 --max-pairs=", 2,
     "tricell: bench: --max-pairs needs a value (see tricell bench --help)\n"},
    {"neighbors quartz.cif --nearest 3 --cutoff 2", 2,
     "tricell: neighbors: --nearest takes no --cutoff, --half, --sorted or --verify (see tricell "
     "neighbors "
     "--help)\n"},
    {"neighbors quartz.cif --nearest 0", 2,
     "tricell: neighbors: --nearest must be a whole number in [1, 2147483648], got '0' (see "
     "tricell neighbors --help)\n"},
    {"neighbors quartz.cif --cutoff 3 --threads 2.5", 2,
     "tricell: neighbors: --threads must be a whole number in [0, 1024], got '2.5' (see tricell "
     "neighbors --help)\n"},
    {"rdf quartz.cif --bins 10", 2, "tricell: rdf: missing --rmax R (see tricell rdf --help)\n"},
    {"rdf quartz.cif --rmax 3", 2, "tricell: rdf: missing --bins N (see tricell rdf --help)\n"},
    {"rdf --rmax 3 --bins 3", 2, "tricell: rdf: missing FILE (see tricell rdf --help)\n"},
    {"rdf quartz.cif --rmax 3 --bins 0", 2,
     "tricell: rdf: --bins must be a whole number in [1, 100000000], got '0' (see tricell rdf "
     "--help)\n"},
    {"rdf quartz.cif --rmax 3 --bins 10 --pair SiO", 2,
     "tricell: rdf: --pair expects two species A-B such as O-H, got 'SiO' (see tricell rdf "
     "--help)\n"},
    {"rdf quartz.cif --rmax 3 --bins 10 --plot g.pdf", 2,
     "tricell: rdf: --plot: cannot tell the image format of 'g.pdf', expected a name ending in "
     ".svg or .png (see tricell rdf --help)\n"},
    {"coordination quartz.cif --cutoff 2 --plot histogram", 2,
     "tricell: coordination: --plot: cannot tell the image format of 'histogram', expected a "
     "name ending in .svg or .png (see tricell coordination --help)\n"},
    {"rdf quartz.cif --rmax 3 --bins 10 --pair Si-Qq", 1,
     "tricell: --pair Si-Qq: no atom of species 'Qq' in quartz.cif (species: Si, O)\n"},
    {"rdf quartz.cif --rmax -3 --bins 10", 1, "tricell: --rmax must be finite and > 0 (got -3)\n"},
    {"rdf water.xyz --rmax 3 --bins 10", 1,
     "tricell: water.xyz (frame 0): Rdf: axis a of the frame is not periodic; g(r) is normalised "
     "by the cell volume, which an open axis does not define\n"},
    {"rdf truncated.cif --rmax 3 --bins 10", 1,
     "tricell: truncated.cif:43: incomplete loop row: the loop of _atom_site_label has 7 tags but "
     "its last row has 4 values (truncated file or missing value?) (frame 0)\n"},
    {"neighbors quartz.cif --cutoff -1", 1, "tricell: cutoff must be > 0 (got -1)\n"},
    {"neighbors quartz.cif --cutoff 0", 1, "tricell: cutoff must be > 0 (got 0)\n"},
    {"info quartz.cif --symprec -1", 1, "tricell: symprec must be > 0 (got -1)\n"},
    {"coordination quartz.cif --cutoff 0", 1, "tricell: cutoff must be > 0 (got 0)\n"},
    {"coordination quartz.cif --bond Si-Qq=2", 1, "tricell: bond Si-Qq: unknown element 'Qq'\n"},
    {"neighbors quartz.cif --cutoff 3 --input-format xyz", 1,
     "tricell: quartz.cif:1: expected the number of atoms (an integer >= 0), got '#'\n"},
};

TEST_F(Cli, UsageErrorsExit2AndValueErrorsExit1) {
    for (const BadCommand& bad : bad_commands) {
        SCOPED_TRACE(bad.args);
        const Result r = run(bad.args);
        EXPECT_EQ(r.status, bad.status);
        EXPECT_EQ(r.out, "");
        EXPECT_EQ(r.err, bad.message);
    }
}

// A memory limit refuses the search before it runs, in the command's words: the message names
// the bytes and --max-bytes (not the library's NeighborOptions::max_bytes); 0 lifts it, and a
// suffix counts powers of 1024.
TEST_F(Cli, MaxBytesRefusesLargerSearchesWithStatus1) {
    for (const std::string command :
         {"neighbors quartz.cif --cutoff 3", "neighbors quartz.cif --cutoff 3 --sorted",
          "coordination quartz.cif --cutoff 3", "bench quartz.cif --cutoff 3 --repeat 1"}) {
        SCOPED_TRACE(command);
        const Result refused = run(command + " --max-bytes 100");
        EXPECT_EQ(refused.status, 1);
        EXPECT_EQ(refused.out, "");
        EXPECT_EQ(refused.err.find("tricell: cutoff 3 would give about "), 0u) << refused.err;
        EXPECT_NE(refused.err.find(" bytes at its peak ("), std::string::npos) << refused.err;
        EXPECT_NE(refused.err.find(", more than --max-bytes 100 (9.31e-08 GiB); raise "
                                   "--max-bytes to allow it (0 = no limit)\n"),
                  std::string::npos)
            << refused.err;
        EXPECT_EQ(refused.err.find("max_bytes"), std::string::npos) << refused.err;
        EXPECT_EQ(std::count(refused.err.begin(), refused.err.end(), '\n'), 1);
        EXPECT_EQ(run(command + " --max-bytes 0").status, 0);
        EXPECT_EQ(run(command + " --max-bytes 1M").status, 0);
    }
    for (const std::string value : {"-1", "1.5", "12X", "1e30", "G", "0.3K"}) {
        SCOPED_TRACE(value);
        const Result bad = run("neighbors quartz.cif --cutoff 3 --max-bytes '" + value + "'");
        EXPECT_EQ(bad.status, 2);
        EXPECT_EQ(bad.err, "tricell: neighbors: --max-bytes must be a whole number of bytes in "
                           "[0, 2^63], or a size with K, M, G or T (powers of 1024) such as 16G, "
                           "got '" +
                               value + "' (see tricell neighbors --help)\n");
    }
}

// A pair limit refuses the search before it runs, in the command's words: the message names
// --max-pairs (not the library's NeighborOptions::max_pairs); 0 lifts it.
TEST_F(Cli, MaxPairsRefusesLargerSearchesWithStatus1) {
    for (const std::string command :
         {"neighbors quartz.cif --cutoff 3", "coordination quartz.cif --cutoff 3",
          "bench quartz.cif --cutoff 3", "rdf quartz.cif --rmax 3 --bins 10",
          "neighbors quartz.cif --nearest 2"}) {
        SCOPED_TRACE(command);
        const Result refused = run(command + " --max-pairs 10");
        EXPECT_EQ(refused.status, 1);
        EXPECT_EQ(refused.out, "");
        EXPECT_NE(refused.err.find("more than --max-pairs 10"), std::string::npos) << refused.err;
        EXPECT_NE(refused.err.find("; raise --max-pairs to allow it (0 = no limit)\n"),
                  std::string::npos)
            << refused.err;
        EXPECT_EQ(refused.err.find("max_pairs"), std::string::npos) << refused.err;
        EXPECT_EQ(std::count(refused.err.begin(), refused.err.end(), '\n'), 1);
        EXPECT_EQ(run(command + " --max-pairs 0").status, 0);
        EXPECT_EQ(run(command + " --max-pairs 1000").status, 0);
    }
    // The default limit stops an absurd request before it runs (these would take hours).
    for (const std::string command :
         {"neighbors quartz.cif --cutoff 1000", "rdf quartz.cif --rmax 1000 --bins 10",
          "neighbors quartz.cif --nearest 100000000"}) {
        SCOPED_TRACE(command);
        const Result refused = run(command);
        EXPECT_EQ(refused.status, 1);
        EXPECT_NE(refused.err.find("more than --max-pairs 500000000"), std::string::npos)
            << refused.err;
    }
}

// bench times the list in the order asked for: the same pairs in every order, and the offsets
// (one per atom and one more) counted in the stored arrays of grouped and sorted output.
TEST_F(Cli, BenchReportsTheOrderAndCountsTheOffsets) {
    auto value = [](const std::string& out, const std::string& key) {
        const std::size_t at = out.find("\n" + key + " ");
        EXPECT_NE(at, std::string::npos) << key << " in " << out;
        const std::size_t start = at + key.size() + 2;
        return out.substr(start, out.find('\n', start) - start);
    };
    const Result search = run("bench quartz.cif --cutoff 3 --repeat 1");
    ASSERT_EQ(search.status, 0) << search.err;
    EXPECT_EQ(value(search.out, "order"), "search");
    for (const std::string order : {"grouped", "sorted"}) {
        SCOPED_TRACE(order);
        const Result r = run("bench quartz.cif --cutoff 3 --repeat 1 --" + order);
        ASSERT_EQ(r.status, 0) << r.err;
        EXPECT_EQ(value(r.out, "order"), order);
        EXPECT_EQ(value(r.out, "pairs"), value(search.out, "pairs"));
        EXPECT_EQ(std::stol(value(r.out, "list_bytes")) -
                      std::stol(value(search.out, "list_bytes")),
                  (std::stol(value(r.out, "atoms")) + 1) * long(sizeof(std::size_t)));
    }
    const Result both = run("bench quartz.cif --cutoff 3 --grouped --sorted");
    EXPECT_EQ(both.status, 2);
    EXPECT_NE(both.err.find("--grouped and --sorted exclude each other"), std::string::npos)
        << both.err;
}

TEST_F(Cli, NoArgumentsPrintsUsageAndExits2) {
    const Result r = run("");
    EXPECT_EQ(r.status, 2);
    EXPECT_EQ(r.out, "");
    EXPECT_EQ(r.err.rfind("usage: tricell COMMAND FILE [OPTIONS]\n", 0), 0u);
}

TEST_F(Cli, AFailedWriteToStandardOutputIsAnError) {
    const std::string err = scratch_ + "/stderr";
    const std::string command =
        "cd '" + data_dir() +
        "' && '" TRICELL_CLI "' neighbors quartz.cif --cutoff 3 > /dev/full 2> '" + err + "'";
    const int status = std::system(command.c_str());
    ASSERT_TRUE(WIFEXITED(status));
    EXPECT_EQ(WEXITSTATUS(status), 1);
    EXPECT_EQ(tricell::test::read_text(err),
              "tricell: cannot write to standard output (No space left on device)\n");
}

// ---- --plot -------------------------------------------------------------------------------

// Width and height from a PNG's IHDR chunk (after the 8-byte signature, length and type).
std::pair<unsigned, unsigned> png_size(const std::string& png) {
    const auto word = [&](std::size_t at) {
        unsigned v = 0;
        for (std::size_t k = 0; k < 4; ++k) {
            v = v << 8 | static_cast<unsigned char>(png[at + k]);
        }
        return v;
    };
    return {word(16), word(20)};
}

TEST_F(Cli, PlotsAreWrittenAsPngOrSvg) {
    const std::string dir = output_dir("plots");
    Result r =
        run("rdf ../../../examples/data/argon.xyz --rmax 8 --bins 40 --plot " + dir + "/g.png");
    EXPECT_EQ(r.status, 0) << r.err;
    const std::string png = tricell::test::read_text(dir + "/g.png");
    ASSERT_GT(png.size(), 24u);
    EXPECT_EQ(png.substr(0, 8), std::string("\x89PNG\r\n\x1a\n", 8));
    EXPECT_EQ(png.substr(12, 4), "IHDR");
    EXPECT_EQ(png_size(png), std::make_pair(640u, 480u));
    EXPECT_EQ(r.out.rfind("# r g n\n", 0), 0u); // the table still goes to standard output

    r = run("coordination quartz.cif --cutoff 2 --plot " + dir + "/cn.svg");
    EXPECT_EQ(r.status, 0) << r.err;
    const std::string svg = tricell::test::read_text(dir + "/cn.svg");
    EXPECT_EQ(svg.rfind("<?xml", 0), 0u);
    EXPECT_NE(svg.find("width=\"640pt\" height=\"480pt\""), std::string::npos);
    EXPECT_NE(svg.find("<path"), std::string::npos);
    EXPECT_EQ(listing(dir), (std::vector<std::string>{"cn.svg", "g.png"}));
}

TEST_F(Cli, PlotLeavesNothingBehindOnError) {
    const std::string dir = output_dir("plot-error");
    for (const std::string args :
         {"rdf truncated.cif --rmax 3 --bins 3", "rdf quartz.cif --rmax 3 --bins 3 --pair Si-Qq",
          "coordination quartz.cif --cutoff -1"}) {
        SCOPED_TRACE(args);
        const Result r = run(args + " --plot " + dir + "/plot.png");
        EXPECT_EQ(r.status, 1);
        EXPECT_TRUE(listing(dir).empty());
    }
    const Result r = run("rdf quartz.cif --rmax 3 --bins 3 --plot " + dir + "/no/such/g.svg");
    EXPECT_EQ(r.status, 1);
    EXPECT_EQ(r.err, "tricell: cannot create a temporary file for " + dir +
                         "/no/such/g.svg (No such file or directory)\n");
    EXPECT_EQ(r.out, "");
}

// ---- --output -----------------------------------------------------------------------------

TEST_F(Cli, OutputWritesTheFileAndNothingElse) {
    const std::string dir = output_dir("ok");
    const Result r =
        run("neighbors quartz.cif --cutoff 1.7 --sorted --output " + dir + "/pairs.tsv");
    EXPECT_EQ(r.status, 0) << r.err;
    EXPECT_EQ(r.out, "");
    EXPECT_EQ(listing(dir), (std::vector<std::string>{"pairs.tsv"}));
    EXPECT_EQ(tricell::test::read_text(dir + "/pairs.tsv"),
              run("neighbors quartz.cif --cutoff 1.7 --sorted").out);
    // The usual permissions of a new file (mkstemp alone would leave 0600).
    const mode_t mask = ::umask(0);
    ::umask(mask);
    struct stat info {};
    ASSERT_EQ(::stat((dir + "/pairs.tsv").c_str(), &info), 0);
    EXPECT_EQ(info.st_mode & 0777, 0666 & ~mask);
}

TEST_F(Cli, OutputIsReplacedWhole) {
    const std::string dir = output_dir("replace");
    std::ofstream(dir + "/pairs.json") << "old contents that are longer than the new ones\n";
    const Result r = run("neighbors si.vasp --cutoff 2.5 --sorted --format json --output " + dir +
                         "/pairs.json");
    EXPECT_EQ(r.status, 0) << r.err;
    EXPECT_EQ(tricell::test::read_text(dir + "/pairs.json"),
              run("neighbors si.vasp --cutoff 2.5 --sorted --format json").out);
    EXPECT_EQ(listing(dir), (std::vector<std::string>{"pairs.json"}));
}

TEST_F(Cli, OutputLeavesNothingBehindOnError) {
    const std::string dir = output_dir("error");
    for (const std::string args :
         {"neighbors truncated.cif --cutoff 3", "neighbors empty.cif --cutoff 3",
          "neighbors quartz.cif --cutoff -1", "neighbors quartz.cif --cutoff 3 --format xml",
          "neighbors quartz.cif --nearest 3 --max-pairs 5", "rdf truncated.cif --rmax 3 --bins 3",
          "rdf quartz.cif --rmax 3 --bins 3 --pair O-Qq"}) {
        SCOPED_TRACE(args);
        const Result r = run(args + " --output " + dir + "/pairs.tsv");
        EXPECT_NE(r.status, 0);
        EXPECT_EQ(r.out, "");
        EXPECT_TRUE(listing(dir).empty());
    }
}

TEST_F(Cli, OutputKeepsAnExistingFileOnError) {
    const std::string dir = output_dir("keep");
    std::ofstream(dir + "/pairs.tsv") << "previous result\n";
    const Result r = run("neighbors non_numeric.cif --cutoff 3 --output " + dir + "/pairs.tsv");
    EXPECT_EQ(r.status, 1);
    EXPECT_EQ(tricell::test::read_text(dir + "/pairs.tsv"), "previous result\n");
    EXPECT_EQ(listing(dir), (std::vector<std::string>{"pairs.tsv"}));
}

TEST_F(Cli, OutputIntoAMissingDirectoryFails) {
    const std::string dir = output_dir("missing");
    const Result r = run("neighbors quartz.cif --cutoff 3 --output " + dir + "/no/such/pairs.tsv");
    EXPECT_EQ(r.status, 1);
    EXPECT_EQ(r.err, "tricell: cannot create a temporary file for " + dir +
                         "/no/such/pairs.tsv (No such file or directory)\n");
    EXPECT_TRUE(listing(dir).empty());
}

TEST_F(Cli, OutputOntoADirectoryFailsAndCleansUp) {
    const std::string dir = output_dir("onto");
    fs::create_directories(dir + "/target");
    const Result r = run("neighbors quartz.cif --cutoff 3 --output " + dir + "/target");
    EXPECT_EQ(r.status, 1);
    EXPECT_EQ(r.err.rfind("tricell: cannot write " + dir + "/target (", 0), 0u) << r.err;
    EXPECT_EQ(listing(dir), (std::vector<std::string>{"target"}));
}

} // namespace
