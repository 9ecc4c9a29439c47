// The atoms a rank owns, and their migration to the ranks that own their positions.
//
// Each rank keeps its atoms as the caller does: a global id, the Cartesian position exactly as
// the caller holds it (wrapped or not, any number of box lengths away; image shifts S in every
// list are relative to these positions), and optionally a fixed number of doubles per atom
// (velocities, charges, ...) that travel with the atom. migrate() sends every atom to the rank
// whose domain contains its wrapped fractional position, positions unchanged. It is one
// MPI_Alltoall of counts and one MPI_Alltoallv of records, so atoms may go anywhere (a first
// distribution, a rebalance, a long jump); the received atoms are ordered by source rank, each
// source's in its own order, so the result is deterministic. When the atoms have moved only a
// little since the last halo was built, migrate() with the halo's neighbour ranks does the same
// with one message to each neighbour instead.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "tricell/box.hpp"
#include "tricell/mpi/decomposition.hpp"
#include "tricell/mpi/export.hpp"
#include "tricell/mpi/traffic.hpp"
#include "tricell/types.hpp"

namespace tricell::mpi {

struct TRICELL_MPI_API LocalAtoms {
    /// Global ids (indices into the caller's global system), one per atom.
    std::vector<std::uint64_t> ids;
    /// Cartesian positions as the caller keeps them, 3 per atom (x0 y0 z0 x1 ...).
    std::vector<double> positions;
    /// payload_width doubles per atom, moved with the atom by migrate().
    std::vector<double> payload;
    std::size_t payload_width = 0;

    std::size_t size() const { return ids.size(); }
    PointsView points() const { return PointsView(positions.data(), ids.size()); }
    /// Throws InvalidArgument when the array sizes disagree or a position is not finite.
    void validate() const;
};

/// Collective: moves every atom to the owner of its wrapped fractional position. Bad input on any
/// rank (sizes, non-finite positions, different payload widths) throws on every rank, with the
/// first failing rank's message, before anything moves.
TRICELL_MPI_API void migrate(const Decomposition& decomposition, const Box& box, LocalAtoms& atoms);

/// Collective: migrate() among neighbour ranks only. `neighbors` (ascending, without this rank)
/// must be a symmetric relation between ranks, as Halo::neighbor_ranks() is. When every atom
/// on every rank goes to its own rank or one of its neighbours (the usual case after one Verlet
/// interval: an atom moves less than the halo reach), one MPI_Allreduce agrees on it and each
/// rank exchanges one message with each neighbour, so nothing grows with the number of ranks;
/// the result (order included) is migrate()'s. Otherwise it is migrate(). Returns true when
/// the neighbours sufficed. With `sent`, adds the messages and bytes this rank sent to its
/// neighbours (one message each, (4 + payload_width) doubles per atom).
TRICELL_MPI_API bool migrate(const Decomposition& decomposition, const Box& box, LocalAtoms& atoms,
                             const std::vector<int>& neighbors, Traffic* sent = nullptr);

/// Collective: true on every rank when every atom on every rank is owned by its rank.
TRICELL_MPI_API bool all_owned(const Decomposition& decomposition, const Box& box,
                               const LocalAtoms& atoms);

} // namespace tricell::mpi
