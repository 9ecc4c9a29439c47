// The cell grid: the box cut into n_a x n_b x n_c cells in fractional space.
//
// Along a periodic axis the grid covers [0, 1) in fractional units with n = floor(w / h) cells
// (w the perpendicular width, h the target cell size = search radius / cells per cutoff), so
// each cell is at least h thick in the real metric. Along an open axis it covers the extent of
// the positions instead. The search reach per axis, m = ceil(r n / w), is the number of cell
// layers a pair within the search radius r can be apart; with images it may exceed n (cutoff
// larger than the box) and the stencil then visits several images of the same cell.
//
// At most 2^20 cells along an axis whatever the cap. The total number of cells is capped (by
// default to a few per atom), so memory follows the atoms, never the volume: when the cap bites,
// cells grow beyond h, the stencil reach shrinks accordingly and more candidate pairs are tested.
// Results never change, only the speed.
//
// Integer helpers use floor division; `%` on negative numbers is never used.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>

#include <Eigen/Core>

#include "tricell/box.hpp"
#include "tricell/export.hpp"

namespace tricell {

/// Floor division for a possibly negative numerator and a positive denominator.
inline int floor_div(int a, int n) {
    return a >= 0 ? a / n : -((-a + n - 1) / n);
}
/// Remainder in [0, n) for a possibly negative numerator and a positive denominator.
inline int floor_mod(int a, int n) {
    return a - floor_div(a, n) * n;
}

struct TRICELL_API GridOptions {
    /// Search radius r (the cutoff, or cutoff + skin); must be > 0.
    double search_radius = 0;
    /// Target cells per search radius along each axis (h = r / k); must be >= 1.
    double cells_per_cutoff = 2;
    /// Upper bound on the total number of cells; must be >= 1.
    std::size_t max_cells = 1;
    void validate() const;
};

class TRICELL_API CellGrid {
  public:
    CellGrid() = default;
    /// A grid over the box. `lower` and `upper` give the fractional extent of the positions along
    /// open axes (ignored along periodic ones, which always span [0, 1)).
    CellGrid(const Box& box, const GridOptions& options, const Eigen::Vector3d& lower,
             const Eigen::Vector3d& upper);

    /// Cells along each axis (>= 1).
    const std::array<int, 3>& dims() const { return dims_; }
    /// Reach per axis: cell layers to search on each side.
    const std::array<int, 3>& reach() const { return reach_; }
    std::size_t cell_count() const {
        return std::size_t(dims_[0]) * std::size_t(dims_[1]) * std::size_t(dims_[2]);
    }
    /// Fractional coordinate where cell 0 starts along each axis (0 on periodic axes).
    const Eigen::Vector3d& origin() const { return origin_; }
    /// Fractional size of one cell along each axis.
    const Eigen::Vector3d& cell_size() const { return cell_size_; }
    const Periodicity& periodicity() const { return pbc_; }
    /// True when max_cells forced cells larger than the target size.
    bool capped() const { return capped_; }

    /// Cell coordinate along an axis of a fractional coordinate (wrapped into [0, 1) on a
    /// periodic axis); clamped into [0, n - 1] against rounding at the upper edge. Clamped
    /// before the cast: on an open axis whose span overflowed (coordinates near +-1e308 apart)
    /// the cell size is infinite and an atom at an infinite distance from the origin is at
    /// inf * 0 = NaN cells, which goes to cell 0 with every other atom there (search fuzzer).
    int coordinate(int axis, double s) const {
        const double c = (s - origin_[axis]) * inverse_size_[axis];
        return c >= 1 ? (c < dims_[axis] ? static_cast<int>(c) : dims_[axis] - 1) : 0;
    }
    /// Flat index of a cell; the c coordinate varies fastest.
    std::size_t flat(int ca, int cb, int cc) const {
        return (std::size_t(ca) * std::size_t(dims_[1]) + std::size_t(cb)) * std::size_t(dims_[2]) +
               std::size_t(cc);
    }
    std::size_t cell_of(const Eigen::Vector3d& s) const {
        return flat(coordinate(0, s[0]), coordinate(1, s[1]), coordinate(2, s[2]));
    }

  private:
    std::array<int, 3> dims_{{1, 1, 1}};
    std::array<int, 3> reach_{{0, 0, 0}};
    Eigen::Vector3d origin_ = Eigen::Vector3d::Zero();
    Eigen::Vector3d cell_size_ = Eigen::Vector3d::Ones();
    Eigen::Vector3d inverse_size_ = Eigen::Vector3d::Ones();
    Periodicity pbc_;
    bool capped_ = false;
};

} // namespace tricell
