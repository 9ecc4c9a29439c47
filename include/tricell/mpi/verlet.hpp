// A Verlet list over ranks: ghosts and candidates at r_c + skin, rebuilt when ALL ranks agree.
//
// A build migrates the atoms to their owners, exchanges ghosts within the list radius
// r_l = r_c + skin of each domain (for a half list the upper ones, halo.hpp) and searches the
// candidates of the owned atoms among the owned and ghost atoms in the local frame (halo.hpp;
// "Candidates" below). Between builds atoms stay with the rank that owned them at the build, even
// when they drift out of its domain. In each update() every rank applies the serial list's
// rebuild rule (tricell/displacement.hpp: skin / 2 in a fixed box, less when the box deforms) to
// its owned atoms, and one MPI_Allreduce (joined with the input check; a kept update's only
// collective) decides for everybody: if any atom anywhere moved past the budget, every rank
// rebuilds (migration, halo, candidates); otherwise the ghosts are refreshed from their owners
// (as Halo::update: same ghosts, new positions) and every rank only filters its candidates. A
// rebuild's migration goes to the halo's neighbour ranks only when every atom's new owner is one
// of them (the usual case), else through the MPI_Alltoall of migrate().
//
// Why the ghosts need no reselection between builds: at the build every owned atom i was inside
// its domain and every image of j within r_l of it was a ghost (for a half list, every image
// upper on i's rank, the rank the pair belongs to). While no atom has moved more
// than the budget, a pair now within r_c was within r_l at the build (the serial list's
// argument), so its j image is still among the ghosts, at its owner's current position.
//
// Why each rank checks only its owned atoms. A ghost's local position is its owner's plus H T
// (halo.hpp), so its fractional displacement since the build is its owner's: the owner's rank
// measures it, and the MPI_Allreduce of the vote covers every ghost on every rank.
//
// Candidates. A build searches the owned atoms' subset (NeighborOptions::query, no ghost-ghost
// pair) over the local atoms, in the box's frame with every axis open, at the list radius
// (widened by the serial list's rounding margins), and applies the list's rule to each local
// pair ONCE (full: both orientations whose i is owned; half: the orientation of neighbors.hpp,
// Newton's third law across ranks). A pair's orientation never changes between builds (its
// owned end, or global ids, decide it, and the image shift of an atom with its own image is the
// fixed translation of the ghost), so the candidates are kept already oriented, grouped by their
// owned i. Each update() then only filters them at r_c from the local positions, D = y_j - y_i, and
// writes the global ids: per step a rank does what the serial VerletList's refresh does, plus
// the halo update before it and the caller's reverse_sum() after the force loop.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "tricell/box.hpp"
#include "tricell/displacement.hpp"
#include "tricell/mpi/atoms.hpp"
#include "tricell/mpi/decomposition.hpp"
#include "tricell/mpi/export.hpp"
#include "tricell/mpi/halo.hpp"
#include "tricell/mpi/neighbors.hpp"
#include "tricell/mpi/traffic.hpp"
#include "tricell/neighbor_list.hpp"
#include "tricell/verlet.hpp"

namespace tricell::mpi {

class TRICELL_MPI_API DistributedVerletList {
  public:
    DistributedVerletList() = default;
    /// options as for tricell::VerletList; half follows the rule of neighbors.hpp (upper halo).
    explicit DistributedVerletList(const VerletOptions& options);

    /// r_l = cutoff + skin: the halo's reach and the candidates' radius.
    double list_radius() const { return options_.neighbors.cutoff + options_.skin; }

    /// Collective. Refreshes this rank's pairs for the current positions (caller positions,
    /// wrapped or not) and box. When the ranks agree to rebuild, atoms migrate first: `atoms`
    /// (ids, positions, payload) may then change order and size. Returns true if it rebuilt.
    /// Bad input on any rank (a non-finite position, ...) throws on every rank; the pairs are
    /// then left empty and the next update() rebuilds.
    bool update(const Decomposition& decomposition, const Box& box, LocalAtoms& atoms);
    /// Collective. Refreshes the ghosts' positions from their owners' current `atoms` (the same
    /// atoms as the last update(), in the same order), without a search or a rebuild vote:
    /// update() does this itself; call it alone to read fresh ghost positions (halo()) between
    /// updates.
    void forward(const Decomposition& decomposition, const Box& box, const LocalAtoms& atoms);
    /// Collective. Halo::forward() of this list's halo: `width` doubles per local atom
    /// (halo().size() rows); each ghost row becomes a copy of its owner's row.
    void forward_values(const Decomposition& decomposition, std::vector<double>& values,
                        std::size_t width) const;
    /// Collective. Halo::reverse_sum() of this list's halo: `width` doubles per local atom
    /// (halo().size() rows: owned, then ghosts); each ghost row is added into its owner's row.
    void reverse_sum(const Decomposition& decomposition, std::vector<double>& values,
                     std::size_t width) const;

    /// This rank's pairs of the last update(), grouped by their owned i (pairs.owned ascending).
    const DistributedPairs& pairs() const { return pairs_; }
    const Halo& halo() const { return halo_; }
    std::size_t rebuild_count() const { return rebuild_count_; }
    /// Candidate pairs of this rank's current build (at the list radius, already oriented).
    std::size_t candidate_count() const { return candidate_b_.size(); }
    /// Rebuilds whose migration needed the MPI_Alltoall (the first, and any where some atom's
    /// new owner was not a halo neighbour); the others exchanged with the neighbours only.
    std::size_t alltoall_migrations() const { return alltoall_migrations_; }
    /// What this rank sent, by kind (see ListTraffic).
    const ListTraffic& traffic() const { return traffic_; }
    void reset_traffic() { traffic_ = ListTraffic(); }
    /// Forgets the build; the next update() rebuilds.
    void reset();

  private:
    void build(const Decomposition& decomposition, const Box& open);
    void refresh();

    VerletOptions options_;
    Halo halo_;
    // The owned atoms' local positions at the build, in the open box of the build.
    DisplacementTracker tracker_;
    NeighborSearch search_;
    NeighborList raw_;
    DistributedPairs oriented_;
    // Candidates grouped by owned i (CSR): j's local index.
    std::vector<std::size_t> candidate_offsets_;
    std::vector<std::uint32_t> candidate_b_;
    DistributedPairs pairs_;
    bool built_ = false;
    bool halo_built_ = false; // on every rank alike: at the same collective rebuilds
    Periodicity built_periodicity_;
    std::size_t rebuild_count_ = 0;
    std::size_t alltoall_migrations_ = 0;
    mutable ListTraffic traffic_; // counted by the const forward_values() and reverse_sum()
};

} // namespace tricell::mpi
