// box_info: reads a small box description and prints its lattice parameters, volume,
// perpendicular widths, the atoms' fractional coordinates and their minimum-image distances.
//
// Input (one item per line, '#' starts a comment):
//   rows ax ay az bx by bz cx cy cz      lattice vectors as rows, or
//   parameters a b c alpha beta gamma    lattice parameters (degrees)
//   pbc T T T                            optional, default all periodic
//   atom NAME x y z                      Cartesian position, any number of lines
#include <cstdio>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include <tricell/tricell.hpp>

namespace {

struct Atom {
    std::string name;
    tricell::Cartesian position;
};

struct Input {
    tricell::Box box = tricell::Box::from_parameters(1, 1, 1, 90, 90, 90);
    std::vector<Atom> atoms;
};

Input read_input(const std::string& path) {
    std::ifstream file(path);
    if (!file) {
        throw tricell::ParseError(path, 0, "cannot open file");
    }
    Input input;
    bool have_box = false;
    tricell::Periodicity pbc;
    Eigen::Matrix3d rows;
    tricell::LatticeParameters parameters;
    bool by_rows = false;
    std::string line;
    for (std::size_t number = 1; std::getline(file, line); ++number) {
        line = line.substr(0, line.find('#'));
        std::istringstream words(line);
        std::string key;
        if (!(words >> key)) {
            continue;
        }
        bool ok = true;
        if (key == "rows") {
            for (int k = 0; k < 9 && ok; ++k) {
                ok = static_cast<bool>(words >> rows(k / 3, k % 3));
            }
            have_box = by_rows = true;
        } else if (key == "parameters") {
            ok = static_cast<bool>(words >> parameters.a >> parameters.b >> parameters.c >>
                                   parameters.alpha >> parameters.beta >> parameters.gamma);
            have_box = true;
            by_rows = false;
        } else if (key == "pbc") {
            for (int k = 0; k < 3 && ok; ++k) {
                std::string flag;
                ok = (words >> flag) && (flag == "T" || flag == "F");
                pbc.axes[static_cast<std::size_t>(k)] = flag == "T";
            }
        } else if (key == "atom") {
            Atom atom;
            ok = static_cast<bool>(words >> atom.name >> atom.position.x() >> atom.position.y() >>
                                   atom.position.z());
            input.atoms.push_back(atom);
        } else {
            throw tricell::ParseError(path, number, "unknown keyword '" + key + "'");
        }
        if (!ok) {
            throw tricell::ParseError(path, number, "malformed '" + key + "' line");
        }
    }
    if (!have_box) {
        throw tricell::ParseError(path, 0, "no 'rows' or 'parameters' line");
    }
    input.box = by_rows ? tricell::Box::from_rows(rows, pbc)
                        : tricell::Box::from_parameters(parameters, pbc);
    return input;
}

void print(const Input& input) {
    const tricell::Box& box = input.box;
    const tricell::LatticeParameters p = box.parameters();
    std::printf("lattice a b c       %.6f %.6f %.6f\n", p.a, p.b, p.c);
    std::printf("angles alpha beta gamma %.4f %.4f %.4f\n", p.alpha, p.beta, p.gamma);
    std::printf("volume              %.6f\n", box.volume());
    const Eigen::Vector3d& w = box.perpendicular_widths();
    std::printf("perpendicular widths %.6f %.6f %.6f\n", w[0], w[1], w[2]);
    std::printf("periodic            %c %c %c\n", box.periodic(0) ? 'T' : 'F',
                box.periodic(1) ? 'T' : 'F', box.periodic(2) ? 'T' : 'F');
    std::printf("\n# atom fractional (a b c) wrapped into [0,1)\n");
    for (const Atom& atom : input.atoms) {
        const tricell::WrappedFractional s = box.wrap(box.to_fractional(atom.position));
        std::printf("%-4s %.6f %.6f %.6f  image %d %d %d\n", atom.name.c_str(), s.wrapped[0],
                    s.wrapped[1], s.wrapped[2], s.image[0], s.image[1], s.image[2]);
    }
    std::printf("\n# minimum-image distances\n");
    for (std::size_t i = 0; i < input.atoms.size(); ++i) {
        for (std::size_t j = i + 1; j < input.atoms.size(); ++j) {
            const tricell::MinimumImage mi = box.minimum_image(
                tricell::Cartesian(input.atoms[j].position - input.atoms[i].position));
            std::printf("%s%zu-%s%zu %.6f  shift %d %d %d\n", input.atoms[i].name.c_str(), i,
                        input.atoms[j].name.c_str(), j, mi.distance, mi.shift[0], mi.shift[1],
                        mi.shift[2]);
        }
    }
}

} // namespace

int main(int argc, char** argv) {
    if (argc != 2) {
        std::fprintf(stderr, "usage: box_info FILE\n");
        return 2;
    }
    try {
        print(read_input(argv[1]));
    } catch (const tricell::Error& e) {
        std::fprintf(stderr, "box_info: %s\n", e.what());
        return 1;
    }
    return 0;
}
