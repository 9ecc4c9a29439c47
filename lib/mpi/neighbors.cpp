#include "tricell/mpi/neighbors.hpp"

#include "collective.hpp"
#include "pair_map.hpp"
#include "tricell/error.hpp"

namespace tricell::mpi {

void DistributedSearch::build(const Decomposition& decomposition, const Box& box,
                              const LocalAtoms& atoms, const NeighborOptions& options) {
    detail::agreed(decomposition.comm(), [&] {
        options.validate();
        atoms.validate();
    });
    options_ = options;
    halo_.build(decomposition, box, atoms.ids, atoms.points(), options.cutoff);
    // The ghosts are the periodic images: the local search runs with every axis open.
    const Box open = Box::from_columns(box.matrix(), Periodicity::none());
    detail::agreed(decomposition.comm(),
                   [&] { local_.build(open, halo_.points(), detail::local_options(options_)); });
}

void DistributedSearch::compute(DistributedPairs& out) const {
    local_.compute(scratch_);
    detail::map_pairs(scratch_, halo_, options_.half, options_.sorted, options_.quantities, out);
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
