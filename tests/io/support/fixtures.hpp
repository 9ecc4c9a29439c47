// Access to fixtures/ (structures and pymatgen references) and small helpers for the io tests.
#pragma once

#include <algorithm>
#include <array>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include <Eigen/Core>

namespace tricell::test {

inline std::string source_dir() {
    return TRICELL_SOURCE_DIR;
}
inline std::string fixtures_dir() {
    return source_dir() + "/fixtures";
}

inline std::string read_text(const std::string& path) {
    std::ifstream file(path, std::ios::binary);
    if (!file) {
        throw std::runtime_error("cannot open " + path);
    }
    std::ostringstream content;
    content << file.rdbuf();
    return content.str();
}

/// Names of fixtures/structures/NAME.cif, sorted.
inline std::vector<std::string> fixture_names() {
    std::vector<std::string> names;
    for (const auto& entry : std::filesystem::directory_iterator(fixtures_dir() + "/structures")) {
        if (entry.path().extension() == ".cif") {
            names.push_back(entry.path().stem().string());
        }
    }
    std::sort(names.begin(), names.end());
    return names;
}

/// pymatgen's expanded structure (fixtures/reference/NAME.structure.tsv).
struct ReferenceStructure {
    Eigen::Matrix3d rows;
    std::vector<std::string> symbols;
    std::vector<Eigen::Vector3d> fractional;
    std::vector<Eigen::Vector3d> cartesian;
    std::vector<double> occupancies;
};

inline ReferenceStructure read_reference_structure(const std::string& name) {
    std::istringstream in(read_text(fixtures_dir() + "/reference/" + name + ".structure.tsv"));
    std::string line;
    std::getline(in, line); // comment
    std::string word;
    in >> word;
    if (word != "lattice_rows") {
        throw std::runtime_error("bad structure file for " + name);
    }
    ReferenceStructure out;
    for (int r = 0; r < 3; ++r) {
        for (int c = 0; c < 3; ++c) {
            in >> out.rows(r, c);
        }
    }
    std::size_t n = 0;
    in >> word >> n;
    for (std::size_t k = 0; k < n; ++k) {
        std::string symbol;
        Eigen::Vector3d f, x;
        double occupancy = 0;
        in >> symbol >> f[0] >> f[1] >> f[2] >> x[0] >> x[1] >> x[2] >> occupancy;
        out.symbols.push_back(symbol);
        out.fractional.push_back(f);
        out.cartesian.push_back(x);
        out.occupancies.push_back(occupancy);
    }
    if (!in) {
        throw std::runtime_error("truncated structure file for " + name);
    }
    return out;
}

struct ReferencePair {
    std::uint32_t i, j;
    std::array<int, 3> shift;
    double distance;
};

/// pymatgen's full neighbour list (fixtures/reference/FILE).
inline std::vector<ReferencePair> read_reference_pairs(const std::string& file) {
    std::istringstream in(read_text(fixtures_dir() + "/reference/" + file));
    std::string line;
    std::getline(in, line); // comment
    std::vector<ReferencePair> out;
    ReferencePair p{};
    while (in >> p.i >> p.j >> p.shift[0] >> p.shift[1] >> p.shift[2] >> p.distance) {
        out.push_back(p);
    }
    return out;
}

/// (file, cutoff) of every neighbour list of a structure, from MANIFEST.tsv.
inline std::vector<std::pair<std::string, double>> reference_lists(const std::string& name) {
    std::istringstream in(read_text(fixtures_dir() + "/reference/MANIFEST.tsv"));
    std::string line;
    std::vector<std::pair<std::string, double>> out;
    while (std::getline(in, line)) {
        std::istringstream words(line);
        std::string file, kind, sites, pairs, cutoff;
        words >> file >> kind >> sites >> pairs >> cutoff;
        if (kind == "neighbors" && file.rfind(name + ".neighbors.", 0) == 0) {
            out.emplace_back(file, std::stod(cutoff));
        }
    }
    return out;
}

} // namespace tricell::test
