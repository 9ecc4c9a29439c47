// Lattice basis reduction for up to three vectors.
//
// A greedy pairwise (Lagrange-Gauss style) reduction: repeatedly subtract the nearest integer
// multiple of one vector from another while that shortens it. The result spans the same lattice
// (the transform is unimodular) and is close to orthogonal, which keeps the minimum-image search
// and the neighbour-search stencils small for strongly skewed cells. Exactness never depends on
// how well this reduces: callers bound their searches from the reduced basis itself.
#pragma once

#include <array>

#include <Eigen/Core>

namespace tricell::detail {

struct ReducedBasis {
    /// Columns 0..count-1: the reduced vectors.
    Eigen::Matrix3d vectors = Eigen::Matrix3d::Zero();
    /// Columns 0..count-1: integer coefficients of each reduced vector in the input basis,
    /// vectors.col(k) = input * transform.col(k).
    Eigen::Matrix3i transform = Eigen::Matrix3i::Zero();
    int count = 0;
};

/// Reduces the first `count` columns of `basis` (count in 0..3).
ReducedBasis reduce_basis(const Eigen::Matrix3d& basis, int count);

/// A box matrix with its periodic columns reduced: h = original * transform, where transform
/// is unimodular, mixes periodic columns only and leaves open columns as they are.
struct ReducedCell {
    Eigen::Matrix3d h;
    Eigen::Matrix3i transform = Eigen::Matrix3i::Identity();
};

ReducedCell reduce_cell(const Eigen::Matrix3d& h, const std::array<bool, 3>& periodic);

} // namespace tricell::detail
