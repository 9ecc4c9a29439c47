// What a built search holds (NeighborSearch's state), and the one way to make a scanner of it.
#pragma once

#include <cstddef>

#include "backends/backend.hpp"
#include "frame/search_frame.hpp"
#include "scan/atom_table.hpp"
#include "scan/candidate_scan.hpp"
#include "scan/cutoff_rule.hpp"
#include "search/registry.hpp"
#include "tricell/neighbor_list.hpp"

namespace tricell::detail {

struct SearchState {
    NeighborOptions options;
    SearchFrame frame;
    double search_radius = 0;
    double estimated_pairs = 0;
    double most_pairs = 0; ///< BuildPlan::most_pairs
    std::size_t atom_count = 0;
    std::size_t query_atoms = 0; ///< a subset search's query atoms (0: the ordinary search)
    CutoffRule rule;
    AtomTable atoms; ///< in the backend's order
    // The backend of the last build, null when no pair can count (all radii zero, ...).
    Backend* backend = nullptr;
    BackendPool pool;

    /// A scanner of this search's atoms that hands its pairs to `sink`.
    CandidateScanner scanner(PairSink& sink) const {
        return CandidateScanner(atoms, frame, rule, options.half, sink);
    }
};

} // namespace tricell::detail
