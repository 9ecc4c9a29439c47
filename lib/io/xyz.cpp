// Extended XYZ reader (the layout ASE writes), which also reads plain XYZ.
//
// Line 1 holds the number of atoms N, line 2 a comment, then one line per atom. The comment is
// read as key=value pairs (values bare, "double-quoted" with backslash escapes, or in {} or [];
// a key alone is a flag); keys are case-insensitive and only three matter:
//   Lattice="ax ay az bx by bz cx cy cz"  the lattice vectors a, b, c as rows;
//   pbc="T T F"                            periodicity per axis (T/F, True/False or 1/0), all T
//                                          by default when a Lattice is given;
//   Properties=species:S:1:pos:R:3:...     the columns of the atom lines, as name:type:count
//                                          triples; species and pos are looked up in it.
// A comment that is free text (plain XYZ) simply has none of them. Without Properties the
// columns are species:S:1:pos:R:3. Species are element symbols or, in plain XYZ files, atomic
// numbers. Without a Lattice the system is open: no axis is periodic (a pbc with a T is an
// error) and the box is an orthogonal frame whose edges are the extent of the positions along x,
// y and z plus 1 Angstrom, so that it is never flat. Only the first frame of a multi-frame file
// is read (trajectory.cpp hands this parser one frame at a time). Positions keep the file order
// and are not wrapped.
#include <algorithm>

#include "text.hpp"

namespace tricell::io::detail {

namespace {

struct KeyValue {
    std::string key; // lower case
    std::string value;
    bool unterminated = false;
};

std::vector<KeyValue> parse_key_values(std::string_view text) {
    std::vector<KeyValue> out;
    std::size_t k = 0;
    const auto is_space = [&](std::size_t at) {
        return at < text.size() && (text[at] == ' ' || text[at] == '\t');
    };
    while (k < text.size()) {
        while (is_space(k)) {
            ++k;
        }
        if (k >= text.size()) {
            break;
        }
        KeyValue entry;
        const std::size_t key_start = k;
        while (k < text.size() && !is_space(k) && text[k] != '=') {
            ++k;
        }
        entry.key = lower(text.substr(key_start, k - key_start));
        std::size_t after = k;
        while (is_space(after)) {
            ++after;
        }
        if (after < text.size() && text[after] == '=') {
            k = after + 1;
            while (is_space(k)) {
                ++k;
            }
            if (k < text.size() && text[k] == '"') {
                ++k;
                entry.unterminated = true;
                while (k < text.size()) {
                    if (text[k] == '\\' && k + 1 < text.size()) {
                        entry.value += text[k + 1];
                        k += 2;
                    } else if (text[k] == '"') {
                        ++k;
                        entry.unterminated = false;
                        break;
                    } else {
                        entry.value += text[k++];
                    }
                }
            } else if (k < text.size() && (text[k] == '{' || text[k] == '[')) {
                const char close = text[k] == '{' ? '}' : ']';
                const std::size_t end = text.find(close, k);
                entry.unterminated = end == std::string_view::npos;
                const std::size_t stop = entry.unterminated ? text.size() : end;
                entry.value = std::string(text.substr(k + 1, stop - k - 1));
                k = entry.unterminated ? stop : stop + 1;
            } else {
                const std::size_t value_start = k;
                while (k < text.size() && !is_space(k)) {
                    ++k;
                }
                entry.value = std::string(text.substr(value_start, k - value_start));
            }
        } else {
            entry.value = "T"; // a flag
        }
        if (!entry.key.empty()) {
            out.push_back(std::move(entry));
        }
    }
    return out;
}

struct Columns {
    std::size_t species = 0;
    std::size_t pos = 1;
    std::size_t count = 4;
};

Columns parse_properties(const Lines& lines, std::size_t line, const std::string& value) {
    std::vector<std::string> fields;
    std::size_t start = 0;
    while (true) {
        const std::size_t colon = value.find(':', start);
        fields.push_back(value.substr(start, colon - start));
        if (colon == std::string::npos) {
            break;
        }
        start = colon + 1;
    }
    if (fields.size() % 3 != 0) {
        lines.fail(line, "Properties must be name:type:count triples, got ", quote(value));
    }
    Columns columns;
    bool have_species = false;
    bool have_pos = false;
    std::size_t column = 0;
    for (std::size_t k = 0; k < fields.size(); k += 3) {
        const std::string& property = fields[k];
        const std::string type = lower(fields[k + 1]);
        long long count = 0;
        if (property.empty() || (type != "s" && type != "r" && type != "i" && type != "l") ||
            !parse_integer(fields[k + 2], count) || count < 1 || count > 1000) {
            lines.fail(line,
                       "Properties must be name:type:count triples with type S, R, I or L "
                       "and a count >= 1, got ",
                       quote(property + ":" + fields[k + 1] + ":" + fields[k + 2]));
        }
        const std::string name = lower(property);
        if (name == "species") {
            if (type != "s" || count != 1) {
                lines.fail(line, "Properties: species must be species:S:1, got ",
                           quote(property + ":" + fields[k + 1] + ":" + fields[k + 2]));
            }
            columns.species = column;
            have_species = true;
        } else if (name == "pos") {
            if (type != "r" || count != 3) {
                lines.fail(line, "Properties: pos must be pos:R:3, got ",
                           quote(property + ":" + fields[k + 1] + ":" + fields[k + 2]));
            }
            columns.pos = column;
            have_pos = true;
        }
        column += std::size_t(count);
    }
    if (!have_species || !have_pos) {
        lines.fail(line, "Properties has no ", have_species ? "pos:R:3" : "species:S:1",
                   " column, got ", quote(value));
    }
    columns.count = column;
    return columns;
}

} // namespace

Structure parse_xyz(const std::string& text, const std::string& name, const ReadOptions& options) {
    if (split_words(text).empty()) {
        tricell::detail::fail_parse(name, 0,
                                    "file is empty, expected an XYZ file (number of atoms, "
                                    "comment line, one line per atom)");
    }
    Lines lines(text, name);
    std::size_t line = lines.number();
    const std::vector<std::string_view> first = split_words(lines.next("the number of atoms"));
    long long count = 0;
    if (first.empty() || !parse_integer(first[0], count) || count < 0) {
        lines.fail(line, "expected the number of atoms (an integer >= 0), got ",
                   first.empty() ? std::string("an empty line") : quote(first[0]));
    }
    if (options.max_atoms != 0 && std::size_t(count) > options.max_atoms) {
        lines.fail(line, "the file has ", count,
                   " atoms, more than ReadOptions::max_atoms = ", options.max_atoms);
    }
    const std::size_t comment_line = lines.number();
    const std::vector<KeyValue> pairs = parse_key_values(lines.next("the comment line"));
    if (std::size_t(count) > lines.remaining()) {
        lines.fail(lines.number() + lines.remaining(), "file ends after ", lines.remaining(),
                   " of ", count, " atom lines");
    }

    bool have_lattice = false;
    Eigen::Matrix3d rows = Eigen::Matrix3d::Zero();
    bool have_pbc = false;
    Periodicity pbc = Periodicity::all();
    Columns columns;
    std::string properties = "species:S:1:pos:R:3";
    for (const KeyValue& pair : pairs) {
        if (pair.key != "lattice" && pair.key != "pbc" && pair.key != "properties") {
            continue;
        }
        if (pair.unterminated) {
            lines.fail(comment_line, "unterminated quote in the value of ", pair.key);
        }
        if (pair.key == "lattice") {
            const std::vector<std::string_view> numbers = split_words(pair.value);
            if (numbers.size() != 9) {
                lines.fail(comment_line, "Lattice must hold 9 numbers (a, b, c as rows), got ",
                           numbers.size());
            }
            for (int k = 0; k < 9; ++k) {
                if (!parse_real(numbers[std::size_t(k)], rows(k / 3, k % 3))) {
                    lines.fail(comment_line, "expected a number in Lattice, got ",
                               quote(numbers[std::size_t(k)]));
                }
            }
            have_lattice = true;
        } else if (pair.key == "pbc") {
            const std::vector<std::string_view> flags = split_words(pair.value);
            bool ok = flags.size() == 3;
            for (std::size_t k = 0; ok && k < 3; ++k) {
                ok = parse_bool(flags[k], pbc.axes[k]);
            }
            if (!ok) {
                lines.fail(comment_line, "pbc must be three of T/F (as in pbc=\"T T F\"), got ",
                           quote(pair.value));
            }
            have_pbc = true;
        } else {
            properties = pair.value;
            columns = parse_properties(lines, comment_line, pair.value);
        }
    }
    if (!have_lattice && have_pbc && pbc.any()) {
        lines.fail(comment_line, "pbc has a periodic axis but there is no Lattice");
    }

    Structure structure;
    structure.positions.reserve(std::size_t(count));
    for (long long atom = 0; atom < count; ++atom) {
        line = lines.number();
        const std::vector<std::string_view> words = split_words(lines.next("an atom line"));
        if (words.size() < columns.count) {
            lines.fail(line, "expected ", columns.count,
                       " columns (Properties=", one_line(properties), ") for atom ", atom, ", got ",
                       words.size());
        }
        const std::string_view token = words[columns.species];
        const std::string element = element_symbol(std::string(token), true);
        if (element.empty()) {
            lines.fail(line, "unknown element ", quote(token), " for atom ", atom,
                       ", expected an element symbol or atomic number");
        }
        Eigen::Vector3d x;
        for (int c = 0; c < 3; ++c) {
            if (!parse_real(words[columns.pos + std::size_t(c)], x[c])) {
                lines.fail(line, "expected a number for coordinate ", c + 1, " of atom ", atom,
                           ", got ", quote(words[columns.pos + std::size_t(c)]));
            }
        }
        structure.species.push_back(element);
        structure.labels.emplace_back(token);
        structure.positions.push_back(x);
    }
    structure.occupancies.assign(structure.species.size(), 1.0);

    try {
        if (have_lattice) {
            structure.box = Box::from_rows(rows, pbc);
        } else {
            Eigen::Vector3d lower_corner = Eigen::Vector3d::Zero();
            Eigen::Vector3d upper_corner = Eigen::Vector3d::Zero();
            if (!structure.positions.empty()) {
                lower_corner = upper_corner = structure.positions.front();
                for (const Eigen::Vector3d& x : structure.positions) {
                    lower_corner = lower_corner.cwiseMin(x);
                    upper_corner = upper_corner.cwiseMax(x);
                }
            }
            const Eigen::Vector3d edges = (upper_corner - lower_corner).array() + 1.0;
            structure.box =
                Box::from_columns(edges.asDiagonal().toDenseMatrix(), Periodicity::none());
        }
    } catch (const Error& e) {
        lines.fail(comment_line, "invalid box: ", e.what());
    }
    return structure;
}

} // namespace tricell::io::detail
