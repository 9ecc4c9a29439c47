// tricell coordination: coordination number and nearest bonded neighbour of every atom, with one
// cutoff for all pairs and/or cutoffs per pair of elements.
#include <cstdio>
#include <cstdlib>
#include <string>

#include <tricell/error.hpp>
#include <tricell/io/coordination.hpp>

#include "cli.hpp"

namespace tricell::cli {

namespace {

const char* const help =
    R"(usage: tricell coordination FILE (--cutoff R | --bond A-B=R ...) [--max-pairs N]
                            [--input-format cif|xyz|poscar]

For every atom, counts the neighbours j (periodic images included) at distance d < cutoff,
where the cutoff of a pair of elements is the --bond value given for it, else --cutoff; a pair
with neither does not count. --bond is unordered (Si-O=1.8 also sets O-Si) and may be repeated.

Prints a first line '# i element label cn nearest' and then one tab-separated line per atom:
its 0-based index (file order; for a CIF, the expanded unit cell), element, site label,
coordination number and the shortest counted distance (nan when it has no neighbour).

Options:
  --cutoff R          cutoff for every pair of elements not given by --bond (Angstrom)
  --bond A-B=R        cutoff for the elements A and B, e.g. --bond Si-O=1.8 (repeatable)
  --max-pairs N       refuse a search of more than N pairs before allocating it (default
                      500000000; 0 = no limit)
  --input-format F    cif, xyz or poscar, instead of the guess from the file name
  -h, --help          this help
)";

io::BondCutoff parse_bond(const Arguments& arguments, const std::string& text) {
    const std::size_t equals = text.find('=');
    const std::size_t dash = text.find('-');
    if (equals == std::string::npos || dash == std::string::npos || dash == 0 ||
        dash + 1 >= equals || equals + 1 >= text.size()) {
        arguments.fail("--bond expects A-B=R such as Si-O=1.8, got '" + text + "'");
    }
    io::BondCutoff bond;
    bond.a = text.substr(0, dash);
    bond.b = text.substr(dash + 1, equals - dash - 1);
    const std::string number = text.substr(equals + 1);
    char* end = nullptr;
    bond.cutoff = std::strtod(number.c_str(), &end);
    if (end == number.c_str() || *end != '\0') {
        arguments.fail("--bond expects A-B=R with a number R, got '" + text + "'");
    }
    return bond;
}

} // namespace

int run_coordination(const std::vector<std::string>& args) {
    Arguments arguments("coordination", args);
    std::string file;
    io::ReadOptions read_options;
    io::CoordinationOptions options;
    bool have_cutoff = false;
    while (arguments.next()) {
        if (arguments.flag("--help") || arguments.flag("-h")) {
            std::fputs(help, stdout);
            return 0;
        }
        if (arguments.option("--cutoff")) {
            options.cutoff = arguments.real();
            have_cutoff = true;
            if (!(options.cutoff > 0)) {
                throw InvalidArgument("cutoff must be > 0 (got " + brief(options.cutoff) + ")");
            }
        } else if (arguments.option("--bond")) {
            options.bonds.push_back(parse_bond(arguments, arguments.value()));
        } else if (take_max_pairs(arguments, options.max_pairs)) {
        } else if (!take_input(arguments, read_options, file)) {
            arguments.unknown();
        }
    }
    require_file(arguments, file);
    if (!have_cutoff && options.bonds.empty()) {
        arguments.fail("missing --cutoff R or --bond A-B=R");
    }
    options.validate();

    const io::Structure structure = io::read_structure(file, read_options);
    const std::vector<io::Coordination> result = io::coordination(structure, options);
    std::string text = "# i element label cn nearest\n";
    for (std::size_t k = 0; k < result.size(); ++k) {
        text += std::to_string(k) + "\t" + structure.species[k] + "\t" + structure.labels[k] +
                "\t" + std::to_string(result[k].count) + "\t" +
                (result[k].count == 0 ? std::string("nan") : brief(result[k].nearest)) + "\n";
    }
    Output out("");
    out.write(text);
    out.commit();
    return 0;
}

} // namespace tricell::cli
