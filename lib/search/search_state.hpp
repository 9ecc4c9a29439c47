// What a built search holds (NeighborSearch's state), and the one way to make a scanner of it.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "backends/backend.hpp"
#include "scan/candidate_scan.hpp"
#include "search/registry.hpp"
#include "tricell/neighbor_list.hpp"

namespace tricell::detail {

struct SearchState {
    NeighborOptions options;
    Eigen::Matrix3d h = Eigen::Matrix3d::Identity(); // of the search frame
    // Shifts in the search frame map to the caller's as S = to_caller * S' (identity unless
    // the cell was reduced).
    Eigen::Matrix3i to_caller = Eigen::Matrix3i::Identity();
    bool reduced_frame = false;
    double search_radius = 0;
    double cutoff_sq = 0; // the scan's threshold (of the largest cutoff)
    std::size_t atom_count = 0;
    double estimated_pairs = 0;
    CutoffRule rule;
    AtomTable atoms;
    // A subset search (NeighborOptions::query): 1 per query atom, in the backend's order (the
    // AtomTable's); empty for the ordinary search.
    std::vector<std::uint8_t> query;
    // The backend of the last build, null when no pair can count (all radii zero, ...).
    Backend* backend = nullptr;
    BackendPool pool;

    /// A scanner of this search's atoms that hands its pairs to `sink`.
    CandidateScanner scanner(PairSink& sink) const {
        const bool subset = !query.empty();
        return CandidateScanner(atoms, h, cutoff_sq, rule, options.half, to_caller, reduced_frame,
                                sink, subset ? query.data() : nullptr, subset && options.half);
    }
};

} // namespace tricell::detail
