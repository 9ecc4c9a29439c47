// Neighbour lists over ranks: each rank lists the pairs of the atoms it owns.
//
// A rank gathers ghosts within the cutoff of its domain (tricell::mpi::Halo), then runs the
// serial search (tricell::NeighborSearch, any backend, with the caller's options) over its
// owned and ghost atoms in their continuous local frame, in the box's frame with every axis
// open (the ghosts already are the periodic images), as a half list of the subset of the owned
// atoms (NeighborOptions::query): owned-owned pairs once, owned-ghost pairs once from the owned
// end, ghost-ghost pairs never searched. Each local pair a -> b (and b -> a when both are owned)
// maps to the global pair (id(a), id(b), S = c_a - c_b), see halo.hpp, and is kept by the rule
// below. Over all ranks (docs/contract.md, MPI):
//
// - full list: every (i, j, S) of the serial full list with i owned by this rank, once; the halo
//   holds every ghost (GhostSet::all).
// - half list (Newton's third law across ranks): the halo holds the upper ghosts only
//   (GhostSet::upper, halo.hpp "Upper halos"), so each owned-ghost pair is within reach of one
//   rank only, the one where its ghost is upper, and is reported there once, oriented from its
//   owned end (i owned, j the ghost); an owned-owned pair is reported by its rank once, in the
//   serial list's canonical orientation (i < j, or i == j with S lexicographically positive).
//   Each pair is reported exactly once over all ranks and, up to orientation, the union is the
//   serial half list. Like LAMMPS's "newton on" (a half stencil; LAMMPS decides owned-ghost
//   pairs by coordinates, tricell by the domain grid, which needs no tie-break under rounding),
//   each owned-ghost pair is searched once, on one rank: a force loop adds the pair's force to
//   i and its opposite to the ghost row local_j, and Halo::reverse_sum() (or
//   DistributedVerletList::reverse_sum()) then adds every ghost's force into its owner. A full
//   list needs no reverse communication but computes each force twice.
//
// Indices are global ids; S is relative to the positions the owners hold; D = x_j - x_i + H S
// and d are computed from the local frame (the same doubles as a serial search up to rounding).
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "tricell/box.hpp"
#include "tricell/mpi/atoms.hpp"
#include "tricell/mpi/decomposition.hpp"
#include "tricell/mpi/export.hpp"
#include "tricell/mpi/halo.hpp"
#include "tricell/neighbor_list.hpp"

namespace tricell::mpi {

/// The pairs one rank reports, in the shared pair columns (tricell/pair_columns.hpp) with global
/// ids as i and j; i is always one of this rank's atoms. S, d and D are stored as
/// Quantities asks.
struct TRICELL_MPI_API DistributedPairs : BasicPairColumns<std::uint64_t> {
    /// Index of i among the caller's owned atoms (LocalAtoms order), per pair.
    PairArray<std::uint32_t> owned;
    /// Index of j among the halo's local atoms (owned first, in LocalAtoms order, then ghosts),
    /// per pair: where a force loop puts the force on j before Halo::reverse_sum().
    PairArray<std::uint32_t> local_j;

    /// Empties the lists, keeping their capacity.
    void clear() {
        BasicPairColumns<std::uint64_t>::clear();
        owned.clear();
        local_j.clear();
    }
};

/// Halo plus local search for one configuration. build() is collective; compute() is local.
class TRICELL_MPI_API DistributedSearch {
  public:
    /// Collective. options as for tricell::NeighborSearch (cutoff, half, quantities, sorted,
    /// backend and tuning); the atoms must be owned by this rank (migrate() first). Variable
    /// cutoffs work too: options.radii and options.species then hold one value per OWNED atom,
    /// in the order of `atoms` (ghosts get their owners'); the halo reaches twice the largest
    /// radius over all ranks, or the largest cutoff of options.species_cutoffs.
    void build(const Decomposition& decomposition, const Box& box, const LocalAtoms& atoms,
               const NeighborOptions& options);
    /// This rank's pairs, as the options asked (sorted or grouped: by i, then j, then S, without
    /// offsets, since i is a global id).
    void compute(DistributedPairs& out) const;
    const Halo& halo() const { return halo_; }

  private:
    NeighborOptions options_;
    Halo halo_;
    NeighborSearch local_;
    mutable NeighborList scratch_;
};

/// Collective convenience: build a DistributedSearch and return this rank's pairs.
TRICELL_MPI_API DistributedPairs compute_neighbors(const Decomposition& decomposition,
                                                   const Box& box, const LocalAtoms& atoms,
                                                   const NeighborOptions& options);

} // namespace tricell::mpi
