// The search policy: every choice of how a search runs, and nothing about what it finds. It
// answers once per phase with a plan, each choice from the cost model's formulas
// (cost_model.hpp); no other file of the search decides any of these. None of them changes a
// result: the same input gives the same pairs in the same order whatever is chosen here.
//
// - Build plan: the threads of the per-atom phases (asked for explicitly they are always used,
//   from 16 atoms per thread; automatic ones only where a phase outweighs waking a thread), the
//   pairs expected from the density, the backend (`automatic` becomes direct enumeration for a
//   few atoms in a cell narrower than the cutoff, else the grid the cell count allows: dense
//   under the cell cap, the compact hash above it, unless the two-density model prices the
//   octree clearly cheaper from the local densities of a sample of atoms), the cell cap
//   (4 N + 64 cells, so that a grid's memory follows the atoms, not the volume), the grid's
//   cells per cutoff (cost_model.hpp) and the stencil's pruning.
// - Compute plan: the threads of the scan, the pairs expected of each work unit from its
//   occupancy, the room reserved for the list, and for several threads the batches: units cut
//   into batches of about equal occupancy work and a few thousand pairs each, so that a batch's
//   columns stay in the core's cache until they are copied out.
// - Batch plan: the runs of structures of a batch call, one per thread, of about equal cost.
#pragma once

#include <cstddef>
#include <functional>
#include <vector>

#include "frame/wrap.hpp"
#include "policy/list_limits.hpp"
#include "tricell/box.hpp"
#include "tricell/neighbor_list.hpp"

namespace tricell::detail {

/// Occupancy of every work unit of a backend: its atoms and its fractional volume (for the work
/// and pair-count estimates from the occupancy moments, cost_model.hpp).
struct UnitOccupancy {
    PairArray<double> atoms;
    PairArray<double> volume;
};

/// The most threads any phase of a call may use (the size of the call's thread team).
std::size_t call_threads(const NeighborOptions& options);

/// compute_neighbors() reuses one search object per thread below this many atoms: small
/// systems are called millions of times (one cell per step of a potential), and their buffers
/// then stop being allocated once grown; larger ones use a fresh object, so that no large buffer
/// outlives its call.
constexpr std::size_t reuse_search_below = 1024;

/// Threads of a build's per-atom phases (checks, wrap, binning, the atom table) for n atoms:
/// the first phases run before the rest of the build plan can be made.
std::size_t build_threads(const NeighborOptions& options, std::size_t atoms);

/// How build() runs.
struct BuildPlan {
    std::size_t threads = 1;    ///< of the per-atom phases (build_threads())
    double estimated_pairs = 0; ///< of the list, from the density
    double most_pairs = 0; ///< the list can hold at most (possible_pairs()); caps every reserve
    SearchBackend backend = SearchBackend::dense; ///< never `automatic`
    std::size_t cell_cap = 0;                     ///< most cells of the dense and linked grids
    double cells_per_cutoff = 1;                  ///< of the grids (the option, or chosen)
    std::size_t atoms = 0;
    /// A full list found through the half stencil: each pair the search finds is stored as
    /// found and turned around (the scanner's mirrored mode), so a full list costs a half
    /// search plus its stores.
    bool mirrored = false;

    /// Whether the backends name each unordered pair once: a half list, or a mirrored full one.
    bool half_stencil(const NeighborOptions& options) const { return options.half || mirrored; }

    /// Whether the stencil prunes offsets by the exact closest approach of their cells (a small
    /// quadratic problem per boundary offset) in a grid of `cells` cells: worth it only when an
    /// offset leads to more distance tests than solving it costs.
    bool exact_pruning(double cells) const;
};

/// The plan of a build of `wrapped.fractional.size()` atoms wrapped into `frame`, at
/// `search_radius` (the largest cutoff `cutoff` plus a rounding margin), of which
/// `query_atoms` are query atoms (all of them for the ordinary search).
BuildPlan plan_build(const NeighborOptions& options, const Box& frame,
                     const WrappedPositions& wrapped, double cutoff, double search_radius,
                     std::size_t query_atoms);

/// How a threaded compute() splits units: batch b is units [bounds[b], bounds[b + 1]) with room
/// for reserve[b] pairs.
struct BatchPlan {
    std::vector<std::size_t> bounds;
    std::vector<std::size_t> reserve;
    std::size_t size() const { return reserve.size(); }
};

/// Scanned batches a thread may hold before it waits for a stalled neighbour, so that its batch
/// columns stay a few MB instead of growing towards the list.
constexpr std::size_t max_pending_batches = 16;

/// What a compute plan is made from: the built search and its backend's units.
struct ComputeInput {
    double estimated_pairs = 0; ///< of the list (BuildPlan::estimated_pairs)
    double most_pairs = 0;      ///< BuildPlan::most_pairs
    double box_volume = 0;      ///< of the search frame
    double max_cutoff = 0;      ///< the largest cutoff
    std::size_t atoms = 0;
    std::size_t query_atoms = 0;        ///< a subset search's query atoms (0: not a subset search)
    UnitOccupancy occupancy;            ///< of each unit, in visiting order
    std::function<double()> neighbours; ///< units a unit is paired with (asked only for threads)
    std::size_t claim = 0;              ///< the most pairs the scan claims at once
};

/// How compute() runs.
struct ComputePlan {
    std::size_t threads = 1;
    /// Pairs to reserve the list's columns for: the expected pairs and a tenth more, at most one
    /// claim past the pair limit, so that a list reaching the limit is refused there, not by a
    /// growth it would not need. Untouched reserved memory is never resident, so a list within
    /// the estimate never grows, and so never holds an old and a new copy of its columns at once
    /// (docs/memory.md).
    std::size_t room = 0;
    BatchPlan batches; ///< for more than one thread
};

/// Pairs to reserve room for when `expected` are expected: a tenth more, at most `limit` (the
/// pair limit), or 2^24 pairs when there is no limit (0).
std::size_t pair_room(double expected, std::size_t limit = 0);

ComputePlan plan_compute(const NeighborOptions& options, const ComputeInput& input,
                         const ListLimits& limits);

/// The estimated cost of one structure of a batch call (compute_neighbors_batch), in stored
/// pairs: a fixed cost per call and per atom, plus the pairs expected from the density.
double structure_cost(const Box& box, std::size_t atoms, const NeighborOptions& options);

/// The runs of structures of a batch call, one per thread, of about equal total `cost` (one
/// entry per structure): bounds[0] = 0 <= ... <= bounds.back() = cost.size().
std::vector<std::size_t> plan_structure_runs(const std::vector<double>& cost,
                                             const NeighborOptions& options);

} // namespace tricell::detail
