// The seam between the shared search (lib/search/) and the structures that find
// candidate pairs. A backend does two things only: it bins the atoms (choosing the order in
// which they are stored, so that its candidates are contiguous ranges) and it enumerates the
// candidate (range, range, image shift) triples of a range of its work units (cells, buckets,
// leaves) into a CandidateScanner. It never sees the caller's frame, the output layout, the
// cutoff rule or threads; the shared part never knows how cells are stored.
//
// Adding a backend: a file here and one line of the table in lib/search/registry.cpp; the
// automatic choice (lib/policy/policy.cpp) picks it only once the cost model knows its cost.
// A backend takes its tuning from the build plan it is given (threads, the cell cap, the
// stencil's pruning), never from a policy of its own.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

#include <Eigen/Core>

#include "policy/policy.hpp"
#include "scan/candidate_scan.hpp"
#include "tricell/box.hpp"
#include "tricell/error.hpp"
#include "tricell/neighbor_list.hpp"

namespace tricell::detail {

/// What every backend is given to bin: the search frame and the wrapped fractional positions.
struct BinningInput {
    const Box& frame;                             ///< the search frame (maybe reduced)
    const PairArray<Eigen::Vector3d>& fractional; ///< in [0, 1) along periodic axes
    Eigen::Vector3d lower, upper;                 ///< extent of the positions, per axis
    double search_radius;                         ///< largest cutoff plus a rounding margin
    const NeighborOptions& options;               ///< tuning knobs (half, leaf_size, ...)
    const BuildPlan& plan;                        ///< threads, the cell cap, the pruning
};

class Backend {
  public:
    virtual ~Backend() = default;
    /// Bins the atoms. order[k] is the caller's index of the k-th atom in the backend's order
    /// (the order of the AtomTable that visit() will index).
    virtual void bin(const BinningInput& input, std::vector<std::uint32_t>& order) = 0;
    /// Work units that threads split (visited in this order; concatenating the pairs of
    /// consecutive unit ranges gives the pairs of the whole range).
    virtual std::size_t unit_count() const = 0;
    /// Atoms and fractional volume of each unit.
    virtual void occupancy(UnitOccupancy& out) const = 0;
    /// How many units a unit is paired with on average (its stencil): for the work estimate of a
    /// threaded split only, so a backend may compute it here, on demand.
    virtual double neighbours() const = 0;
    /// Names the candidates of units [begin, end) to the scanner.
    virtual void visit(std::size_t begin, std::size_t end, CandidateScanner& scan) const = 0;
    /// Fills the backend-specific fields of info (backend, cells, stored_cells).
    virtual void describe(SearchInfo& info) const = 0;
};

/// The periodic images a backend enumerates along `axis` (perpendicular width `width`) for
/// `search_radius`, `images` (from its own bound), as an int. Refused past a million, as the
/// grid refuses a million cells: before the cast, which a radius of ~1e286 (a Verlet list's
/// rounding margin for coordinates of 1e300) overflowed.
inline int checked_image_reach(double images, double search_radius, double width, int axis) {
    if (!(images < 1e6)) {
        fail<InvalidArgument>("search radius ", search_radius,
                              " spans more than a million images along axis ", axis,
                              " (perpendicular width ", width, ")");
    }
    return int(images);
}

} // namespace tricell::detail
