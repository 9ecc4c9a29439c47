// spglib bindings: space group of a structure and Niggli reduction of a box.
//
// spglib takes the lattice with the vectors as columns (lattice[i][j] = component i of vector
// j, the same layout as tricell's H), fractional positions and an integer type per atom. It
// reports errors through spg_get_error_code(); its messages are passed on.
#include "tricell/io/symmetry.hpp"

#include <cmath>
#include <map>
#include <utility>

#include <spglib.h>

#include "tricell/error.hpp"

namespace tricell::io {

namespace {

void require_periodic(const Box& box, const char* what) {
    if (box.periodicity().count() != 3) {
        tricell::detail::fail<InvalidArgument>(what, " needs a box periodic along a, b and c");
    }
}

void require_tolerance(double value, const char* name) {
    if (!(std::isfinite(value) && value > 0)) {
        tricell::detail::fail<InvalidArgument>(name, " must be > 0 (got ", value, ")");
    }
}

std::string spglib_error() {
    return spg_get_error_message(spg_get_error_code());
}

} // namespace

SpaceGroupInfo find_space_group(const Structure& structure, double symprec) {
    require_tolerance(symprec, "symprec");
    require_periodic(structure.box, "the space group");
    const std::size_t n = structure.size();
    if (n == 0) {
        tricell::detail::fail<InvalidArgument>("the space group needs at least one atom");
    }
    double lattice[3][3];
    for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) {
            lattice[i][j] = structure.box.matrix()(i, j);
        }
    }
    std::vector<double> positions(3 * n);
    std::vector<int> types(n);
    std::map<std::pair<std::string, double>, int> type_of;
    for (std::size_t k = 0; k < n; ++k) {
        const Fractional s = structure.box.to_fractional(Cartesian(structure.positions[k]));
        for (int c = 0; c < 3; ++c) {
            positions[3 * k + std::size_t(c)] = s[c];
        }
        const double occupancy = k < structure.occupancies.size() ? structure.occupancies[k] : 1;
        const auto key = std::make_pair(structure.species[k], occupancy);
        types[k] = type_of.emplace(key, int(type_of.size()) + 1).first->second;
    }
    SpglibDataset* dataset = spg_get_dataset(
        lattice, reinterpret_cast<double(*)[3]>(positions.data()), types.data(), int(n), symprec);
    if (dataset == nullptr) {
        tricell::detail::fail<GeometryError>("spglib found no space group (", spglib_error(),
                                             ") with symprec ", symprec);
    }
    SpaceGroupInfo info;
    info.number = dataset->spacegroup_number;
    info.international = dataset->international_symbol;
    info.hall = dataset->hall_symbol;
    spg_free_dataset(dataset);
    return info;
}

Box niggli_reduce(const Box& box, double tolerance) {
    require_tolerance(tolerance, "the Niggli tolerance");
    require_periodic(box, "Niggli reduction");
    double lattice[3][3];
    for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) {
            lattice[i][j] = box.matrix()(i, j);
        }
    }
    if (spg_niggli_reduce(lattice, tolerance) == 0) {
        tricell::detail::fail<GeometryError>("spglib could not Niggli-reduce the cell (",
                                             spglib_error(), ")");
    }
    Eigen::Matrix3d h;
    for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) {
            h(i, j) = lattice[i][j];
        }
    }
    return Box::from_columns(h, box.periodicity());
}

std::string spglib_version() {
    return std::to_string(spg_get_major_version()) + "." + std::to_string(spg_get_minor_version()) +
           "." + std::to_string(spg_get_micro_version());
}

} // namespace tricell::io
