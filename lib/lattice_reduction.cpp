#include "detail/lattice_reduction.hpp"

#include <cmath>

namespace tricell::detail {

ReducedBasis reduce_basis(const Eigen::Matrix3d& basis, int count) {
    ReducedBasis out;
    out.count = count;
    for (int k = 0; k < count; ++k) {
        out.vectors.col(k) = basis.col(k);
        out.transform(k, k) = 1;
    }
    // Each accepted step shortens a vector by a relative margin, so this terminates; the cap
    // only guards against pathological floating-point input. A step whose integer coefficients
    // would leave a comfortable int range is skipped: the basis is then less reduced, which
    // costs search time in callers but never exactness.
    constexpr int max_sweeps = 200;
    constexpr long long max_coefficient = 1LL << 30;
    for (int sweep = 0; sweep < max_sweeps; ++sweep) {
        bool changed = false;
        for (int i = 0; i < count; ++i) {
            for (int j = 0; j < count; ++j) {
                if (i == j) {
                    continue;
                }
                const double norm_j_sq = out.vectors.col(j).squaredNorm();
                const double q = std::round(out.vectors.col(i).dot(out.vectors.col(j)) / norm_j_sq);
                if (q == 0.0 || !(std::abs(q) <= double(max_coefficient))) {
                    continue;
                }
                const Eigen::Matrix<long long, 3, 1> column =
                    out.transform.col(i).cast<long long>() -
                    static_cast<long long>(q) * out.transform.col(j).cast<long long>();
                if (column.cwiseAbs().maxCoeff() > max_coefficient) {
                    continue;
                }
                const Eigen::Vector3d candidate = out.vectors.col(i) - q * out.vectors.col(j);
                if (candidate.squaredNorm() < out.vectors.col(i).squaredNorm() * (1 - 1e-12)) {
                    out.vectors.col(i) = candidate;
                    out.transform.col(i) = column.cast<int>();
                    changed = true;
                }
            }
        }
        if (!changed) {
            break;
        }
    }
    // Recompute from the integer transform so the vectors are exact lattice vectors.
    for (int k = 0; k < count; ++k) {
        out.vectors.col(k) = basis * out.transform.col(k).cast<double>();
    }
    return out;
}

ReducedCell reduce_cell(const Eigen::Matrix3d& h, const std::array<bool, 3>& periodic) {
    Eigen::Matrix3d periodic_vectors = Eigen::Matrix3d::Zero();
    int axis_of[3] = {0, 0, 0};
    int count = 0;
    for (int axis = 0; axis < 3; ++axis) {
        if (periodic[std::size_t(axis)]) {
            axis_of[count] = axis;
            periodic_vectors.col(count++) = h.col(axis);
        }
    }
    const ReducedBasis reduced = reduce_basis(periodic_vectors, count);
    ReducedCell out;
    out.h = h;
    for (int l = 0; l < count; ++l) {
        out.h.col(axis_of[l]) = reduced.vectors.col(l);
        for (int k = 0; k < count; ++k) {
            out.transform(axis_of[k], axis_of[l]) = reduced.transform(k, l);
        }
    }
    return out;
}

} // namespace tricell::detail
