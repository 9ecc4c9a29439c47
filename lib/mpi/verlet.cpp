#include "tricell/mpi/verlet.hpp"

#include <exception>
#include <numeric>
#include <string>

#include "collective.hpp"
#include "pair_map.hpp"
#include "tricell/error.hpp"

namespace tricell::mpi {

DistributedVerletList::DistributedVerletList(const VerletOptions& options) : options_(options) {
    options_.validate();
    VerletOptions local = options_;
    local.neighbors.half = true;
    local.neighbors.quantities = Quantities{false, true, true};
    local_ = VerletList(local);
}

void DistributedVerletList::reset() {
    built_ = false;
    local_.reset();
    pairs_.clear();
}

bool DistributedVerletList::update(const Decomposition& decomposition, const Box& box,
                                   LocalAtoms& atoms) {
    const MPI_Comm comm = decomposition.comm();
    const Box open = Box::from_columns(box.matrix(), Periodicity::none());
    detail::agreed(comm, [&] { atoms.validate(); });

    // Can the build still serve? Every rank must say yes.
    int keep =
        built_ && atoms.size() == halo_.owned_count() && box.periodicity() == built_periodicity_;
    detail::check_mpi(MPI_Allreduce(MPI_IN_PLACE, &keep, 1, MPI_INT, MPI_MIN, comm),
                      "MPI_Allreduce");
    if (keep) {
        halo_.update(decomposition, box, atoms.points());
        double excess = 0;
        detail::agreed(comm, [&] {
            excess =
                local_.max_displacement(open, halo_.points()) - local_.displacement_budget(open);
        });
        detail::check_mpi(MPI_Allreduce(MPI_IN_PLACE, &excess, 1, MPI_DOUBLE, MPI_MAX, comm),
                          "MPI_Allreduce");
        keep = excess <= 0;
    }
    if (keep) {
        detail::agreed(comm, [&] { local_.update(open, halo_.points()); });
    } else {
        built_ = false;
        // Among the last halo's neighbour ranks when every atom's owner is one of them (an atom
        // moves less than the halo reach in a Verlet interval), else MPI_Alltoall.
        if (!halo_built_ || !migrate(decomposition, box, atoms, halo_.neighbor_ranks())) {
            if (!halo_built_) {
                migrate(decomposition, box, atoms);
            }
            ++alltoall_migrations_;
        }
        halo_.build(decomposition, box, atoms.ids, atoms.points(), local_.list_radius());
        // Pairs of the owned atoms only (the first of the local atoms): no ghost-ghost pair.
        std::vector<std::uint32_t> owned(halo_.owned_count());
        std::iota(owned.begin(), owned.end(), 0u);
        local_.set_query(std::move(owned));
        detail::agreed(comm, [&] { local_.rebuild(open, halo_.points()); });
        built_ = true;
        halo_built_ = true;
        built_periodicity_ = box.periodicity();
        ++rebuild_count_;
    }
    detail::map_pairs(local_.pairs(), halo_, options_.neighbors.half, false,
                      options_.neighbors.quantities, pairs_);
    return !keep;
}

void DistributedVerletList::forward(const Decomposition& decomposition, const Box& box,
                                    const LocalAtoms& atoms) {
    halo_.update(decomposition, box, atoms.points());
}

void DistributedVerletList::reverse_sum(const Decomposition& decomposition,
                                        std::vector<double>& values, std::size_t width) const {
    halo_.reverse_sum(decomposition, values, width);
}

} // namespace tricell::mpi
