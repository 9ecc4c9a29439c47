// tricell neighbors: the neighbour list of a structure file, as TSV, CSV or JSON.
#include <cstdio>
#include <optional>
#include <string>

#include <tricell/neighbor_list.hpp>

#include "cli.hpp"

namespace tricell::cli {

namespace {

const char* const help =
    R"(usage: tricell neighbors FILE --cutoff R [--half] [--sorted] [--format tsv|csv|json]
                         [--output PATH] [--max-pairs N] [--input-format cif|xyz|poscar]

Lists every pair (i, j, S) of atoms closer than R: D = x_j - x_i + H S with |D| < R, where x
are the positions in the order the file gives them (for a CIF, the symmetry-expanded unit
cell), H has the lattice vectors a, b, c as columns and S = (Sa, Sb, Sc) is the image shift
(0 along non-periodic axes). Indices are 0-based. An atom paired with its own periodic image is
listed; an atom with itself is not.

Options:
  --cutoff R          cutoff in the length unit of the file (Angstrom), R > 0 (required)
  --half              each pair once, oriented i < j (for i == j: S lexicographically positive)
  --sorted            sort by i, then j, then Sa, Sb, Sc (otherwise the order is unspecified)
  --format F          tsv (default), csv or json
  --output PATH       write to PATH, completely or not at all, instead of standard output
  --max-pairs N       refuse lists of more than N pairs before allocating them (default
                      500000000, about 14 GB; 0 = no limit)
  --input-format F    cif, xyz or poscar, instead of the guess from the file name
  -h, --help          this help

Output: tsv prints a first line '# i j Sa Sb Sc d Dx Dy Dz' and then one tab-separated line per
pair; csv prints the header 'i,j,Sa,Sb,Sc,d,Dx,Dy,Dz' and comma-separated lines; json prints
one object {"file", "atoms", "cutoff", "half", "pairs", "i", "j", "S", "d", "D"} with one array
per column (S and D as arrays of triples). Reals have 17 significant digits and read back
exactly.
)";

enum class TableFormat { tsv, csv, json };

std::string json_string(const std::string& text) {
    std::string out = "\"";
    for (char c : text) {
        if (c == '"' || c == '\\') {
            out += '\\';
            out += c;
        } else if (static_cast<unsigned char>(c) < 0x20) {
            char escaped[8];
            std::snprintf(escaped, sizeof escaped, "\\u%04x", c);
            out += escaped;
        } else {
            out += c;
        }
    }
    return out + "\"";
}

void write_table(Output& out, const NeighborList& list, char separator, bool comment_header) {
    const char s = separator;
    std::string buffer =
        comment_header ? "# i j Sa Sb Sc d Dx Dy Dz\n" : "i,j,Sa,Sb,Sc,d,Dx,Dy,Dz\n";
    char line[256];
    for (std::size_t k = 0; k < list.size(); ++k) {
        const Shift shift = list.shift(k);
        const Eigen::Vector3d d = list.vector(k);
        std::snprintf(line, sizeof line, "%u%c%u%c%d%c%d%c%d%c%.17g%c%.17g%c%.17g%c%.17g\n",
                      list.i()[k], s, list.j()[k], s, shift[0], s, shift[1], s, shift[2], s,
                      list.distances()[k], s, d[0], s, d[1], s, d[2]);
        buffer += line;
        if (buffer.size() > (1U << 16)) {
            out.write(buffer);
            buffer.clear();
        }
    }
    out.write(buffer);
}

void write_json(Output& out, const NeighborList& list, const std::string& file, std::size_t atoms,
                const NeighborOptions& options) {
    std::string buffer = "{\n  \"file\": " + json_string(file) +
                         ",\n  \"atoms\": " + std::to_string(atoms) +
                         ",\n  \"cutoff\": " + exact(options.cutoff) +
                         ",\n  \"half\": " + (options.half ? "true" : "false") +
                         ",\n  \"pairs\": " + std::to_string(list.size());
    const auto flush = [&] {
        if (buffer.size() > (1U << 16)) {
            out.write(buffer);
            buffer.clear();
        }
    };
    const auto array = [&](const char* key, auto&& item) {
        buffer += ",\n  \"";
        buffer += key;
        buffer += "\": [";
        for (std::size_t k = 0; k < list.size(); ++k) {
            buffer += k == 0 ? "" : ", ";
            buffer += item(k);
            flush();
        }
        buffer += "]";
    };
    array("i", [&](std::size_t k) { return std::to_string(list.i()[k]); });
    array("j", [&](std::size_t k) { return std::to_string(list.j()[k]); });
    array("S", [&](std::size_t k) {
        const Shift shift = list.shift(k);
        return "[" + std::to_string(shift[0]) + ", " + std::to_string(shift[1]) + ", " +
               std::to_string(shift[2]) + "]";
    });
    array("d", [&](std::size_t k) { return exact(list.distances()[k]); });
    array("D", [&](std::size_t k) {
        const Eigen::Vector3d d = list.vector(k);
        return "[" + exact(d[0]) + ", " + exact(d[1]) + ", " + exact(d[2]) + "]";
    });
    buffer += "\n}\n";
    out.write(buffer);
}

} // namespace

int run_neighbors(const std::vector<std::string>& args) {
    Arguments arguments("neighbors", args);
    std::string file;
    std::string output;
    bool have_cutoff = false;
    TableFormat format = TableFormat::tsv;
    io::ReadOptions read_options;
    NeighborOptions options;
    options.quantities.shifts = true;
    options.quantities.distances = true;
    options.quantities.vectors = true;
    while (arguments.next()) {
        if (arguments.flag("--help") || arguments.flag("-h")) {
            std::fputs(help, stdout);
            return 0;
        }
        if (arguments.option("--cutoff")) {
            options.cutoff = arguments.real();
            have_cutoff = true;
        } else if (arguments.flag("--half")) {
            options.half = true;
        } else if (arguments.flag("--sorted")) {
            options.sorted = true;
        } else if (arguments.option("--format")) {
            const std::string& name = arguments.value();
            if (name == "tsv") {
                format = TableFormat::tsv;
            } else if (name == "csv") {
                format = TableFormat::csv;
            } else if (name == "json") {
                format = TableFormat::json;
            } else {
                arguments.fail("--format must be tsv, csv or json, got '" + name + "'");
            }
        } else if (arguments.option("--output")) {
            output = arguments.value();
        } else if (take_max_pairs(arguments, options.max_pairs)) {
        } else if (!take_input(arguments, read_options, file)) {
            arguments.unknown();
        }
    }
    require_file(arguments, file);
    if (!have_cutoff) {
        arguments.fail("missing --cutoff R");
    }
    // compute_neighbors() validates the options (cutoff > 0) before any work.
    const io::Structure structure = io::read_structure(file, read_options);
    const NeighborList list = compute_neighbors(structure.box, structure.positions, options);

    Output out(output);
    switch (format) {
    case TableFormat::tsv:
        write_table(out, list, '\t', true);
        break;
    case TableFormat::csv:
        write_table(out, list, ',', false);
        break;
    case TableFormat::json:
        write_json(out, list, file, structure.size(), options);
        break;
    }
    out.commit();
    return 0;
}

} // namespace tricell::cli
