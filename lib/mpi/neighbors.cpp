#include "tricell/mpi/neighbors.hpp"

#include <algorithm>
#include <limits>

#include "collective.hpp"
#include "pair_map.hpp"
#include "tricell/error.hpp"

namespace tricell::mpi {

void DistributedSearch::build(const Decomposition& decomposition, const Box& box,
                              const LocalAtoms& atoms, const NeighborOptions& options) {
    // Which rule decides, the same on every rank: a species table, per-atom radii (the cutoff
    // left at 0; a rank without atoms then has no radii), or the cutoff.
    const bool by_species = !options.species_cutoffs.empty();
    const bool by_radii = !by_species && options.cutoff == 0;
    detail::agreed(decomposition.comm(), [&] {
        NeighborOptions check = options;
        if (by_radii && atoms.size() == 0) {
            check.radii = {0.0}; // nothing to check but the rule itself
        }
        check.validate();
        if (options.max_neighbors != 0) {
            tricell::detail::fail<InvalidArgument>(
                "the distributed search keeps every pair within the cutoff: max_neighbors is "
                "for NeighborSearch");
        }
        atoms.validate();
    });
    options_ = options;
    // How far the halo must reach: the cutoff, or the largest pair cutoff any rank can have.
    double reach = options.cutoff;
    if (by_radii) {
        const double largest = options.radii.empty()
                                   ? 0.0
                                   : *std::max_element(options.radii.begin(), options.radii.end());
        detail::check_mpi(
            MPI_Allreduce(&largest, &reach, 1, MPI_DOUBLE, MPI_MAX, decomposition.comm()),
            "MPI_Allreduce");
        reach *= 2;
    } else if (by_species) {
        reach = 0;
        for (const SpeciesCutoff& e : options.species_cutoffs) {
            reach = std::max(reach, e.cutoff);
        }
    }
    // No pair can count when every radius is 0; any positive reach is then right.
    reach = std::max(reach, std::numeric_limits<double>::min());
    halo_.build(decomposition, box, atoms.ids, atoms.points(), reach,
                by_radii ? &options.radii : nullptr, by_species ? &options.species : nullptr,
                options.half ? GhostSet::upper : GhostSet::all);
    // The ghosts are the periodic images: the local search runs with every axis open, with the
    // local atoms' radii and species.
    const Box open = Box::from_columns(box.matrix(), Periodicity::none());
    NeighborOptions local = detail::local_options(options_, halo_.owned_count());
    local.radii = halo_.radii();
    local.species = halo_.species();
    if (by_radii && halo_.size() == 0) {
        local.cutoff = reach; // no atoms here: no radii to give, no pair either way
    }
    detail::agreed(decomposition.comm(), [&] { local_.build(open, halo_.points(), local); });
}

void DistributedSearch::compute(DistributedPairs& out) const {
    local_.compute(scratch_);
    detail::map_pairs(scratch_, halo_, options_.half, options_.with_offsets(), options_.quantities,
                      out);
}

DistributedPairs compute_neighbors(const Decomposition& decomposition, const Box& box,
                                   const LocalAtoms& atoms, const NeighborOptions& options) {
    DistributedSearch search;
    search.build(decomposition, box, atoms, options);
    DistributedPairs out;
    search.compute(out);
    return out;
}

} // namespace tricell::mpi
