#include "translate.hpp"

#include "boundary.hpp"

namespace tricell::c_api {

Periodicity to_periodicity(const int periodic[3]) {
    static const char* const names[3] = {"periodic[0]", "periodic[1]", "periodic[2]"};
    Periodicity pbc;
    for (int k = 0; k < 3; ++k) {
        pbc.axes[std::size_t(k)] = require_flag(periodic[k], names[k]);
    }
    return pbc;
}

Box to_box(const tricell_box& box) {
    Eigen::Matrix3d rows;
    for (int k = 0; k < 3; ++k) {
        for (int c = 0; c < 3; ++c) {
            rows(k, c) = box.vectors[k][c];
        }
    }
    return Box::from_rows(rows, to_periodicity(box.periodic));
}

tricell_box to_c_box(const Box& box) {
    tricell_box out;
    for (int k = 0; k < 3; ++k) {
        for (int c = 0; c < 3; ++c) {
            out.vectors[k][c] = box.matrix()(c, k);
        }
        out.periodic[k] = box.periodic(k) ? 1 : 0;
    }
    return out;
}

NeighborOptions to_options(const tricell_neighbor_options& options) {
    NeighborOptions out;
    out.cutoff = options.cutoff;
    out.half = require_flag(options.half, "options.half");
    out.sorted = require_flag(options.sorted, "options.sorted");
    out.quantities.shifts = require_flag(options.shifts, "options.shifts");
    out.quantities.distances = require_flag(options.distances, "options.distances");
    out.quantities.vectors = require_flag(options.vectors, "options.vectors");
    out.threads = options.threads;
    out.max_pairs = options.max_pairs;
    return out;
}

tricell_neighbor_options to_c_options(const NeighborOptions& options) {
    tricell_neighbor_options out;
    out.cutoff = options.cutoff;
    out.half = options.half ? 1 : 0;
    out.sorted = options.sorted ? 1 : 0;
    out.shifts = options.quantities.shifts ? 1 : 0;
    out.distances = options.quantities.distances ? 1 : 0;
    out.vectors = options.quantities.vectors ? 1 : 0;
    out.threads = options.threads;
    out.max_pairs = options.max_pairs;
    return out;
}

namespace {
// Where a stored but empty quantity points, so that "stored" and "NULL" never coincide.
const std::uint32_t no_index = 0;
const std::int32_t no_shift = 0;
const double no_value = 0;
const std::size_t no_offset = 0;

template <class T> const T* data_or(const PairArray<T>& v, const T* empty) {
    return v.empty() ? empty : v.data();
}
} // namespace

tricell_pairs to_pairs(const NeighborList& list, const Quantities& stored, bool offsets) {
    tricell_pairs out;
    out.size = list.size();
    out.i = data_or(list.i(), &no_index);
    out.j = data_or(list.j(), &no_index);
    out.shifts = stored.shifts ? data_or(list.shifts(), &no_shift) : nullptr;
    out.distances = stored.distances ? data_or(list.distances(), &no_value) : nullptr;
    out.vectors = stored.vectors ? data_or(list.vectors(), &no_value) : nullptr;
    if (!offsets) {
        out.atoms = 0;
        out.offsets = nullptr;
    } else if (list.offsets().empty()) {
        out.atoms = 0;
        out.offsets = &no_offset;
    } else {
        out.atoms = list.offsets().size() - 1;
        out.offsets = list.offsets().data();
    }
    return out;
}

} // namespace tricell::c_api
