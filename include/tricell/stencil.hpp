// The stencil: which neighbouring cells, with which image shifts, a cell must be paired with.
//
// An entry is a cell offset delta. From a cell c, the offset reaches cell (c + delta) mod n
// with image shift floor((c + delta) / n) along each periodic axis. That map from delta to
// (neighbour cell, image shift) is one-to-one for a given c, so every periodic image of every
// cell is visited exactly once: with one or two cells along an axis, the offsets -1 and +1
// reach the same cell through different images, and with a cutoff spanning several boxes the
// offsets -m..m visit the images of one cell one by one. Neither double counts nor misses.
//
// Offsets range over -m..m per axis (m = the grid's reach) and are pruned when the closest
// approach of the two cells, measured in the real metric of the triclinic box (a small
// box-constrained quadratic problem, solved exactly), is not below the search radius. The
// pruning is symmetric in delta and -delta, so the half stencil stays exact.
//
// The stencil also owns what backends need to walk it: its rows (for each (da, db), the range of
// dc it keeps: in a layout where c varies fastest the cells of one row are consecutive, so a row
// is scanned as a few contiguous atom ranges instead of one range per offset) and, on request,
// per-axis tables turning a cell coordinate plus an offset into the neighbour cell and its image
// shift.
//
// The full stencil holds every kept offset. The half stencil holds the zero offset (pairs inside
// one cell, each unordered pair once) and the lexicographically positive offsets: for any pair
// of atoms and image shift, exactly one of (i, j, S) and (j, i, -S) is found through it.
#pragma once

#include <array>
#include <cstddef>
#include <vector>

#include "tricell/box.hpp"
#include "tricell/export.hpp"
#include "tricell/grid.hpp"

namespace tricell {

using CellOffset = std::array<int, 3>;

/// A row of the stencil: offsets (da, db, dc) for dc in [dc_lo, dc_hi].
struct StencilRow {
    int da, db, dc_lo, dc_hi;
};

class TRICELL_API Stencil {
  public:
    Stencil() = default;
    /// Every offset whose cells can hold a pair closer than the search radius. With
    /// `exact = false` only the cheap tests run (the gap across one pair of faces, the distance
    /// of the cell centres) and offsets they cannot decide are kept: a superset, for grids so
    /// sparse that solving the closest-approach problem costs more than scanning the cells.
    /// With `tables` the per-axis neighbour tables are built too (O(cells per axis) memory).
    static Stencil full(const CellGrid& grid, const Box& box, double search_radius,
                        bool exact = true, bool tables = false);
    /// The zero offset first, then the lexicographically positive half of full().
    static Stencil half(const CellGrid& grid, const Box& box, double search_radius,
                        bool exact = true, bool tables = false);

    const std::vector<CellOffset>& offsets() const { return offsets_; }
    std::size_t size() const { return offsets_.size(); }
    bool is_half() const { return half_; }
    /// The rows, for each (da, db) the hull of its dc (a superset of the kept offsets is always
    /// correct; in practice the kept dc already form an interval).
    const std::vector<StencilRow>& rows() const { return rows_; }
    /// With tables: the neighbour cell along `axis` of coordinate t = c + delta in
    /// [-reach, n + reach), -1 beyond the end of an open axis, and its image shift.
    int neighbour_cell(int axis, int t) const {
        return neighbour_cell_[axis][std::size_t(t + reach_[std::size_t(axis)])];
    }
    int neighbour_shift(int axis, int t) const {
        return neighbour_shift_[axis][std::size_t(t + reach_[std::size_t(axis)])];
    }

  private:
    static Stencil make(const CellGrid& grid, const Box& box, double search_radius, bool half,
                        bool exact, bool tables);
    std::vector<CellOffset> offsets_;
    std::vector<StencilRow> rows_;
    std::array<int, 3> reach_{};
    std::vector<int> neighbour_cell_[3];
    std::vector<int> neighbour_shift_[3];
    bool half_ = false;
};

/// Squared closest approach |H u|^2 over u in the box lower <= u <= upper (fractional), solved
/// exactly by enumerating the active sets of the box constraints.
TRICELL_API double closest_approach_sq(const Eigen::Matrix3d& h, const Eigen::Vector3d& lower,
                                       const Eigen::Vector3d& upper);
/// The same with the Gram matrix H^T H given, for callers that test many boxes in one metric.
TRICELL_API double closest_approach_sq(const Eigen::Matrix3d& h, const Eigen::Matrix3d& gram,
                                       const Eigen::Vector3d& lower, const Eigen::Vector3d& upper);
/// Whether some u in the box lower <= u <= upper has |H u| < radius. Two bounds around the box's
/// centre c settle most boxes at the cost of one product H c: the centre itself (|H c| < radius:
/// yes) and the triangle inequality |H u| >= |H c| - sum_k |a_k| |u_k - c_k| (no when that exceeds
/// the radius); closest_approach_sq decides the boxes between them. `edges` holds |a_k|.
TRICELL_API bool box_within_radius(const Eigen::Matrix3d& h, const Eigen::Matrix3d& gram,
                                   const Eigen::Vector3d& edges, const Eigen::Vector3d& lower,
                                   const Eigen::Vector3d& upper, double radius);

} // namespace tricell
