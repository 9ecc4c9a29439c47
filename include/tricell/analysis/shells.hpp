// Neighbour lists at several cutoffs r_1 < r_2 < ... < r_m from one search.
//
// One search at the largest cutoff r_m; its pairs are then ordered by shell: first every pair
// with d < r_1, then those with r_1 <= d < r_2, and so on (within a shell, in the order the search
// gives, i.e. by i, j, S with NeighborOptions::sorted). So the list at cutoff r_k is the prefix
// [0, offsets[k + 1]) of one list, holding exactly the (i, j, S) and the same d that a separate
// compute_neighbors() at cutoff r_k gives (the test d < r_k is the search's own). The cost is
// one search at r_m plus a stable counting sort of its pairs by shell.
#pragma once

#include <cstddef>
#include <vector>

#include "tricell/box.hpp"
#include "tricell/export.hpp"
#include "tricell/neighbor_list.hpp"
#include "tricell/types.hpp"

namespace tricell {

/// Pairs of several cutoffs, ordered by shell.
struct ShellNeighborList {
    /// The cutoffs, strictly increasing.
    std::vector<double> cutoffs;
    /// cutoffs.size() + 1 entries: shell k (cutoffs[k - 1] <= d < cutoffs[k], from 0 for k = 0)
    /// is [offsets[k], offsets[k + 1]); the list at cutoffs[k] is [0, offsets[k + 1]).
    std::vector<std::size_t> offsets;
    /// The pairs, with the quantities NeighborOptions::quantities asked for. With
    /// NeighborOptions::sorted each shell is sorted by i, j, S and pairs.offsets() is empty
    /// (per-atom offsets do not apply to a list ordered by shell).
    NeighborList pairs;

    /// Number of pairs within cutoffs[k].
    std::size_t count(std::size_t k) const { return offsets[k + 1]; }
};

/// Lists at every cutoff of `cutoffs` (finite, > 0, strictly increasing, at least one) from one
/// search at the largest. `options` is used as given except that its `cutoff` must stay 0 and
/// variable cutoffs (radii, species_cutoffs) are refused: InvalidArgument naming the value.
TRICELL_API ShellNeighborList compute_neighbors(const Box& box, PointsView positions,
                                                const std::vector<double>& cutoffs,
                                                const NeighborOptions& options);

} // namespace tricell
