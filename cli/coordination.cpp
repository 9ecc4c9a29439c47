// tricell coordination: coordination number and nearest bonded neighbour of every atom, with one
// cutoff for all pairs and/or cutoffs per pair of elements.
#include <cstdio>
#include <cstdlib>
#include <map>
#include <string>

#include <tricell/error.hpp>
#include <tricell/io/coordination.hpp>

#include "cli.hpp"
#include "plot.hpp"

namespace tricell::cli {

// The text of 'tricell coordination --help', for the row of dispatch.cpp's table.
std::string coordination_help() {
    return R"(usage: tricell coordination FILE (--cutoff R | --bond A-B=R ...) [--summary]
                            [--plot PATH.svg|PATH.png] [--max-pairs N] [--max-bytes N]
                            [--input-format cif|xyz|poscar]

For every atom, counts the neighbours j (periodic images included) at distance d < cutoff,
where the cutoff of a pair of elements is the --bond value given for it, else --cutoff; a pair
with neither does not count. --bond is unordered (Si-O=1.8 also sets O-Si) and may be repeated.

Prints a first line '# i element label cn nearest mean' and then one tab-separated line per
atom: its 0-based index (file order; for a CIF, the expanded unit cell), element, site label,
coordination number, the shortest and the mean counted distance (nan when it has no
neighbour).

With --summary, prints one line per element instead, in order of first appearance, under
'# element atoms mean_cn mean_bond histogram': the number of atoms, their mean coordination
number, the mean length of their counted bonds (nan when none) and the histogram of their
coordination numbers as cn:atoms items separated by commas ("4:3" is three atoms with four
neighbours).

Options:
  --cutoff R          cutoff for every pair of elements not given by --bond (Angstrom)
  --bond A-B=R        cutoff for the elements A and B, e.g. --bond Si-O=1.8 (repeatable)
  --summary           the per-element summary instead of the per-atom table
  --plot PATH         draw the histogram of coordination numbers per element into PATH, an
                      SVG (*.svg) or PNG (*.png) image, completely or not at all
  --max-pairs N       refuse a search of more than N pairs before allocating it (default
                      500000000; 0 = no limit)
  --max-bytes N       refuse a search whose list would pass N bytes of memory (a suffix K, M,
                      G or T counts powers of 1024: 16G) before allocating it (default three
                      quarters of the memory tricell may use; 0 = no limit)
  --input-format F    cif, xyz or poscar, instead of the guess from the file name
  -h, --help          this help
)";
}

namespace {

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

// The atoms of one element: how many have each coordination number, and their bonds.
struct ElementSummary {
    std::string element;
    std::size_t atoms = 0;
    std::map<std::size_t, std::size_t> histogram; // coordination number -> atoms
    std::size_t bonds = 0;
    double bond_length_sum = 0;
};

// One summary per element, in order of first appearance.
std::vector<ElementSummary> summarise(const io::Structure& structure,
                                      const std::vector<io::Coordination>& result) {
    std::vector<ElementSummary> out;
    std::map<std::string, std::size_t> index;
    for (std::size_t k = 0; k < result.size(); ++k) {
        const auto [at, added] = index.emplace(structure.species[k], out.size());
        if (added) {
            out.push_back(ElementSummary{structure.species[k], 0, {}, 0, 0});
        }
        ElementSummary& e = out[at->second];
        ++e.atoms;
        ++e.histogram[result[k].count];
        if (result[k].count > 0) {
            e.bonds += result[k].count;
            e.bond_length_sum += result[k].mean * double(result[k].count);
        }
    }
    return out;
}

std::string summary_table(const std::vector<ElementSummary>& summary) {
    std::string text = "# element atoms mean_cn mean_bond histogram\n";
    for (const ElementSummary& e : summary) {
        text += e.element + "\t" + std::to_string(e.atoms) + "\t" +
                brief(double(e.bonds) / double(e.atoms)) + "\t" +
                (e.bonds == 0 ? std::string("nan") : brief(e.bond_length_sum / double(e.bonds))) +
                "\t";
        const char* separator = "";
        for (const auto& [cn, atoms] : e.histogram) {
            text += separator + std::to_string(cn) + ":" + std::to_string(atoms);
            separator = ",";
        }
        text += "\n";
    }
    return text;
}

Plot histogram_plot(const std::string& file, const std::vector<ElementSummary>& summary) {
    Plot plot;
    plot.kind = Plot::Kind::bars;
    plot.title = "Coordination numbers, " + file;
    plot.x_label = "coordination number";
    plot.y_label = "atoms";
    for (const ElementSummary& e : summary) {
        Series series{e.element, {}, {}};
        for (const auto& [cn, atoms] : e.histogram) {
            series.x.push_back(double(cn));
            series.y.push_back(double(atoms));
        }
        plot.series.push_back(std::move(series));
    }
    return plot;
}

} // namespace

int run_coordination(Arguments& arguments) {
    std::string file;
    io::ReadOptions read_options;
    io::CoordinationOptions options;
    bool have_cutoff = false;
    bool summary = false;
    std::string plot_path;
    while (arguments.next()) {
        if (arguments.printed_help()) {
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
        } else if (arguments.flag("--summary")) {
            summary = true;
        } else if (take_plot(arguments, plot_path)) {
        } else if (take_max_pairs(arguments, options.max_pairs)) {
        } else if (take_max_bytes(arguments, options.max_bytes)) {
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
    const std::vector<ElementSummary> elements = summarise(structure, result);
    if (!plot_path.empty()) {
        write_plot(histogram_plot(file, elements), plot_path);
    }
    std::string text;
    if (summary) {
        text = summary_table(elements);
    } else {
        text = "# i element label cn nearest mean\n";
        for (std::size_t k = 0; k < result.size(); ++k) {
            const bool none = result[k].count == 0;
            text += std::to_string(k) + "\t" + structure.species[k] + "\t" + structure.labels[k] +
                    "\t" + std::to_string(result[k].count) + "\t" +
                    (none ? std::string("nan") : brief(result[k].nearest)) + "\t" +
                    (none ? std::string("nan") : brief(result[k].mean)) + "\n";
        }
    }
    Output out("");
    out.write(text);
    out.commit();
    return 0;
}

} // namespace tricell::cli
