// The table of subcommands: run() picks the command named by the first argument, calls it and
// turns every exception into one line on stderr and an exit status. main() only converts argv;
// the fuzzer (tests/fuzz/cli_fuzzer.cpp) calls run() in-process.
//
// The usage text (tricell --help), the choice of the handler and the "unknown command" error
// all come from the table, so a new subcommand is one row here plus its own file.
//
// Exit status: 0 on success, 1 when the input or a value is rejected (a bad file, a cutoff
// <= 0), 2 when the command line cannot be parsed, 3 when `neighbors --verify` finds the list
// wrong (verify_failed). Errors are one line on stderr:
// "tricell: FILE:LINE: what is wrong" or "tricell: what is wrong".
#include <algorithm>
#include <cstdio>
#include <exception>
#include <string>
#include <vector>

#include <tricell/error.hpp>

#include "cli.hpp"

namespace tricell::cli {

// Each command's file defines its help text and its handler.
std::string neighbors_help();
int run_neighbors(Arguments& arguments);
std::string info_help();
int run_info(Arguments& arguments);
std::string coordination_help();
int run_coordination(Arguments& arguments);
std::string rdf_help();
int run_rdf(Arguments& arguments);
std::string bench_help();
int run_bench(Arguments& arguments);

namespace {

// The subcommands, in the order of the usage text: name, another accepted spelling, the lines
// of the usage text (arguments and summary), the help text and the handler.
const std::vector<Command>& commands() {
    static const std::vector<Command> table = {
        {"neighbors",
         "neighbours",
         {{"FILE --cutoff R", "all pairs closer than R, with image shifts and vectors"},
          {"FILE --nearest K", "the K nearest neighbours of every atom"}},
         neighbors_help,
         run_neighbors},
        {"info",
         nullptr,
         {{"FILE", "formula, cell, volume, widths, space group, Niggli cell"}},
         info_help,
         run_info},
        {"coordination",
         nullptr,
         {{"FILE --cutoff R", "coordination number and bond lengths of every atom, or per "
                              "element (--summary), with a histogram plot (--plot)"}},
         coordination_help,
         run_coordination},
        {"rdf",
         nullptr,
         {{"FILE --rmax R --bins N", "g(r) and n(r), total and partial, over every frame of FILE"}},
         rdf_help,
         run_rdf},
        {"bench",
         nullptr,
         {{"FILE --cutoff R", "time the neighbour list (pairs per second, peak memory)"}},
         bench_help,
         run_bench},
    };
    return table;
}

// "usage: ...", one line per usage line of the table (the summaries aligned three columns
// past the longest "NAME ARGS"), then what every command shares.
std::string usage() {
    std::size_t longest = 0;
    for (const Command& command : commands()) {
        for (const UsageLine& line : command.usage) {
            longest = std::max(longest, std::string(command.name).size() + 1 +
                                            std::string(line.args).size());
        }
    }
    const std::size_t column = 2 + longest + 3;
    std::string text = "usage: tricell COMMAND FILE [OPTIONS]\n\nCommands:\n";
    for (const Command& command : commands()) {
        for (const UsageLine& line : command.usage) {
            std::string left = std::string("  ") + command.name + " " + line.args;
            left.resize(column, ' ');
            text += left + wrap(line.summary, column, column) + "\n";
        }
    }
    return text + R"(
FILE is a CIF (*.cif), an extended XYZ (*.xyz, *.extxyz) or a VASP 5 POSCAR (POSCAR, CONTCAR,
*.vasp, *.poscar); --input-format cif|xyz|poscar overrides the guess from the name.
Run 'tricell COMMAND --help' for the options of a command.

Exit status: 0 on success, 1 for a rejected input or value, 2 for a malformed command line,
3 when 'neighbors --verify' finds a difference.
)";
}

const Command* find_command(const std::string& name) {
    for (const Command& command : commands()) {
        if (name == command.name || (command.alias != nullptr && name == command.alias)) {
            return &command;
        }
    }
    return nullptr;
}

[[noreturn]] void unknown_command(const std::string& name) {
    std::vector<std::string> names;
    for (const Command& command : commands()) {
        names.push_back(command.name);
    }
    throw UsageError("unknown command '" + name + "', expected " + choices(names) +
                     " (see tricell --help)");
}

// A refused pair or memory limit in the command's words: the limit is the option --max-pairs
// or --max-bytes, where 0 lifts it.
std::string pair_limit_message(const PairLimitError& e) {
    if (e.which() == PairLimitError::Limit::bytes) {
        return e.message_for("--max-bytes " + e.limit_text(), "--max-bytes");
    }
    return e.message_for("--max-pairs " + std::to_string(e.limit()), "--max-pairs") +
           " (0 = no limit)";
}

void one_line(std::string text) {
    for (char& c : text) {
        if (c == '\n' || c == '\r') {
            c = ' ';
        }
    }
    std::fprintf(stderr, "tricell: %s\n", text.c_str());
}

} // namespace

int run(const std::vector<std::string>& args) {
    if (args.empty()) {
        std::fputs(usage().c_str(), stderr);
        return 2;
    }
    const std::string& name = args[0];
    try {
        if (name == "--help" || name == "-h" || name == "help") {
            std::fputs(usage().c_str(), stdout);
            return 0;
        }
        if (name == "--version") {
            std::printf("tricell %s\n", TRICELL_VERSION);
            return 0;
        }
        const Command* command = find_command(name);
        if (command == nullptr) {
            unknown_command(name);
        }
        Arguments arguments(*command, std::vector<std::string>(args.begin() + 1, args.end()));
        return command->run(arguments);
    } catch (const UsageError& e) {
        one_line(e.what());
        return 2;
    } catch (const PairLimitError& e) {
        one_line(pair_limit_message(e));
        return 1;
    } catch (const std::exception& e) {
        one_line(e.what());
        return 1;
    }
}

} // namespace tricell::cli
