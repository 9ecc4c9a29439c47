// At most k nearest neighbours within the cutoff (NeighborOptions::max_neighbors), as the graphs
// of machine-learning potentials are built (ORB: 20 within 6 A; FAIRChem: up to 300). It works
// on the full list grouped by centre: each centre's pairs are ranked by (d, j, S), a total order
// (no two pairs of a centre share j and S), so the k kept are the same on every backend and for
// every thread count. A selection (nth_element) finds the k-th pair of each centre with more
// than k; with a tie tolerance every other pair with d <= d_k + tolerance is kept too (the
// degeneracy rule of FAIRChem's mask, which compares with the (k+1)-th distance instead: its k is
// max_neighbors = k + 1 here). The symmetric rule then adds (j, i, -S) wherever (i, j, S) is
// kept and its reverse is not: the reverse pair is in the full list with exactly -D and the same
// d, so it is made from its forward pair, and whether the reverse is kept at j is one comparison
// with j's k-th key. Each centre's kept pairs are finally written in (d, j, S) order, one column
// at a time through one scratch column (docs/memory.md counts the permutation, the output order
// and that column).
#pragma once

#include <cstddef>

#include "tricell/neighbor_list.hpp"
#include "tricell/pair_columns.hpp"

namespace tricell::detail {

/// Keeps of `columns`, a full list grouped by i with offsets for `atoms` atoms that stores S and
/// d, at most options.max_neighbors pairs per centre by options' rule (see above), each
/// centre's in (d, j, S) order, and refills the offsets. `spare` is raw scratch memory kept
/// between calls (left empty, its capacity kept). Runs on `threads` threads (the calling
/// thread's team); the result does not depend on them.
void keep_nearest_within(PairColumns& columns, std::size_t atoms, const NeighborOptions& options,
                         std::size_t threads, PairArray<unsigned char>& spare);

} // namespace tricell::detail
