// The orders a stored list can be asked for, both with per-atom offsets (CSR). Grouped: by i,
// stable, so each atom's pairs keep the order the search found them in; it is one counting sort
// on i (a histogram, a prefix sum, then each column scattered into one scratch column and copied
// back) that moves runs of consecutive pairs of one atom whole, since the search meets an atom's
// pairs several at a time. Sorted: by i, then j, then S lexicographically; the counting sort on i
// followed by a comparison sort of each atom's own pairs by (j, S), which are few.
#pragma once

#include <cstddef>

#include "tricell/pair_columns.hpp"

namespace tricell::detail {

/// Groups `columns` by i (stable) and fills its offsets for `atoms` atoms. `spare` is raw
/// scratch memory kept between calls: grown to the widest column, left empty with its capacity.
void group_pairs(PairColumns& columns, std::size_t atoms, PairArray<unsigned char>& spare);

/// Sorts `columns` (S needed) by i, j, S and fills its offsets for `atoms` atoms.
void sort_pairs(PairColumns& columns, std::size_t atoms);

} // namespace tricell::detail
