// libFuzzer harness for the `tricell` command line, called in-process through
// tricell::cli::run() (cli/dispatch.cpp). The input is the argument list, one
// argument per line ("neighbors\nquartz.cif\n--cutoff=3\n").
//
// The command runs in a scratch directory holding a few small structure files (copied from
// fixtures/ and tests/io/data/ at start-up, restored before each input when a command changed
// one, anything else the command wrote removed after it), with standard output sent to /dev/null.
// So that every input stays small and fast, the harness sets --max-pairs 100000 itself and skips
// inputs that name a path outside the scratch directory ('/' in an argument), override
// --max-pairs, or ask for more than 3 bench repeats, 8 threads or 100000 RDF bins (--max-pairs
// bounds the pairs of rdf and of neighbors --nearest too). Plots (--plot) are written into the
// scratch directory and removed like any other output.
//
// What counts as a failure: a crash, a sanitizer report, a hang or a large allocation, an
// exception escaping run(), or an exit status other than 0, 1 or 2.
#include <dirent.h>
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "cli.hpp"

namespace {

// The scratch directory's files: name -> contents.
std::vector<std::pair<std::string, std::string>> files;

std::string slurp(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    std::ostringstream text;
    text << in.rdbuf();
    return text.str();
}

// Puts the file back as it was, writing only when a command changed it (or removed it): on ext4
// a truncate-and-rewrite flushes the file to disk at close, which was 60% of the harness's time
// (76 inputs per second) when every file was rewritten before every input.
void restore(const std::string& name, const std::string& text) {
    if (slurp(name) == text) {
        return;
    }
    std::ofstream out(name, std::ios::binary | std::ios::trunc);
    out << text;
}

bool known(const std::string& name) {
    for (const auto& file : files) {
        if (file.first == name) {
            return true;
        }
    }
    return false;
}

char scratch[] = "/tmp/tricell-cli-fuzz.XXXXXX";

void remove_others() {
    char here[sizeof scratch + 1];
    if (::getcwd(here, sizeof here) == nullptr || std::string(here) != scratch) {
        return; // only ever clean the scratch directory
    }
    DIR* dir = ::opendir(".");
    if (dir == nullptr) {
        return;
    }
    std::vector<std::string> extra;
    while (const dirent* entry = ::readdir(dir)) {
        const std::string name = entry->d_name;
        if (name != "." && name != ".." && !known(name)) {
            extra.push_back(name);
        }
    }
    ::closedir(dir);
    for (const std::string& name : extra) {
        std::remove(name.c_str());
    }
}

// A real number > limit, for the --repeat, --threads and --bins guards (strtod as the CLI reads
// it).
bool above(const std::string& value, double limit) {
    char* end = nullptr;
    const double x = std::strtod(value.c_str(), &end);
    return !(x <= limit);
}

bool acceptable(const std::vector<std::string>& args) {
    for (std::size_t k = 0; k < args.size(); ++k) {
        const std::string& arg = args[k];
        const std::string next = k + 1 < args.size() ? args[k + 1] : "";
        if (arg.find('/') != std::string::npos || arg.find("--max-pairs") != std::string::npos ||
            arg.find('\0') != std::string::npos) {
            return false;
        }
        for (const auto& [option, limit] :
             {std::pair{"--repeat", 3.0}, {"--threads", 8.0}, {"--bins", 1e5}}) {
            const std::string name = option;
            if ((arg == name && above(next, limit)) ||
                (arg.rfind(name + "=", 0) == 0 && above(arg.substr(name.size() + 1), limit))) {
                return false;
            }
        }
    }
    return true;
}

} // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
    const std::string root = TRICELL_SOURCE_DIR;
    files = {{"quartz.cif", slurp(root + "/tests/io/data/quartz.cif")},
             {"wustite.cif", slurp(root + "/tests/io/data/wustite.cif")},
             {"POSCAR", slurp(root + "/examples/data/POSCAR")},
             {"si.vasp", slurp(root + "/tests/io/data/si.vasp")},
             {"water.xyz", slurp(root + "/tests/io/data/water.xyz")},
             {"graphene.extxyz", slurp(root + "/tests/io/data/graphene.extxyz")}};
    if (::mkdtemp(scratch) == nullptr || ::chdir(scratch) != 0) {
        std::perror("cli_fuzzer: scratch directory");
        std::abort();
    }
    std::atexit([] {
        files.clear();
        remove_others();
        if (::chdir("/") == 0) {
            ::rmdir(scratch);
        }
    });
    if (std::freopen("/dev/null", "w", stdout) == nullptr) {
        std::abort();
    }
    return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    std::vector<std::string> args;
    std::string arg;
    for (std::size_t k = 0; k < size; ++k) {
        if (data[k] == '\n') {
            args.push_back(arg);
            arg.clear();
        } else {
            arg += char(data[k]);
        }
    }
    if (!arg.empty()) {
        args.push_back(arg);
    }
    if (!acceptable(args)) {
        return -1; // not added to the corpus
    }
    if (!args.empty() && (args[0] == "neighbors" || args[0] == "neighbours" ||
                          args[0] == "coordination" || args[0] == "bench" || args[0] == "rdf")) {
        args.insert(args.begin() + 1, "--max-pairs=100000");
    }
    for (const auto& [name, text] : files) {
        restore(name, text);
    }
    const int status = tricell::cli::run(args);
    std::fflush(stdout);
    remove_others();
    if (status < 0 || status > 2) {
        std::fprintf(stderr, "cli_fuzzer: exit status %d\n", status);
        std::abort();
    }
    return 0;
}
