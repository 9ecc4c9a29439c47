// The table of subcommands: run() picks the command named by the first argument, calls it and
// turns every exception into one line on stderr and an exit status. main() only converts argv;
// the fuzzer (tests/fuzz/cli_fuzzer.cpp) calls run() in-process.
//
// Exit status: 0 on success, 1 when the input or a value is rejected (a bad file, a cutoff
// <= 0), 2 when the command line cannot be parsed. Errors are one line on stderr:
// "tricell: FILE:LINE: what is wrong" or "tricell: what is wrong".
#include <cstdio>
#include <exception>
#include <string>
#include <vector>

#include <tricell/error.hpp>

#include "cli.hpp"

namespace {

const char* const usage = R"(usage: tricell COMMAND FILE [OPTIONS]

Commands:
  neighbors FILE --cutoff R      all pairs closer than R, with image shifts and vectors
  neighbors FILE --nearest K     the K nearest neighbours of every atom
  info FILE                      formula, cell, volume, widths, space group, Niggli cell
  coordination FILE --cutoff R   coordination number and bond lengths of every atom, or per
                                 element (--summary), with a histogram plot (--plot)
  rdf FILE --rmax R --bins N     g(r) and n(r), total and partial, over every frame of FILE
  bench FILE --cutoff R          time the neighbour list (pairs per second, peak memory)

FILE is a CIF (*.cif), an extended XYZ (*.xyz, *.extxyz) or a VASP 5 POSCAR (POSCAR, CONTCAR,
*.vasp, *.poscar); --input-format cif|xyz|poscar overrides the guess from the name.
Run 'tricell COMMAND --help' for the options of a command.

Exit status: 0 on success, 1 for a rejected input or value, 2 for a malformed command line.
)";

// The library names its own fields ("raise NeighborOptions::max_pairs to allow it",
// "RdfOptions::rmax must be ..."); a command-line user sets options instead, so the message
// names them.
std::string in_command_words(std::string text) {
    const auto replace = [&](const std::string& from, const std::string& to) {
        for (std::size_t at = text.find(from); at != std::string::npos;
             at = text.find(from, at + to.size())) {
            text.replace(at, from.size(), to);
        }
    };
    replace("raise NeighborOptions::max_pairs to allow it",
            "raise --max-pairs to allow it (0 = no limit)");
    replace("max_pairs = ", "--max-pairs ");
    replace("RdfOptions::rmax", "--rmax");
    replace("RdfOptions::bins", "--bins");
    return text;
}

void one_line(const char* message) {
    std::string text = in_command_words(message);
    for (char& c : text) {
        if (c == '\n' || c == '\r') {
            c = ' ';
        }
    }
    std::fprintf(stderr, "tricell: %s\n", text.c_str());
}

} // namespace

namespace tricell::cli {

int run(const std::vector<std::string>& args) {
    if (args.empty()) {
        std::fputs(usage, stderr);
        return 2;
    }
    const std::string& command = args[0];
    const std::vector<std::string> rest(args.begin() + 1, args.end());
    try {
        if (command == "--help" || command == "-h" || command == "help") {
            std::fputs(usage, stdout);
            return 0;
        }
        if (command == "--version") {
            std::printf("tricell %s\n", TRICELL_VERSION);
            return 0;
        }
        if (command == "neighbors" || command == "neighbours") {
            return run_neighbors(rest);
        }
        if (command == "info") {
            return run_info(rest);
        }
        if (command == "coordination") {
            return run_coordination(rest);
        }
        if (command == "bench") {
            return run_bench(rest);
        }
        if (command == "rdf") {
            return run_rdf(rest);
        }
        throw UsageError("unknown command '" + command +
                         "', expected neighbors, info, coordination, rdf or bench (see "
                         "tricell --help)");
    } catch (const UsageError& e) {
        one_line(e.what());
        return 2;
    } catch (const std::exception& e) {
        one_line(e.what());
        return 1;
    }
}

} // namespace tricell::cli
