// At most k nearest neighbours within the cutoff (NeighborOptions::max_neighbors), as the graphs
// of machine-learning potentials are built (ORB: 20 within 6 A; FAIRChem: up to 300). Each
// centre's pairs are ranked by (d, j, S), a total order (no two pairs of a centre share j and
// S), so the k kept are the same on every backend and for every thread count. It works on the
// full list in the search's order: a counting sort on i gathers each centre's (d, index) pairs,
// and a bucket sort on (d / d_max)^3 (a pair count grows as the cube of d, so the buckets hold
// about one pair each) orders a centre's pairs by bucket, after which only the buckets up to the
// k-th pair are sorted: no comparison sort of a whole centre's pairs. With a tie tolerance every
// other pair with d <= d_k + tolerance is kept too (the degeneracy rule of FAIRChem's mask,
// which compares with the (k+1)-th distance instead: its k is max_neighbors = k + 1 here). The
// symmetric rule then adds (j, i, -S) wherever (i, j, S) is kept and its reverse is not: the
// reverse pair is in the full list with exactly -D and the same d, so it is made from its
// forward pair, and whether the reverse is kept at j is one comparison with j's k-th key. The
// kept pairs are finally gathered, one column at a time through one scratch column, in the
// output order (docs/memory.md counts the ranking's pairs, the output order and that column).
#pragma once

#include <cstddef>

#include "tricell/neighbor_list.hpp"
#include "tricell/pair_columns.hpp"

namespace tricell::detail {

/// Keeps of `columns`, a full list in any order for `atoms` atoms that stores S and d, at most
/// options.max_neighbors pairs per centre by options' rule (see above), grouped by i, each
/// centre's in (d, j, S) order, and fills the offsets. `spare` is raw scratch memory kept
/// between calls (left empty, its capacity kept): max(16, the widest column's bytes) + 8 bytes
/// per pair (policy/list_limits.cpp counts them). Runs on `threads` threads (the calling
/// thread's team); the result does not depend on them.
void keep_nearest_within(PairColumns& columns, std::size_t atoms, const NeighborOptions& options,
                         std::size_t threads, PairArray<unsigned char>& spare);

} // namespace tricell::detail
