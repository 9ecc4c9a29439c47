// The search policy: every choice of how a search runs, and nothing about what it finds. Each
// choice calls the cost model's formulas (cost_model.hpp) with its inputs; no other file of the
// search decides any of these. None of them changes a result: the same input gives the same
// pairs in the same order whatever is chosen here.
//
// - Backend: `automatic` becomes direct enumeration for a few atoms in a cell narrower than the
//   cutoff, else the grid the cell count allows (dense under the cell cap, the compact hash
//   above it), unless the two-density model prices the octree clearly cheaper from the local
//   densities of a sample of atoms.
// - Threads: asked for explicitly they are always used (from 16 atoms per thread in a build's
//   per-atom phases); automatic ones only where a phase outweighs waking a thread.
// - Batches: a threaded compute() cuts the work units into batches of about equal occupancy
//   work and a few thousand pairs each, so a batch's columns stay in the core's cache until they
//   are copied out.
// - Memory: pair columns are reserved from the density estimate; grids are capped at 4 N + 64
//   cells so that their memory follows the atoms, not the volume.
#pragma once

#include <cstddef>
#include <vector>

#include <Eigen/Core>

#include "backends/backend.hpp"
#include "tricell/box.hpp"
#include "tricell/neighbor_list.hpp"

namespace tricell::detail {

/// Threads of a build's per-atom phases (checks, wrap, binning, the atom table) for n atoms.
std::size_t build_threads(const NeighborOptions& options, std::size_t atoms);

/// Threads of compute() for a search of `units` work units and `estimated_pairs` pairs.
std::size_t compute_threads(const NeighborOptions& options, double estimated_pairs,
                            std::size_t units);

/// The most threads any phase of a call may use (the size of the call's thread team).
std::size_t call_threads(const NeighborOptions& options);

/// compute_neighbors() reuses one search object per thread below this many atoms: small
/// systems are called millions of times (one cell per step of a potential), and their buffers
/// then stop being allocated once grown; larger ones use a fresh object, so that no large buffer
/// outlives its call.
constexpr std::size_t reuse_search_below = 1024;

/// The cap on the cells of the dense and linked grids: NeighborOptions::max_cells, or 4 N + 64.
std::size_t cell_cap(const NeighborOptions& options, std::size_t atoms);

/// Whether the stencil prunes offsets by the exact closest approach of their cells (a small
/// quadratic problem per boundary offset), for `atoms` atoms in `cells` cells: worth it only
/// when an offset leads to more distance tests than solving it costs.
bool exact_stencil_pruning(double atoms, double cells);

/// The concrete backend for `automatic` (see above). `fractional`, `lower` and `upper` are the
/// wrapped positions and their extent in `frame`.
SearchBackend automatic_backend(const Box& frame, const std::vector<Eigen::Vector3d>& fractional,
                                const Eigen::Vector3d& lower, const Eigen::Vector3d& upper,
                                double search_radius, const NeighborOptions& options);

/// Expected stored pairs of a whole system: the density over the region the atoms occupy (an
/// open axis counts as at least one cutoff thick); what max_pairs is checked against.
double estimated_system_pairs(const Box& frame, std::size_t atoms, const Eigen::Vector3d& lower,
                              const Eigen::Vector3d& upper, double cutoff, bool half);

/// Pairs to reserve room for when `expected` are expected: a tenth more, at most `limit` (the
/// pair limit), or 2^24 pairs when there is no limit (0). Untouched reserved memory is never
/// resident, so a list within the estimate never grows, and so never holds an old and a new copy
/// of its columns at once (docs/memory.md).
std::size_t pair_room(double expected, std::size_t limit = 0);

/// How a threaded compute() splits units: batch b is units [bounds[b], bounds[b + 1]) with room
/// for reserve[b] pairs.
struct BatchPlan {
    std::vector<std::size_t> bounds;
    std::vector<std::size_t> reserve;
    std::size_t size() const { return reserve.size(); }
};

/// The batches of `units` units with `expected[u]` expected pairs and `work[u]` occupancy work
/// each, for `threads` threads (at least four batches per thread).
BatchPlan plan_batches(const std::vector<double>& work, const std::vector<double>& expected,
                       std::size_t threads);

/// Scanned batches a thread may hold before it waits for a stalled neighbour, so that its batch
/// columns stay a few MB instead of growing towards the list.
constexpr std::size_t max_pending_batches = 16;

/// Estimated cost of one structure of a batch of structures (compute_neighbors_batch), in units
/// of one stored pair: a fixed cost per call and per atom, plus the pairs expected from the
/// density. Threads take contiguous runs of about equal total cost.
double structure_cost(const Box& box, std::size_t atoms, const NeighborOptions& options);

} // namespace tricell::detail
