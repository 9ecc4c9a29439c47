// tricell info: a summary of a structure file (formula, cell, volume, widths, periodicity,
// space group and Niggli-reduced cell through spglib, partial occupancies).
//
// spglib's space-group search grows about as N^2 in the atom count (random and crystalline
// cells alike: 1000 atoms take under a second, 2000 about 4 s), so above
// --symmetry-max-atoms atoms (default_symmetry_max_atoms) it is skipped and the line says so;
// every other line costs O(N). While spglib runs, a status line on stderr says so (on a terminal).
#include <cmath>
#include <cstdio>
#include <map>
#include <string>
#include <utility>

#include <tricell/error.hpp>
#include <tricell/io/symmetry.hpp>

#include "cli.hpp"
#include "progress.hpp"

namespace tricell::cli {

// The text of 'tricell info --help', for the row of dispatch.cpp's table.
std::string info_help() {
    return R"(usage: tricell info FILE [--symprec X] [--symmetry-max-atoms N] [--quiet]
                    [--input-format cif|xyz|poscar]

Prints one 'key: value' line each for: the file and its format; the formula (Hill order, cell
contents weighted by occupancy); the number of atoms (sites); the cell parameters a, b, c,
alpha, beta, gamma (Angstrom, degrees) and the lattice vectors as rows; the volume; the
perpendicular widths (distances between opposite faces); the periodic axes; the space group
(Hermann-Mauguin symbol and number, found by spglib with tolerance X; atoms count as equivalent
when element and occupancy agree); the Niggli-reduced cell; and the partially occupied sites.

spglib's search takes time growing as the square of the atom count (under a second for 1000
atoms, about 4 s for 2000), so for more than N atoms the space group line says it was skipped and
why; --symmetry-max-atoms 0 searches whatever the size.

Options:
  --symprec X         symmetry tolerance in Angstrom for the space group (default 0.001)
  --symmetry-max-atoms N
                      search the space group only up to N atoms (default 1000, 0 = no limit)
  --quiet             no status line on stderr while spglib searches (shown only when stderr is
                      a terminal)
  --input-format F    cif, xyz or poscar, instead of the guess from the file name
  -h, --help          this help
)";
}

namespace {

// Above this many atoms the space group is not searched unless --symmetry-max-atoms says so.
constexpr std::size_t default_symmetry_max_atoms = 1000;

std::string parameters(const Box& box) {
    const LatticeParameters p = box.parameters();
    return "a=" + brief(p.a) + " b=" + brief(p.b) + " c=" + brief(p.c) +
           " alpha=" + brief(p.alpha) + " beta=" + brief(p.beta) + " gamma=" + brief(p.gamma);
}

// Components below 1e-12 of the vector's length print as 0 (cos 90 degrees is 6e-17, not 0).
std::string triple(const Eigen::Vector3d& v) {
    const auto shown = [&](double x) { return std::abs(x) < 1e-12 * v.norm() ? 0.0 : x; };
    return brief(shown(v[0])) + " " + brief(shown(v[1])) + " " + brief(shown(v[2]));
}

} // namespace

int run_info(Arguments& arguments) {
    std::string file;
    double symprec = 1e-3;
    std::size_t symmetry_max_atoms = default_symmetry_max_atoms;
    bool quiet = false;
    io::ReadOptions read_options;
    while (arguments.next()) {
        if (arguments.printed_help()) {
            return 0;
        }
        if (arguments.option("--symprec")) {
            symprec = arguments.real();
        } else if (arguments.option("--symmetry-max-atoms")) {
            symmetry_max_atoms = arguments.whole(0, io::ReadOptions().max_atoms);
        } else if (take_quiet(arguments, quiet)) {
        } else if (!take_input(arguments, read_options, file)) {
            arguments.unknown();
        }
    }
    require_file(arguments, file);
    if (!(symprec > 0)) {
        throw InvalidArgument("symprec must be > 0 (got " + brief(symprec) + ")");
    }

    const io::Structure s = io::read_structure(file, read_options);
    const Box& box = s.box;
    const bool periodic = box.periodicity().count() == 3;
    std::string text;
    const auto line = [&](const std::string& key, const std::string& value) {
        text += key + ": " + value + "\n";
    };
    line("file", file);
    line("format",
         io::format_name(read_options.format ? *read_options.format : io::format_from_name(file)));
    line("formula", s.size() == 0 ? "(no atoms)" : io::formula(s));
    line("atoms", std::to_string(s.size()));
    line("cell", parameters(box) + (box.periodicity().any() ? "" : " (frame of an open system)"));
    line("vector a", triple(box.vector(0)));
    line("vector b", triple(box.vector(1)));
    line("vector c", triple(box.vector(2)));
    line("volume", brief(box.volume()));
    line("perpendicular widths", triple(box.perpendicular_widths()));
    std::string axes;
    for (int axis = 0; axis < 3; ++axis) {
        if (box.periodic(axis)) {
            axes += std::string(axes.empty() ? "" : " ") + "abc"[axis];
        }
    }
    line("periodic", axes.empty() ? "none" : axes);

    if (!periodic) {
        line("space group", "n/a (needs a box periodic along a, b and c)");
        line("niggli cell", "n/a (needs a box periodic along a, b and c)");
    } else {
        if (symmetry_max_atoms != 0 && s.size() > symmetry_max_atoms) {
            line("space group", "skipped: " + std::to_string(s.size()) +
                                    " atoms, more than --symmetry-max-atoms " +
                                    std::to_string(symmetry_max_atoms) +
                                    " (0 = no limit; spglib's time grows as atoms^2)");
        } else {
            std::string group;
            Progress status("searching the space group of " + std::to_string(s.size()) +
                                " atoms (spglib)",
                            0, !quiet);
            status.show();
            try {
                const io::SpaceGroupInfo info = io::find_space_group(s, symprec);
                group = info.international + " (" + std::to_string(info.number) + ")";
            } catch (const Error& e) {
                group = std::string("not determined: ") + e.what();
            }
            status.finish();
            line("space group", group + ", symprec " + brief(symprec));
        }
        line("niggli cell", parameters(io::niggli_reduce(box)));
    }

    // Partially occupied sites, grouped by element and occupancy in order of appearance.
    std::vector<std::pair<std::string, double>> groups;
    std::map<std::pair<std::string, double>, std::size_t> sites;
    std::size_t partial = 0;
    for (std::size_t k = 0; k < s.size(); ++k) {
        if (s.occupancies[k] < 1) {
            const auto key = std::make_pair(s.species[k], s.occupancies[k]);
            if (sites[key]++ == 0) {
                groups.push_back(key);
            }
            ++partial;
        }
    }
    if (partial == 0) {
        line("occupancy", "all sites fully occupied");
    } else {
        std::string value = std::to_string(partial) + " of " + std::to_string(s.size()) +
                            " sites partially occupied:";
        for (std::size_t g = 0; g < groups.size(); ++g) {
            value += std::string(g == 0 ? " " : ", ") + groups[g].first + " " +
                     brief(groups[g].second) + " (" + std::to_string(sites[groups[g]]) + " sites)";
        }
        line("occupancy", value);
        line("occupied atoms", brief(io::occupied_count(s)));
    }

    Output out("");
    out.write(text);
    out.commit();
    return 0;
}

} // namespace tricell::cli
