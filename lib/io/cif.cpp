// CIF reader: cell, atom sites and symmetry operators, expanded to the full unit cell.
//
// gemmi's PEGTL grammar parses the syntax. The parse runs with our own actions (gemmi's plus a
// record of the line of every data block and loop value), so that every error can name its
// line. The structure comes from the first data block that has _atom_site_fract_x (the first
// block if none has):
//   - cell: _cell_length_a/b/c and _cell_angle_alpha/beta/gamma, all required; the box has a
//     along x and b in the xy plane. Numbers may carry a standard uncertainty, "4.916(3)".
//   - symmetry: the explicit operator loop (_symmetry_equiv_pos_as_xyz or
//     _space_group_symop_operation_xyz) when present; otherwise the Hall symbol
//     (_space_group_name_Hall), otherwise the H-M symbol (_space_group_name_H-M_alt or
//     _symmetry_space_group_name_H-M) through gemmi's tables, taken as all centring
//     translations times all operators; otherwise P 1. A space-group number alone does not fix
//     the setting and is refused unless it is 1.
//   - atom sites: _atom_site_fract_x/y/z (required) with the optional _atom_site_label,
//     _atom_site_type_symbol (element from its leading letters, "Fe2+" is Fe; the label is used
//     when it is absent) and _atom_site_occupancy (default 1, must lie in [0, 1]).
// Expansion: for each site row in file order, the operators in order, each image wrapped into
// [0, 1); an image within merge_distance (Cartesian, minimum image) of an image already kept
// for the same row is dropped, so special positions are not duplicated; with more than one
// operator, a cell narrower than twice merge_distance is refused. Rows are never merged with
// each other: two species sharing a site (substitutional disorder) both stay, each with its
// occupancy.
#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <map>
#include <utility>

#include <gemmi/cif.hpp>
#include <gemmi/symmetry.hpp>

#include "text.hpp"

namespace tricell::io::detail {

namespace {

namespace cif = gemmi::cif;
namespace pegtl = tao::pegtl;

// A gemmi Document that also knows the lines of its blocks and loop values.
struct LinedDocument : cif::Document {
    std::string name;
    std::vector<std::size_t> block_lines;
    // Line of each value of a top-level loop, by (block index, item index).
    std::map<std::pair<std::size_t, std::size_t>, std::vector<std::size_t>> loop_value_lines;

    std::vector<std::size_t>* current_loop_lines() {
        if (blocks.empty() || items_ != &blocks.back().items || items_->empty()) {
            return nullptr; // inside a save_ frame: lines are not tracked there
        }
        return &loop_value_lines[{blocks.size() - 1, items_->size() - 1}];
    }
};

// gemmi's actions, plus line bookkeeping and a clearer message for an incomplete loop.
template <class Rule> struct LineAction : cif::Action<Rule> {};

template <> struct LineAction<cif::rules::datablockname> {
    template <class Input> static void apply(const Input& in, LinedDocument& doc) {
        cif::Action<cif::rules::datablockname>::apply(in, doc);
        doc.block_lines.push_back(in.iterator().line);
    }
};

template <> struct LineAction<cif::rules::str_global> {
    template <class Input> static void apply(const Input& in, LinedDocument& doc) {
        cif::Action<cif::rules::str_global>::apply(in, doc);
        doc.block_lines.push_back(in.iterator().line);
    }
};

template <> struct LineAction<cif::rules::loop_value> {
    template <class Input> static void apply(const Input& in, LinedDocument& doc) {
        cif::Action<cif::rules::loop_value>::apply(in, doc);
        if (std::vector<std::size_t>* lines = doc.current_loop_lines()) {
            lines->push_back(in.iterator().line);
        }
    }
};

template <> struct LineAction<cif::rules::loop> {
    template <class Input> static void apply(const Input& in, LinedDocument& doc) {
        const cif::Item& item = doc.items_->back();
        const cif::Loop& loop = item.loop;
        const std::size_t width = loop.tags.size();
        const std::size_t extra = loop.values.size() % width;
        if (extra != 0) {
            const std::vector<std::size_t>* lines = doc.current_loop_lines();
            const std::size_t line =
                lines && !lines->empty() ? lines->back() : std::size_t(in.iterator().line);
            tricell::detail::fail_parse(doc.name, line, "incomplete loop row: the loop of ",
                                        loop.tags[0], " has ", width, " tags but its last row has ",
                                        extra, extra == 1 ? " value" : " values",
                                        " (truncated file or missing value?)");
        }
    }
};

// Reads values of one block with their lines.
class BlockReader {
  public:
    BlockReader(LinedDocument& doc, std::size_t index)
        : doc_(doc), index_(index), block_(doc.blocks[index]) {}

    cif::Block& block() { return block_; }
    const std::string& file() const { return doc_.name; }
    std::size_t block_line() const {
        return index_ < doc_.block_lines.size() ? doc_.block_lines[index_] : 0;
    }
    std::string block_name() const { return "data_" + block_.name; }

    /// First of the tags that is present, or an empty column.
    cif::Column find(std::initializer_list<const char*> tags) {
        for (const char* tag : tags) {
            cif::Column column = block_.find_values(tag);
            if (column) {
                return column;
            }
        }
        return cif::Column();
    }

    std::size_t line(const cif::Column& column, int row) const {
        const cif::Item* item = column.item();
        if (item == nullptr) {
            return block_line();
        }
        if (item->type == cif::ItemType::Loop) {
            const auto found =
                doc_.loop_value_lines.find({index_, std::size_t(item - block_.items.data())});
            const std::size_t k = std::size_t(row) * item->loop.width() + column.col();
            if (found != doc_.loop_value_lines.end() && k < found->second.size()) {
                return found->second[k];
            }
        }
        return item->line_number > 0 ? std::size_t(item->line_number) : block_line();
    }

    template <class... Args> [[noreturn]] void fail(std::size_t line, Args&&... args) const {
        tricell::detail::fail_parse(doc_.name, line, std::forward<Args>(args)...);
    }

    /// Fails for a tag without value, a loop without values (gemmi accepts one at the end of
    /// the file) and a tag given twice.
    void check_items() const {
        std::map<std::string, std::size_t> seen;
        for (const cif::Item& item : block_.items) {
            const std::size_t line = item.line_number > 0 ? std::size_t(item.line_number) : 0;
            std::vector<std::string> tags;
            if (item.type == cif::ItemType::Pair) {
                if (item.pair[1].empty()) {
                    fail(line, item.pair[0], " has no value");
                }
                tags.push_back(item.pair[0]);
            } else if (item.type == cif::ItemType::Loop) {
                if (item.loop.values.empty()) {
                    fail(line, "the loop of ", item.loop.tags[0], " has no values");
                }
                tags = item.loop.tags;
            }
            for (const std::string& tag : tags) {
                const auto inserted = seen.emplace(gemmi::to_lower(tag), line);
                if (!inserted.second) {
                    fail(line, "duplicate tag ", tag, " (first given on line ",
                         inserted.first->second, ")");
                }
            }
        }
    }

  private:
    LinedDocument& doc_;
    std::size_t index_;
    cif::Block& block_;
};

// A CIF number: strips quotes and a trailing standard uncertainty "(3)".
bool cif_number(const std::string& raw, double& value) {
    std::string text = cif::as_string(raw);
    const std::size_t open = text.find('(');
    if (open != std::string::npos && !text.empty() && text.back() == ')') {
        const std::string digits = text.substr(open + 1, text.size() - open - 2);
        if (digits.empty() || digits.find_first_not_of("0123456789") != std::string::npos) {
            return false;
        }
        text.erase(open);
    }
    return parse_real(text, value);
}

double read_number(BlockReader& reader, const cif::Column& column, int row, const char* tag,
                   const std::string& context) {
    const std::string& raw = column.at(row);
    double value = 0;
    if (cif::is_null(raw)) {
        reader.fail(reader.line(column, row), tag, context, " is unknown (", raw,
                    "), expected a number");
    }
    if (!cif_number(raw, value)) {
        reader.fail(reader.line(column, row), tag, context, " must be a number, got ", quote(raw));
    }
    return value;
}

// Element of an atom site from the leading letters of a type symbol or label.
std::string element_from(const std::string& text) {
    std::size_t letters = 0;
    while (letters < text.size() && std::isalpha(static_cast<unsigned char>(text[letters]))) {
        ++letters;
    }
    if (letters >= 2) {
        std::string two = element_symbol(text.substr(0, 2));
        if (!two.empty()) {
            return two;
        }
    }
    return letters >= 1 ? element_symbol(text.substr(0, 1)) : std::string();
}

Box read_cell(BlockReader& reader) {
    static const char* const tags[6] = {"_cell_length_a",   "_cell_length_b",
                                        "_cell_length_c",   "_cell_angle_alpha",
                                        "_cell_angle_beta", "_cell_angle_gamma"};
    double p[6];
    std::size_t first_line = 0;
    for (int k = 0; k < 6; ++k) {
        const cif::Column column = reader.find({tags[k]});
        if (!column) {
            reader.fail(reader.block_line(), tags[k], " is missing in ", reader.block_name(),
                        ", expected the cell (_cell_length_a/b/c, _cell_angle_alpha/beta/gamma)");
        }
        p[k] = read_number(reader, column, 0, tags[k], "");
        const std::size_t line = reader.line(column, 0);
        first_line = k == 0 ? line : first_line;
        if (k < 3 && !(p[k] > 0)) {
            reader.fail(line, tags[k], " must be > 0, got ", p[k]);
        }
        if (k >= 3 && !(p[k] > 0 && p[k] < 180)) {
            reader.fail(line, tags[k], " must be between 0 and 180 degrees, got ", p[k]);
        }
    }
    try {
        return Box::from_parameters(p[0], p[1], p[2], p[3], p[4], p[5]);
    } catch (const Error& e) {
        reader.fail(first_line, "invalid cell: ", one_line(e.what()));
    }
}

// A symmetry operator as exact integers: s' = rot s + tran / DEN.
struct Operator {
    Eigen::Matrix3d rot;
    Eigen::Vector3d tran;
};

Operator to_operator(const gemmi::Op& op) {
    Operator out;
    for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) {
            out.rot(i, j) = op.rot[std::size_t(i)][std::size_t(j)] / gemmi::Op::DEN;
        }
        out.tran[i] = double(op.tran[std::size_t(i)]) / gemmi::Op::DEN;
    }
    return out;
}

// Operators of the largest space groups (F m -3 m: 48 point operations x 4 centrings).
constexpr std::size_t max_operators = 192;

// Why gemmi's op is not a lattice symmetry operation, or empty.
std::string check_operator(const gemmi::Op& op) {
    for (const auto& row : op.rot) {
        for (int entry : row) {
            if (entry % gemmi::Op::DEN != 0) {
                return "its rotation part is not an integer matrix";
            }
        }
    }
    const int det = op.det_rot();
    const int unit = gemmi::Op::DEN * gemmi::Op::DEN * gemmi::Op::DEN;
    if (det != unit && det != -unit) {
        return "its rotation part has determinant " + std::to_string(det / unit) +
               ", expected 1 or -1";
    }
    return {};
}

// gemmi's parser multiplies numbers into ints; keep them small so nothing overflows.
bool plausible_triplet(const std::string& text) {
    std::size_t digits = 0;
    for (char c : text) {
        digits = std::isdigit(static_cast<unsigned char>(c)) ? digits + 1 : 0;
        if (digits > 3) {
            return false;
        }
    }
    return true;
}

std::vector<Operator> read_operators(BlockReader& reader, const Box& box) {
    std::vector<Operator> ops;
    const cif::Column explicit_ops =
        reader.find({"_symmetry_equiv_pos_as_xyz", "_space_group_symop_operation_xyz",
                     "_space_group_symop.operation_xyz"});
    if (explicit_ops) {
        std::vector<gemmi::Op> distinct; // translations wrapped into [0, 1)
        for (int row = 0; row < explicit_ops.length(); ++row) {
            const std::string text = cif::as_string(explicit_ops.at(row));
            const std::size_t line = reader.line(explicit_ops, row);
            gemmi::Op op;
            try {
                if (!plausible_triplet(text)) {
                    throw std::runtime_error("a number is too long");
                }
                op = gemmi::parse_triplet(text);
            } catch (const std::exception& e) {
                reader.fail(line, "invalid symmetry operator ", quote(text), " (",
                            one_line(e.what()), "), expected a triplet such as '-y, x-y, z+1/3'");
            }
            const std::string problem = check_operator(op);
            if (!problem.empty()) {
                reader.fail(line, "symmetry operator ", quote(text),
                            " is not a crystallographic operation: ", problem);
            }
            // An operator listed twice adds nothing (its images would merge); more than 192
            // distinct ones is no space group in any cell, and would make the expansion
            // (rows x operators atoms, each compared with the row's other images) explode.
            gemmi::Op wrapped = op;
            wrapped.wrap();
            if (std::find(distinct.begin(), distinct.end(), wrapped) != distinct.end()) {
                continue;
            }
            if (distinct.size() == max_operators) {
                reader.fail(line, "more than ", max_operators,
                            " distinct symmetry operators, more than any space group has");
            }
            distinct.push_back(wrapped);
            ops.push_back(to_operator(op));
        }
        if (ops.empty()) {
            reader.fail(reader.line(explicit_ops, 0), "the symmetry operator loop is empty");
        }
        return ops;
    }

    gemmi::GroupOps group;
    const cif::Column hall =
        reader.find({"_space_group_name_Hall", "_symmetry_space_group_name_Hall"});
    const cif::Column hm =
        reader.find({"_space_group_name_H-M_alt", "_symmetry_space_group_name_H-M"});
    if (hall && !cif::is_null(hall.at(0))) {
        const std::string symbol = cif::as_string(hall.at(0));
        try {
            group = gemmi::symops_from_hall(symbol.c_str());
        } catch (const std::exception& e) {
            reader.fail(reader.line(hall, 0), "invalid Hall symbol ", quote(symbol), " (",
                        one_line(e.what()), ")");
        }
    } else if (hm && !cif::is_null(hm.at(0))) {
        const std::string symbol = cif::as_string(hm.at(0));
        const LatticeParameters p = box.parameters();
        const gemmi::SpaceGroup* group_info =
            gemmi::find_spacegroup_by_name(symbol, p.alpha, p.gamma);
        if (group_info == nullptr) {
            reader.fail(reader.line(hm, 0), "unknown space group ", quote(symbol),
                        ", expected an H-M symbol such as 'P 21/c' or the operators in a "
                        "_symmetry_equiv_pos_as_xyz loop");
        }
        group = group_info->operations();
    } else {
        const cif::Column number =
            reader.find({"_space_group_IT_number", "_symmetry_Int_Tables_number"});
        if (number && !cif::is_null(number.at(0)) && cif::as_string(number.at(0)) != "1") {
            reader.fail(reader.line(number, 0), "only the space-group number (",
                        cif::as_string(number.at(0)),
                        ") is given, which does not fix the setting; expected the operators "
                        "(_symmetry_equiv_pos_as_xyz) or an H-M or Hall symbol");
        }
        ops.push_back({Eigen::Matrix3d::Identity(), Eigen::Vector3d::Zero()}); // P 1
        return ops;
    }
    for (const gemmi::Op::Tran& centring : group.cen_ops) {
        for (const gemmi::Op& op : group.sym_ops) {
            ops.push_back(to_operator(op.add_centering(centring)));
        }
    }
    return ops;
}

// The column of an optional atom-site tag, which must sit in the loop of the coordinates.
cif::Column site_column(BlockReader& reader, const char* tag, const cif::Column& x) {
    cif::Column column = reader.find({tag});
    if (column && column.item() != x.item()) {
        reader.fail(reader.line(column, 0), tag, " must be in the same loop as _atom_site_fract_x");
    }
    return column;
}

} // namespace

Structure parse_cif(const std::string& text, const std::string& name, const ReadOptions& options) {
    if (split_words(text).empty()) {
        tricell::detail::fail_parse(name, 0,
                                    "file is empty, expected a CIF data block (data_NAME)");
    }
    LinedDocument doc;
    doc.name = name;
    doc.source = name;
    try {
        pegtl::memory_input<> in(text.data(), text.size(), name);
        pegtl::parse<cif::rules::file, LineAction, cif::Errors>(in, doc);
    } catch (const pegtl::parse_error& e) {
        const std::size_t line = e.positions().empty() ? 0 : e.positions().front().line;
        std::string message(e.message());
        if (message == "parse error" && !e.positions().empty()) {
            // gemmi's generic message: name what was found instead.
            const std::size_t byte = std::min(e.positions().front().byte, text.size());
            const std::size_t end = std::min(text.find_first_of(" \t\r\n", byte), text.size());
            message = "unexpected " +
                      (byte == text.size() ? std::string("end of file")
                                           : quote(std::string_view(text).substr(
                                                 byte, std::max<std::size_t>(end - byte, 1)))) +
                      ", expected a tag (_name) with its value, loop_ with its tags, or data_NAME";
        }
        tricell::detail::fail_parse(name, line, "CIF syntax error: ", one_line(message));
    }
    if (doc.blocks.empty()) {
        tricell::detail::fail_parse(name, 0,
                                    "no data block, expected a CIF data block (data_NAME)");
    }

    std::size_t index = 0;
    for (std::size_t k = 0; k < doc.blocks.size(); ++k) {
        if (doc.blocks[k].find_values("_atom_site_fract_x")) {
            index = k;
            break;
        }
    }
    BlockReader reader(doc, index);
    reader.check_items();
    Structure structure;
    structure.box = read_cell(reader);
    const Box& box = structure.box;

    const cif::Column x = reader.find({"_atom_site_fract_x"});
    if (!x) {
        reader.fail(reader.block_line(), "_atom_site_fract_x is missing in ", reader.block_name(),
                    ", expected the atom sites (_atom_site_label, _atom_site_type_symbol, "
                    "_atom_site_fract_x/y/z)");
    }
    const cif::Column y = site_column(reader, "_atom_site_fract_y", x);
    const cif::Column z = site_column(reader, "_atom_site_fract_z", x);
    for (const cif::Column* column : {&y, &z}) {
        if (!*column) {
            reader.fail(reader.line(x, 0),
                        column == &y ? "_atom_site_fract_y" : "_atom_site_fract_z",
                        " is missing, expected it next to _atom_site_fract_x");
        }
    }
    const cif::Column label = site_column(reader, "_atom_site_label", x);
    const cif::Column type = site_column(reader, "_atom_site_type_symbol", x);
    const cif::Column occupancy = site_column(reader, "_atom_site_occupancy", x);

    const std::vector<Operator> ops = read_operators(reader, box);

    // Images closer than merge_distance are one atom. The rounded fractional difference gives
    // the true minimum-image distance whenever that is under half the smallest width, so a cell
    // narrower than twice merge_distance is refused rather than searched translate by translate.
    const double merge_sq = options.merge_distance * options.merge_distance;
    const Eigen::Vector3d widths = box.perpendicular_widths();
    for (int k = 0; k < 3 && ops.size() > 1; ++k) {
        if (!(options.merge_distance < 0.5 * widths[k])) {
            reader.fail(
                reader.line(x, 0), "the cell is ", widths[k], " Angstrom wide across ", "abc"[k],
                ", not more than twice ReadOptions::merge_distance = ", options.merge_distance,
                ", so the images of one site cannot be told "
                "apart; pass a smaller merge_distance");
        }
    }
    const auto same_place = [&](const Eigen::Vector3d& s, const Eigen::Vector3d& t) {
        Eigen::Vector3d d = s - t;
        for (int k = 0; k < 3; ++k) {
            d[k] -= std::round(d[k]);
        }
        return (box.matrix() * d).squaredNorm() < merge_sq;
    };

    const double bound = double(x.length()) * double(ops.size());
    if (options.max_atoms != 0 && bound > double(options.max_atoms)) {
        reader.fail(reader.line(x, 0), "the symmetry expansion of ", x.length(), " sites by ",
                    ops.size(), " operators could give ", bound,
                    " atoms, more than ReadOptions::max_atoms = ", options.max_atoms);
    }
    for (int row = 0; row < x.length(); ++row) {
        const std::size_t line = reader.line(x, row);
        const std::string site_label =
            label && !cif::is_null(label.at(row)) ? cif::as_string(label.at(row)) : std::string();
        const std::string type_symbol =
            type && !cif::is_null(type.at(row)) ? cif::as_string(type.at(row)) : std::string();
        const std::string element = element_from(type_symbol.empty() ? site_label : type_symbol);
        if (element.empty()) {
            reader.fail(line, "cannot tell the element of site ",
                        quote(site_label.empty() ? std::to_string(row + 1) : site_label),
                        " from _atom_site_type_symbol ", quote(type_symbol),
                        " or _atom_site_label, expected e.g. 'Si' or 'Si1'");
        }
        const std::string context =
            " of site " + quote(site_label.empty() ? type_symbol : site_label);
        const Eigen::Vector3d s(read_number(reader, x, row, "_atom_site_fract_x", context),
                                read_number(reader, y, row, "_atom_site_fract_y", context),
                                read_number(reader, z, row, "_atom_site_fract_z", context));
        double occ = 1;
        if (occupancy && !cif::is_null(occupancy.at(row))) {
            occ = read_number(reader, occupancy, row, "_atom_site_occupancy", context);
            if (!(occ >= 0 && occ <= 1 + 1e-6)) {
                reader.fail(reader.line(occupancy, row), "_atom_site_occupancy", context,
                            " must be between 0 and 1, got ", occ);
            }
        }
        if (s.cwiseAbs().maxCoeff() > 1e6) {
            reader.fail(line, "fractional coordinates", context, " are implausibly large");
        }

        std::vector<Eigen::Vector3d> kept;
        for (const Operator& op : ops) {
            const Eigen::Vector3d image = box.wrap(Fractional(op.rot * s + op.tran)).wrapped;
            bool duplicate = false;
            for (const Eigen::Vector3d& other : kept) {
                if (same_place(image, other)) {
                    duplicate = true;
                    break;
                }
            }
            if (!duplicate) {
                kept.push_back(image);
            }
        }
        for (const Eigen::Vector3d& image : kept) {
            structure.positions.push_back(box.matrix() * image);
            structure.species.push_back(element);
            structure.labels.push_back(site_label.empty() ? type_symbol : site_label);
            structure.occupancies.push_back(occ);
        }
    }
    return structure;
}

} // namespace tricell::io::detail
