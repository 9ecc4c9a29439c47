// The orders a stored list can be asked for, both with per-atom offsets (CSR). Grouped: by i,
// stable, so each atom's pairs keep the order the search found them in. The search meets an
// atom's pairs in runs of consecutive pairs (a search in cells writes a cell's atoms' pairs one
// atom at a time, tens of pairs each), so the grouping is a counting sort of the runs, not the
// pairs: one pass over i counts each atom's runs and pairs, a second puts the runs in atom order
// (an index of 12 bytes a run), and each column is then gathered run by run into one scratch
// column, written sequentially while the reads jump (prefetched a few runs ahead), and copied
// back. A list of short runs (under 16 pairs on average) is instead scattered run by run to
// each atom's cursor, without the index. Sorted: by i, then j, then S lexicographically; a
// counting sort on i followed by a comparison sort of each atom's own pairs by (j, S), which
// are few.
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
