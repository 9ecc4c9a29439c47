// What a rank sends: messages and bytes of its point-to-point communication, by kind, counted by
// the library where it sends them (the counted side of the model in tricell/mpi.hpp).
#pragma once

#include <cstdint>

namespace tricell::mpi {

/// Messages and bytes one rank sent, summed over calls.
struct Traffic {
    std::uint64_t messages = 0;
    std::uint64_t bytes = 0;

    Traffic& operator+=(const Traffic& other) {
        messages += other.messages;
        bytes += other.bytes;
        return *this;
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

} // namespace tricell::mpi
