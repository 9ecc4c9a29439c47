// What a built search holds (NeighborSearch's state), the one way to make a scanner of it, and
// the steps of a search over a state, which NeighborSearch and the batch call share.
#pragma once

#include <cstddef>

#include "backends/backend.hpp"
#include "frame/search_frame.hpp"
#include "frame/wrap.hpp"
#include "policy/list_limits.hpp"
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
    bool mirrored = false;       ///< BuildPlan::mirrored
    CutoffRule rule;
    AtomTable atoms; ///< in the backend's order
    // The backend of the last build, null when no pair can count (all radii zero, ...).
    Backend* backend = nullptr;
    BackendPool pool;
    // Kept between builds so that their buffers are reused: the wrapped positions and the
    // backend's order of the atoms (the atom table's last index).
    WrappedPositions wrapped;
    std::vector<std::uint32_t> order;

    /// A scanner of this search's atoms that hands its pairs to `sink`.
    CandidateScanner scanner(PairSink& sink) const {
        return CandidateScanner(atoms, frame, rule, options.half, mirrored, sink);
    }
};

/// Builds the search of `positions` in `box` into `s`, whose options are set and validated
/// (NeighborSearch::build() is this plus the validation), on `threads` threads of the per-atom
/// phases. Sets the cutoff rule from the options unless `rule_set` (the caller set it for this
/// atom count). On error `s` holds no usable search.
void build_search(SearchState& s, const Box& box, PointsView positions, std::size_t threads,
                  bool rule_set = false);

/// Stores the pairs of a built search into `out` (NeighborSearch::compute()).
void compute_list(const SearchState& s, NeighborList& out);

/// Appends the pairs of a built search to `columns`, which hold only the columns
/// s.options.quantities asks for, on the calling thread, unordered (the list compute_list()
/// gives when s.options asks for no order), within `limits` (which count the pairs already in
/// `columns`). On error `columns` may hold some of the new pairs: the caller drops them.
void append_pairs(const SearchState& s, PairColumns& columns, const ListLimits& limits);

} // namespace tricell::detail
