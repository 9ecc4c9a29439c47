// Translations between the plain C structs of tricell.h and the C++ types: nothing here
// computes geometry, it only copies fields and checks what C cannot express (flags, NULLs).
#pragma once

#include <vector>

#include "tricell.h"
#include "tricell/batch.hpp"
#include "tricell/box.hpp"
#include "tricell/neighbor_list.hpp"

namespace tricell::c_api {

/// The C++ box of a tricell_box (validated again by the C++ constructor).
Box to_box(const tricell_box& box);
/// The periodicity of three C ints, each required to be 0 or 1.
Periodicity to_periodicity(const int periodic[3]);
/// The C value of a C++ box.
tricell_box to_c_box(const Box& box);

/// Writes the C options for `atoms` positions into `out` (reusing its vectors' memory). Flags
/// must be 0 or 1; the values are left to the C++ API's own validation (NeighborSearch::build,
/// VerletOptions::validate). Reads `atoms` entries of radii and species when they are set.
void to_options(const tricell_neighbor_options& options, std::size_t atoms, NeighborOptions& out);
/// The C options of the C++ options (for the defaults).
tricell_neighbor_options to_c_options(const NeighborOptions& options);

/// A view of a stored list: pointers for the quantities in `stored` (and the offsets when
/// `offsets`), NULL for the others.
tricell_pairs to_pairs(const NeighborList& list, const Quantities& stored, bool offsets);
/// The same for a batch's lists, with its per-structure offsets.
tricell_batch_pairs to_batch_pairs(const BatchList& list, const Quantities& stored, bool offsets);

} // namespace tricell::c_api

/// The handles of tricell.h.
struct tricell_neighbor_search {
    tricell::NeighborSearch search;
    tricell::NeighborOptions options; // of the last call, kept for the memory of its vectors
};

struct tricell_neighbor_list {
    tricell::NeighborList list;
    tricell::Quantities stored; // what the last tricell_neighbors() asked for
    bool with_offsets = false;  // the last call's list is grouped by i with offsets
};

struct tricell_batch_list {
    tricell::BatchList list;
    std::vector<tricell::BatchStructure> structures; // of the last call, kept for their memory
    tricell::NeighborOptions options;                // likewise
    tricell::Quantities stored; // what the last tricell_neighbors_batch() asked for
    bool with_offsets = false;  // the last call's list is grouped by i with offsets
};
