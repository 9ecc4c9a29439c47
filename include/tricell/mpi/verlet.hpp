// A Verlet list over ranks: ghosts and candidates at r_c + skin, rebuilt when ALL ranks agree.
//
// A build migrates the atoms to their owners, exchanges ghosts within the list radius
// r_l = r_c + skin of each domain and builds a serial tricell::VerletList over the owned and
// ghost atoms in the local frame (halo.hpp). Between builds atoms stay with the rank that owned
// them at the build, even when they drift out of its domain. Each update() first refreshes the
// ghosts from their owners (Halo::update: same ghosts, new positions), then every rank measures
// the largest displacement of its local atoms since the build and the displacement budget of
// the serial list (skin / 2 in a fixed box, less when the box deforms; see tricell/verlet.hpp),
// and one MPI_Allreduce (MAX of displacement - budget) decides for everybody: if any atom
// anywhere moved past the budget, every rank rebuilds (migration, halo, candidates); otherwise
// every rank only filters its candidates. A rebuild's migration goes to the halo's neighbour
// ranks only when every atom's new owner is one of them (the usual case), else through the
// MPI_Alltoall of migrate().
//
// Why the ghosts need no reselection between builds: at the build every owned atom i was inside
// its domain and every image of j within r_l of it was a ghost. While no atom has moved more
// than the budget, a pair now within r_c was within r_l at the build (the serial list's
// argument), so its j image is still among the ghosts, at its owner's current position. The
// pairs of update() are mapped to global (i, j, S) by the rules of neighbors.hpp (full, or half
// with the ownership rule: Newton's third law across ranks, forces on ghosts summed back by
// reverse_sum()). The local list is a Verlet list of the owned atoms' subset (no ghost-ghost
// candidates).
#pragma once

#include <cstddef>
#include <vector>

#include "tricell/box.hpp"
#include "tricell/mpi/atoms.hpp"
#include "tricell/mpi/decomposition.hpp"
#include "tricell/mpi/export.hpp"
#include "tricell/mpi/halo.hpp"
#include "tricell/mpi/neighbors.hpp"
#include "tricell/verlet.hpp"

namespace tricell::mpi {

class TRICELL_MPI_API DistributedVerletList {
  public:
    DistributedVerletList() = default;
    /// options as for tricell::VerletList; half follows the ownership rule of neighbors.hpp.
    explicit DistributedVerletList(const VerletOptions& options);

    /// Collective. Refreshes this rank's pairs for the current positions (caller positions,
    /// wrapped or not) and box. When the ranks agree to rebuild, atoms migrate first: `atoms`
    /// (ids, positions, payload) may then change order and size. Returns true if it rebuilt.
    bool update(const Decomposition& decomposition, const Box& box, LocalAtoms& atoms);
    /// Collective. Refreshes the ghosts' positions from their owners' current `atoms` (the same
    /// atoms as the last update(), in the same order), without a search or a rebuild vote:
    /// update() does this itself; call it alone to read fresh ghost positions (halo()) between
    /// updates.
    void forward(const Decomposition& decomposition, const Box& box, const LocalAtoms& atoms);
    /// Collective. Halo::reverse_sum() of this list's halo: `width` doubles per local atom
    /// (halo().size() rows: owned, then ghosts); each ghost row is added into its owner's row.
    void reverse_sum(const Decomposition& decomposition, std::vector<double>& values,
                     std::size_t width) const;

    const DistributedPairs& pairs() const { return pairs_; }
    const Halo& halo() const { return halo_; }
    std::size_t rebuild_count() const { return rebuild_count_; }
    /// Rebuilds whose migration needed the MPI_Alltoall (the first, and any where some atom's
    /// new owner was not a halo neighbour); the others exchanged with the neighbours only.
    std::size_t alltoall_migrations() const { return alltoall_migrations_; }
    /// Forgets the build; the next update() rebuilds.
    void reset();

  private:
    VerletOptions options_;
    Halo halo_;
    VerletList local_;
    DistributedPairs pairs_;
    bool built_ = false;
    bool halo_built_ = false; // on every rank alike: at the same collective rebuilds
    Periodicity built_periodicity_;
    std::size_t rebuild_count_ = 0;
    std::size_t alltoall_migrations_ = 0;
};

} // namespace tricell::mpi
