#include "translate.hpp"

#include <cstdint>
#include <limits>

#include "boundary.hpp"
#include "tricell/error.hpp"

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

static_assert(int(SearchBackend::automatic) == TRICELL_BACKEND_AUTOMATIC &&
                  int(SearchBackend::dense) == TRICELL_BACKEND_DENSE &&
                  int(SearchBackend::linked) == TRICELL_BACKEND_LINKED &&
                  int(SearchBackend::hash) == TRICELL_BACKEND_HASH &&
                  int(SearchBackend::octree) == TRICELL_BACKEND_OCTREE &&
                  int(SearchBackend::direct) == TRICELL_BACKEND_DIRECT,
              "tricell_backend follows tricell::SearchBackend");

void to_options(const tricell_neighbor_options& options, std::size_t atoms, NeighborOptions& out) {
    out.cutoff = options.cutoff;
    out.half = require_flag(options.half, "options.half");
    out.sorted = require_flag(options.sorted, "options.sorted");
    out.grouped = require_flag(options.grouped, "options.grouped");
    out.quantities.shifts = require_flag(options.shifts, "options.shifts");
    out.quantities.distances = require_flag(options.distances, "options.distances");
    out.quantities.vectors = require_flag(options.vectors, "options.vectors");
    out.threads = options.threads;
    // Any int fits SearchBackend's underlying type; NeighborOptions::validate() names a bad one.
    out.backend = static_cast<SearchBackend>(options.backend);
    out.max_pairs = options.max_pairs;
    out.max_bytes = options.max_bytes;
    // Past the C++ limit on atoms nothing is copied: the search refuses the count itself.
    const bool copy = atoms < std::size_t(std::numeric_limits<std::int32_t>::max());
    if (options.radii != nullptr && copy) {
        out.radii.assign(options.radii, options.radii + atoms);
    } else {
        out.radii.clear();
    }
    if (options.species != nullptr && copy) {
        out.species.assign(options.species, options.species + atoms);
    } else {
        out.species.clear();
    }
    out.species_cutoffs.clear();
    if (options.species_cutoff_count > 0) {
        if (options.species_cutoffs == nullptr) {
            detail::fail<InvalidArgument>("options.species_cutoffs is NULL but "
                                          "options.species_cutoff_count is ",
                                          options.species_cutoff_count);
        }
        const tricell_species_cutoff* table = options.species_cutoffs;
        out.species_cutoffs.reserve(options.species_cutoff_count);
        for (std::size_t k = 0; k < options.species_cutoff_count; ++k) {
            out.species_cutoffs.push_back(SpeciesCutoff{table[k].a, table[k].b, table[k].cutoff});
        }
    }
    out.max_neighbors = options.max_neighbors;
    out.tie_tolerance = options.tie_tolerance;
    out.symmetric = require_flag(options.symmetric, "options.symmetric");
    out.query.reset();
    if (options.query != nullptr) {
        out.query.emplace(options.query, options.query + options.query_count);
    } else if (options.query_count > 0) {
        detail::fail<InvalidArgument>("options.query is NULL but options.query_count is ",
                                      options.query_count);
    }
}

tricell_neighbor_options to_c_options(const NeighborOptions& options) {
    tricell_neighbor_options out;
    out.cutoff = options.cutoff;
    out.half = options.half ? 1 : 0;
    out.sorted = options.sorted ? 1 : 0;
    out.grouped = options.grouped ? 1 : 0;
    out.shifts = options.quantities.shifts ? 1 : 0;
    out.distances = options.quantities.distances ? 1 : 0;
    out.vectors = options.quantities.vectors ? 1 : 0;
    out.threads = options.threads;
    out.backend = static_cast<int>(options.backend);
    out.max_pairs = options.max_pairs;
    out.max_bytes = options.max_bytes;
    out.radii = nullptr;
    out.species = nullptr;
    out.species_cutoffs = nullptr;
    out.species_cutoff_count = 0;
    out.query = nullptr;
    out.query_count = 0;
    out.max_neighbors = options.max_neighbors;
    out.tie_tolerance = options.tie_tolerance;
    out.symmetric = options.symmetric ? 1 : 0;
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

// The columns of a list or a batch (same accessors) as a view.
template <class List>
tricell_pairs columns_view(const List& list, const Quantities& stored, bool offsets) {
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
} // namespace

tricell_pairs to_pairs(const NeighborList& list, const Quantities& stored, bool offsets) {
    return columns_view(list, stored, offsets);
}

tricell_batch_pairs to_batch_pairs(const BatchList& list, const Quantities& stored, bool offsets) {
    tricell_batch_pairs out;
    out.structures = list.structure_count();
    out.pair_offsets = list.pair_offsets().empty() ? &no_offset : list.pair_offsets().data();
    out.atom_offsets = list.atom_offsets().empty() ? &no_offset : list.atom_offsets().data();
    out.pairs = columns_view(list, stored, offsets);
    return out;
}

} // namespace tricell::c_api
