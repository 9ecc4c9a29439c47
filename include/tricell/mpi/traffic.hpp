// What a rank sends: messages and bytes of its point-to-point communication, by kind, counted by
// the library where it sends them, and the model of tricell/mpi.hpp they are compared with.
//
// The model, for a grid of d_k equal domains along each periodic axis k of a box with
// perpendicular widths w_k, n atoms per rank at uniform density and a halo reach r: the halo of
// a domain is its fractional box widened by r / w_k on each side, so it holds
//     ghosts per owned atom     g = prod_k (1 + 2 r d_k / w_k) - 1,
// of which the images of the rank's own atoms (along the axes with one domain, d_k = 1) are
//     g_self = prod_{k: d_k = 1} (1 + 2 r / w_k) - 1
// and are copied, not sent; a rank sends as many ghosts as it receives on average,
// n (g - g_self). Its neighbour ranks are M = prod_k min(d_k, 2 ceil(r d_k / w_k) + 1) - 1 (26
// in a large grid with r below a domain's width), one message each way per exchange. Bytes per
// sent ghost: Halo::build_record_bytes at a build, Halo::update_record_bytes per update, 8 w for
// w doubles per atom in forward() and reverse_sum(). An upper halo (GhostSet::upper, the half
// lists of Newton's third law) holds half of g, and sends half of g - g_self: along each axis the
// overlap of a domain's halo with a translate of another domain has the length of the overlap of
// that domain's halo with the opposite translate of the first, so the two orientations of an
// owned-ghost relation are equally likely, and the upper halo keeps one of each; the neighbour
// ranks and messages are the same. Ghosts are expected values (exact up to the fluctuation of
// the atoms in the halo); messages are exact.
#pragma once

#include <cstdint>

#include "tricell/box.hpp"
#include "tricell/mpi/decomposition.hpp"
#include "tricell/mpi/export.hpp"
#include "tricell/mpi/halo.hpp"

namespace tricell::mpi {

/// Messages and bytes one rank sent, summed over `exchanges` calls.
struct Traffic {
    std::uint64_t exchanges = 0;
    std::uint64_t messages = 0;
    std::uint64_t bytes = 0;

    /// Adds one exchange that sent `messages` messages of `bytes` bytes in all.
    void add(std::uint64_t message_count, std::uint64_t byte_count) {
        ++exchanges;
        messages += message_count;
        bytes += byte_count;
    }
};

/// What one rank of a DistributedVerletList sent, by kind, since its construction (or its
/// reset_traffic()). Every exchange sends one message to each neighbour rank, empty or not;
/// images of a rank's own atoms are copied, not sent, and not counted; collectives (the
/// MPI_Allreduce votes, migrate()'s MPI_Alltoall fallback) are not counted.
struct ListTraffic {
    Traffic migration;   ///< atoms to their new owners at rebuilds, among the halo's neighbours
    Traffic halo_build;  ///< ghost records at rebuilds (Halo::build)
    Traffic halo_update; ///< ghost positions between rebuilds (Halo::update)
    Traffic reverse_sum; ///< reverse_sum() of per-ghost values
    Traffic forward;     ///< forward_values() of per-atom values
};

/// The model above for one rank (periodic boxes; equal domains).
struct HaloModel {
    double ghosts_per_atom = 0;      ///< g
    double sent_ghosts_per_atom = 0; ///< g - g_self: ghosts sent (and received) per owned atom
    int messages = 0;                ///< M, per exchange
};

/// Collective-free. The model for `decomposition`'s grid (its boundaries are not read: equal
/// domains assumed) in `box` (every axis periodic, else InvalidArgument) at halo reach `reach`,
/// for a halo of all ghosts or of the upper ones.
TRICELL_MPI_API HaloModel halo_model(const Decomposition& decomposition, const Box& box,
                                     double reach, GhostSet ghosts = GhostSet::all);

} // namespace tricell::mpi
