// The orders a stored list can be asked for. Sorted: by i, then j, then S lexicographically,
// with per-atom offsets (CSR). It is made by a counting sort on i (one pass over the pairs) and
// a comparison sort of each atom's own pairs by (j, S), which are few.
#pragma once

#include <cstddef>

#include "tricell/pair_columns.hpp"

namespace tricell::detail {

/// Sorts `columns` (S needed) by i, j, S and fills its offsets for `atoms` atoms.
void sort_pairs(PairColumns& columns, std::size_t atoms);

} // namespace tricell::detail
