// The lattice vectors of open axes. Along an open axis positions are never wrapped and no image
// is taken, so its vector only sets the frame (the fractional coordinates the search bins in);
// data sets give none there (ASE's Atoms without a cell, a slab with a zero third vector), and
// any vector that keeps the box invertible gives the same pairs. So the vectors of open axes are
// completed where they cannot serve: a zero one is replaced by a unit vector orthogonal to the
// other vectors (ASE's complete_cell), and when the given open vectors are not independent of
// the others every open vector is replaced so: the frame is then orthonormal to the periodic
// vectors (vesin's rule). The periodic vectors are never changed (the caller's Box checks them
// first).
#pragma once

#include <array>

#include <Eigen/Core>

#include "tricell/types.hpp"

namespace tricell::detail {

/// Below this, |det| of unit vectors (or |u x v| of two) is flat: the vectors are taken as
/// linearly dependent.
constexpr double flatness_tolerance = 1e-10;

/// The flatness of the columns `keep` of h, scaled to unit length: |det| for three, |u x v|
/// for two, 1 for one nonzero column or none (0 for a zero column).
double unit_flatness(const Eigen::Matrix3d& h, const std::array<bool, 3>& keep);

/// h with the columns of open axes completed (see above); h's periodic columns must be nonzero
/// and independent.
Eigen::Matrix3d complete_open_axes(const Eigen::Matrix3d& h, const Periodicity& pbc);

} // namespace tricell::detail
