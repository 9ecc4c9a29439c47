#include "tricell/io/structure.hpp"

#include <cmath>
#include <cstdio>
#include <map>

#include <gemmi/elem.hpp>

#include "text.hpp"
#include "tricell/error.hpp"

namespace tricell::io {

namespace {

bool ends_with(const std::string& text, const std::string& suffix) {
    return text.size() >= suffix.size() &&
           text.compare(text.size() - suffix.size(), suffix.size(), suffix) == 0;
}

bool starts_with(const std::string& text, const std::string& prefix) {
    return text.compare(0, prefix.size(), prefix) == 0;
}

} // namespace

void ReadOptions::validate() const {
    if (!(std::isfinite(merge_distance) && merge_distance >= 0)) {
        tricell::detail::fail<InvalidArgument>("merge_distance must be finite and >= 0 (got ",
                                               merge_distance, ")");
    }
}

Format format_from_name(const std::string& path) {
    const std::size_t slash = path.find_last_of("/\\");
    const std::string base =
        detail::lower(slash == std::string::npos ? path : path.substr(slash + 1));
    if (ends_with(base, ".cif")) {
        return Format::cif;
    }
    if (ends_with(base, ".xyz") || ends_with(base, ".extxyz")) {
        return Format::xyz;
    }
    if (ends_with(base, ".vasp") || ends_with(base, ".poscar") || starts_with(base, "poscar") ||
        starts_with(base, "contcar")) {
        return Format::poscar;
    }
    const std::size_t dot = base.find_last_of('.');
    const std::string what = dot == std::string::npos || dot == 0
                                 ? std::string("no file extension")
                                 : "unknown file extension " + detail::quote(base.substr(dot));
    tricell::detail::fail_parse(path, 0, what,
                                ", expected *.cif, *.xyz, *.extxyz, *.vasp, *.poscar, POSCAR or "
                                "CONTCAR (or give the format explicitly)");
}

Format parse_format(const std::string& name) {
    const std::string word = detail::lower(name);
    if (word == "cif") {
        return Format::cif;
    }
    if (word == "xyz" || word == "extxyz") {
        return Format::xyz;
    }
    if (word == "poscar" || word == "vasp") {
        return Format::poscar;
    }
    tricell::detail::fail<InvalidArgument>("unknown format ", detail::quote(name),
                                           ", expected cif, xyz, extxyz, poscar or vasp");
}

const char* format_name(Format format) {
    switch (format) {
    case Format::cif:
        return "cif";
    case Format::xyz:
        return "xyz";
    case Format::poscar:
        return "poscar";
    }
    return "unknown";
}

Structure parse_structure(const std::string& text, const std::string& name,
                          const ReadOptions& options) {
    options.validate();
    const Format format = options.format ? *options.format : format_from_name(name);
    Structure structure;
    switch (format) {
    case Format::cif:
        structure = detail::parse_cif(text, name, options);
        break;
    case Format::xyz:
        structure = detail::parse_xyz(text, name, options);
        break;
    case Format::poscar:
        structure = detail::parse_poscar(text, name, options);
        break;
    }
    structure.source = name;
    return structure;
}

Structure read_structure(const std::string& path, const ReadOptions& options) {
    options.validate();
    ReadOptions resolved = options;
    if (!resolved.format) {
        resolved.format = format_from_name(path); // before opening: a clear message first
    }
    return parse_structure(detail::read_file(path), path, resolved);
}

std::string element_symbol(const std::string& token, bool allow_number) {
    if (allow_number) {
        long long number = 0;
        if (detail::parse_integer(token, number)) {
            if (number < 1 || number > 118) {
                return {};
            }
            return gemmi::element_name(gemmi::Element(static_cast<int>(number)).elem);
        }
    }
    if (token.empty() || token.size() > 2) {
        return {};
    }
    for (char c : token) {
        if (!((c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z'))) {
            return {};
        }
    }
    const gemmi::El element = gemmi::find_element(token.c_str());
    if (element == gemmi::El::X) {
        return {};
    }
    return gemmi::element_name(element);
}

double occupied_count(const Structure& structure) {
    double total = 0;
    for (double occupancy : structure.occupancies) {
        total += occupancy;
    }
    return total;
}

std::string formula(const Structure& structure) {
    std::map<std::string, double> counts;
    for (std::size_t k = 0; k < structure.species.size(); ++k) {
        const double occupancy = k < structure.occupancies.size() ? structure.occupancies[k] : 1.0;
        counts[structure.species[k]] += occupancy;
    }
    std::vector<std::string> order;
    const bool carbon = counts.count("C") != 0;
    if (carbon) {
        order.push_back("C");
        if (counts.count("H") != 0) {
            order.push_back("H");
        }
    }
    for (const auto& entry : counts) {
        if (!carbon || (entry.first != "C" && entry.first != "H")) {
            order.push_back(entry.first);
        }
    }
    std::string out;
    for (const std::string& element : order) {
        const double count = counts[element];
        if (count <= 0) {
            continue;
        }
        if (!out.empty()) {
            out += ' ';
        }
        out += element;
        if (count != 1) {
            char number[32];
            std::snprintf(number, sizeof number, "%.6g", count);
            out += number;
        }
    }
    return out;
}

} // namespace tricell::io
