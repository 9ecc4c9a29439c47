// From a rank's local half list (owned + ghost atoms, local frame) to its global pairs, by the
// full-list and half-list ownership rules of tricell/mpi/neighbors.hpp. The one place those
// rules are written.
#pragma once

#include <cstddef>

#include "tricell/mpi/halo.hpp"
#include "tricell/mpi/neighbors.hpp"
#include "tricell/neighbor_list.hpp"

namespace tricell::mpi::detail {

/// The local search options every rank runs: the caller's, as a half list of the subset of the
/// `owned` first local atoms (the owned ones), storing d and D.
NeighborOptions local_options(const NeighborOptions& caller, std::size_t owned);

/// Replaces out with the global pairs of `local` (a half list of the owned atoms' subset over
/// halo's local atoms, with distances and vectors): full, or half by the ownership rule; sorted by
/// (i, j, S) if asked.
void map_pairs(const NeighborList& local, const Halo& halo, bool half, bool sorted,
               const Quantities& quantities, DistributedPairs& out);

} // namespace tricell::mpi::detail
