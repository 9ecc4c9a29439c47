// VASP 5 POSCAR/CONTCAR reader.
//
// Line 1 is a comment. Line 2 is the scale: one number s > 0 multiplies the lattice vectors,
// s < 0 means "scale the lattice so that the volume is |s|", and three positive numbers scale
// the x, y and z components separately (VASP 6). Lines 3-5 are the lattice vectors a, b, c as
// rows. Line 6 names the elements (POTCAR suffixes such as "Fe_pv" or "Si/abc" are dropped; a
// line of numbers here is the VASP 4 layout, which has no names and is refused), line 7 gives
// as many counts. An optional line starting with S/s is "Selective dynamics". The next line
// picks Direct (first letter D/d) or Cartesian (C/c/K/k) coordinates, followed by one line per
// atom with three numbers; anything after them (T/F flags, comments) is ignored, as is anything
// after the last atom (velocities, predictor-corrector data). Cartesian coordinates are scaled
// like the lattice. Words from a '#' or '!' on are comments in the header lines. Atoms keep the
// file order and are not wrapped; the box is fully periodic.
#include <cmath>

#include <Eigen/LU>

#include "text.hpp"

namespace tricell::io::detail {

namespace {

constexpr const char* axis_name[3] = {"a", "b", "c"};

std::string element_of_name(std::string_view name) {
    const std::size_t cut = name.find_first_of("_/.:");
    return element_symbol(std::string(name.substr(0, cut)));
}

std::string describe(const std::vector<std::string_view>& words) {
    return words.empty() ? std::string("an empty line") : quote(words[0]);
}

} // namespace

Structure parse_poscar(const std::string& text, const std::string& name,
                       const ReadOptions& options) {
    if (split_words(text).empty()) {
        tricell::detail::fail_parse(name, 0,
                                    "file is empty, expected a POSCAR (comment, scale factor, "
                                    "lattice vectors, element names, counts, positions)");
    }
    Lines lines(text, name);
    lines.next("the comment line");

    // Scale factor(s).
    std::size_t line = lines.number();
    std::vector<std::string_view> words = data_words(lines.next("the scale factor"));
    Eigen::Vector3d component_scale = Eigen::Vector3d::Ones();
    double scale = 1;
    if (words.size() == 1) {
        if (!parse_real(words[0], scale) || scale == 0) {
            lines.fail(line, "expected the scale factor (a non-zero number), got ",
                       quote(words[0]));
        }
    } else if (words.size() == 3) {
        for (int k = 0; k < 3; ++k) {
            if (!parse_real(words[k], component_scale[k]) || component_scale[k] <= 0) {
                lines.fail(line, "expected three positive scale factors, got ", quote(words[k]));
            }
        }
    } else {
        lines.fail(line, "expected the scale factor (one number, or three), got ",
                   words.empty() ? std::string("an empty line")
                                 : std::to_string(words.size()) + " fields");
    }

    // Lattice vectors as rows.
    const std::size_t lattice_line = lines.number();
    Eigen::Matrix3d rows;
    for (int axis = 0; axis < 3; ++axis) {
        line = lines.number();
        words = data_words(lines.next("a lattice vector"));
        if (words.size() != 3) {
            lines.fail(line, "expected 3 numbers for lattice vector ", axis_name[axis], ", got ",
                       words.size(), words.size() == 1 ? " field" : " fields");
        }
        for (int k = 0; k < 3; ++k) {
            if (!parse_real(words[k], rows(axis, k))) {
                lines.fail(line, "expected a number in lattice vector ", axis_name[axis], ", got ",
                           quote(words[k]));
            }
        }
    }
    for (int k = 0; k < 3; ++k) {
        rows.col(k) *= component_scale[k];
    }
    if (scale < 0) {
        const double volume = std::abs(rows.determinant());
        if (!(volume > 0)) {
            lines.fail(lattice_line, "cannot scale to volume ", -scale,
                       ": the lattice vectors are coplanar");
        }
        scale = std::cbrt(-scale / volume);
    }
    rows *= scale;

    // Element names and counts.
    line = lines.number();
    const std::vector<std::string_view> names = data_words(lines.next("the element names"));
    long long probe = 0;
    if (names.empty() || parse_integer(names[0], probe)) {
        lines.fail(line, "expected element names (VASP 5 format), got ", describe(names),
                   "; VASP 4 files without names are not supported");
    }
    std::vector<std::string> elements;
    for (std::string_view element_name : names) {
        const std::string element = element_of_name(element_name);
        if (element.empty()) {
            lines.fail(line, "unknown element ", quote(element_name),
                       ", expected element symbols such as 'Si'");
        }
        elements.push_back(element);
    }
    line = lines.number();
    words = data_words(lines.next("the atom counts"));
    if (words.size() != elements.size()) {
        lines.fail(line, "expected ", elements.size(), " atom counts (one per element), got ",
                   words.size());
    }
    std::vector<std::size_t> counts;
    std::size_t total = 0;
    for (std::size_t k = 0; k < elements.size(); ++k) {
        long long count = 0;
        if (!parse_integer(words[k], count) || count < 0) {
            lines.fail(line, "expected the number of ", elements[k],
                       " atoms (an integer >= 0), got ", quote(words[k]));
        }
        counts.push_back(std::size_t(count));
        total += std::size_t(count);
        if (total > text.size()) { // each atom needs a line: cannot be in this file
            lines.fail(line, "atom count ", count, " is larger than the file can hold");
        }
    }
    if (options.max_atoms != 0 && total > options.max_atoms) {
        lines.fail(line, "the file has ", total,
                   " atoms, more than ReadOptions::max_atoms = ", options.max_atoms);
    }

    // Optional "Selective dynamics", then the coordinate mode.
    line = lines.number();
    std::vector<std::string_view> mode = data_words(lines.next("'Direct' or 'Cartesian'"));
    if (!mode.empty() && (mode[0][0] == 'S' || mode[0][0] == 's')) {
        line = lines.number();
        mode = data_words(lines.next("'Direct' or 'Cartesian'"));
    }
    const char letter = mode.empty() ? ' ' : mode[0][0];
    bool cartesian = false;
    if (letter == 'C' || letter == 'c' || letter == 'K' || letter == 'k') {
        cartesian = true;
    } else if (letter != 'D' && letter != 'd') {
        lines.fail(line, "expected 'Direct' or 'Cartesian', got ", describe(mode));
    }

    Structure structure;
    try {
        structure.box = Box::from_rows(rows);
    } catch (const Error& e) {
        lines.fail(lattice_line, "invalid lattice: ", e.what());
    }
    const Eigen::Vector3d cartesian_scale = scale * component_scale;
    for (std::size_t k = 0; k < elements.size(); ++k) {
        for (std::size_t n = 0; n < counts[k]; ++n) {
            const std::size_t atom = structure.positions.size();
            if (lines.at_end()) {
                lines.fail(lines.number(), "file ends after ", atom, " of ", total,
                           " atom positions");
            }
            line = lines.number();
            words = split_words(lines.next("an atom position"));
            if (words.size() < 3) {
                lines.fail(line, "expected 3 coordinates for atom ", atom, ", got ", words.size());
            }
            Eigen::Vector3d x;
            for (int c = 0; c < 3; ++c) {
                if (!parse_real(words[c], x[c])) {
                    lines.fail(line, "expected a number for coordinate ", c + 1, " of atom ", atom,
                               ", got ", quote(words[c]));
                }
            }
            const Eigen::Vector3d position = cartesian
                                                 ? Eigen::Vector3d(x.cwiseProduct(cartesian_scale))
                                                 : Eigen::Vector3d(structure.box.matrix() * x);
            if (!position.allFinite()) {
                lines.fail(line, "atom ", atom, " is too far away: its coordinates times the ",
                           cartesian ? "scale" : "lattice", " are not finite numbers");
            }
            structure.positions.push_back(position);
            structure.species.push_back(elements[k]);
            structure.labels.emplace_back(names[k]);
        }
    }
    structure.occupancies.assign(structure.species.size(), 1.0);
    return structure;
}

} // namespace tricell::io::detail
