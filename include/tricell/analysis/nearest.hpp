// The k nearest neighbours (j, S) of every atom, over periodic images.
//
// An atom's candidates are every (j, S) except (i, 0): other atoms and every periodic image of
// every atom, its own included, so k may exceed the number of atoms when an axis is periodic.
// They are ordered by distance d = |x_j - x_i + H S| (the value the neighbour search computes),
// ties broken by j, then S lexicographically, so the result is deterministic (the same for
// every backend and thread count).
//
// How: no all-pairs scan. A radius where about k neighbours are expected is estimated from the
// density (the search's own estimate: N over the volume the atoms occupy, the cell along
// periodic axes and the extent of the positions along open ones); one half-list search at that
// radius keeps, per atom, its k best candidates in a bounded heap (memory O(N k), nothing else
// stored). Atoms left with fewer than k candidates make the radius grow (by the cube root of the
// worst shortfall, between 1.25 and 2 times) and the search run again for them, until every
// atom has k. The work is that of a neighbour list holding about N k pairs.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "tricell/box.hpp"
#include "tricell/export.hpp"
#include "tricell/neighbor_list.hpp"
#include "tricell/types.hpp"

namespace tricell {

/// Atom i's neighbours are entries [i * k, (i + 1) * k), nearest first.
struct NearestNeighbors {
    std::size_t k = 0;
    std::vector<std::uint32_t> j;
    /// 3 ints per entry: S relative to the positions as given (docs/contract.md), so
    /// D = x_j - x_i + H S.
    std::vector<std::int32_t> shifts;
    std::vector<double> distances;

    /// Number of atoms.
    std::size_t size() const { return k == 0 ? 0 : j.size() / k; }
    Shift shift(std::size_t entry) const {
        return Shift(shifts[3 * entry], shifts[3 * entry + 1], shifts[3 * entry + 2]);
    }
};

struct NearestOptions {
    /// Threads of each search (NeighborOptions::threads; 0 means all). Never changes the result.
    int threads = 1;
    /// Search backend. Never changes the result.
    SearchBackend backend = SearchBackend::automatic;
};

/// The k nearest (j, S) of every atom (see the top of this header). k >= 1. Throws
/// InvalidArgument when k is 0, when the system is open along every axis and has fewer than
/// k + 1 atoms (naming k and N), or for what NeighborSearch::build() refuses (non-finite
/// positions); GeometryError for a bad box. No atoms give an empty result.
TRICELL_API NearestNeighbors nearest_neighbors(const Box& box, PointsView positions, std::size_t k,
                                               const NearestOptions& options = {});

} // namespace tricell
