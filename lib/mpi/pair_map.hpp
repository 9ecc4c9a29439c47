// From a rank's local half list (owned + ghost atoms, local frame) to its global pairs, by the
// full-list and half-list rules of tricell/mpi/neighbors.hpp (which pairs a rank reports, and
// in which orientation). The one place those rules are written.
#pragma once

#include <cstddef>
#include <cstdint>
#include <type_traits>

#include "tricell/mpi/halo.hpp"
#include "tricell/mpi/neighbors.hpp"
#include "tricell/neighbor_list.hpp"

namespace tricell::mpi::detail {

/// The local search options every rank runs: the caller's, as a half list of the subset of the
/// `owned` first local atoms (the owned ones), storing d and D as the caller asks (S comes from
/// the halo images).
NeighborOptions local_options(const NeighborOptions& caller, std::size_t owned);

/// Replaces out with the global pairs of `local` (a half list of the owned atoms' subset over
/// halo's local atoms, with the distances and vectors quantities asks): full, or half by the
/// half-list rule (halo must then be an upper halo); sorted by (i, j, S) if asked.
void map_pairs(const NeighborList& local, const Halo& halo, bool half, bool sorted,
               const Quantities& quantities, DistributedPairs& out);

/// Raw pointers to the columns of a DistributedPairs, for the writers (map_pairs, the distributed
/// Verlet list's refresh) that fill arrays sized for the most pairs there can be and then trim
/// them to the pairs kept.
struct ColumnPointers {
    std::uint32_t* owned;
    std::uint32_t* local_j;
    std::uint64_t* i;
    std::uint64_t* j;
    std::int32_t* shifts;
    double* distances;
    double* vectors;
};

/// Resizes every column of `out` to `n` pairs (S, d and D only where kept; PairArray does not
/// zero-fill) and returns pointers to them.
ColumnPointers resize_columns(DistributedPairs& out, std::size_t n, bool shifts, bool distances,
                              bool vectors);

/// Calls f with std::true_type or std::false_type: one instantiation per flag, no branch inside.
template <class F> std::size_t with_flag(bool flag, F f) {
    return flag ? f(std::true_type{}) : f(std::false_type{});
}

} // namespace tricell::mpi::detail
