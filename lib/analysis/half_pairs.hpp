// How the analysis functions see the pairs of a configuration: every pair of the half list
// within a cutoff, once, as (i, j, S, d), from the one neighbour search.
//
// On one thread the pairs stream through NeighborSearch::for_each_pair() and nothing is stored
// (constant memory whatever the cutoff). With threads != 1 the half list is computed by the
// threaded compute() and then visited, because for_each_pair() runs on the calling thread only;
// that stores i, j, S and d, 24 bytes per pair. Either way the visitor sees the same set of
// (i, j, S, d), so a result that only sums over pairs (a histogram, a bounded heap with a total
// order) does not depend on the number of threads. No pair limit applies (max_pairs = 0): the
// caller asked for every pair within its radius (nor does max_bytes).
#pragma once

#include <cmath>
#include <cstdint>

#include "tricell/neighbor_list.hpp"

namespace tricell::detail {

/// Calls visit(i, j, s, d) (s: three ints, S relative to the positions as given; d = |D|) once
/// for every pair of the half list of `options` (whose half, max_pairs, max_bytes and quantities
/// are set here; cutoff, backend and threads are the caller's).
template <class Visit>
void for_each_half_pair(const Box& box, PointsView positions, NeighborOptions options,
                        Visit&& visit) {
    options.half = true;
    options.sorted = false;
    options.grouped = false;
    options.max_pairs = 0;
    options.max_bytes = 0;
    options.quantities = Quantities{true, true, false};
    NeighborSearch search;
    search.build(box, positions, options);
    if (options.threads == 1) {
        search.for_each_pair([&](const Pair& pair) {
            const std::int32_t s[3] = {pair.shift[0], pair.shift[1], pair.shift[2]};
            visit(pair.i, pair.j, s, std::sqrt(pair.distance_sq));
        });
        return;
    }
    NeighborList list;
    search.compute(list);
    for (std::size_t k = 0; k < list.size(); ++k) {
        visit(list.i()[k], list.j()[k], list.shifts().data() + 3 * k, list.distances()[k]);
    }
}

} // namespace tricell::detail
