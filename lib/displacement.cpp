#include "tricell/displacement.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include <Eigen/SVD>

#include "tricell/error.hpp"

namespace tricell {

namespace {

// Fractional displacements beyond this are not tracked (their jump would not fit an int); such
// an atom counts as moved without bound.
constexpr double max_tracked = 1e9;

// eps = max(0, ||H0 H^-1|| - 1): how much a pair vector in the current box can grow when mapped
// back to the build box. Exactly 0 for an unchanged box.
double box_growth(const Box& built, const Box& box) {
    if (built.matrix() == box.matrix()) {
        return 0;
    }
    const Eigen::Matrix3d m = built.matrix() * box.inverse();
    const double norm = Eigen::JacobiSVD<Eigen::Matrix3d>(m).singularValues()[0];
    return std::max(0.0, norm - 1);
}

void check_finite(PointsView positions, std::size_t i) {
    const Eigen::Vector3d r = positions[i];
    if (!r.allFinite()) {
        detail::fail<InvalidArgument>("position ", i, " is not finite (got ", r.x(), ", ", r.y(),
                                      ", ", r.z(), ")");
    }
}

void check_view(PointsView positions) {
    if (positions.size() > 0 && positions.data == nullptr) {
        detail::fail<InvalidArgument>("positions: null data for ", positions.size(), " points");
    }
}

void check_all_finite(PointsView positions) {
    for (std::size_t i = 0; i < positions.size(); ++i) {
        check_finite(positions, i);
    }
}

} // namespace

void DisplacementTracker::reset() {
    build_box_.reset();
    atom_count_ = 0;
}

void DisplacementTracker::record(const Box& box, PointsView positions, std::int32_t* jumps,
                                 double* unwrapped) {
    reset();
    check_view(positions);
    check_all_finite(positions);
    const std::size_t n = positions.size();
    reference_.resize(3 * n);
    build_jumps_.resize(3 * n);
    const Eigen::Matrix3d& h = box.matrix();
    for (std::size_t i = 0; i < n; ++i) {
        const WrappedFractional w = box.wrap(box.to_fractional(Cartesian(positions[i])));
        const Eigen::Vector3d r = Eigen::Vector3d(positions[i]) - h * w.image.cast<double>();
        for (std::size_t k = 0; k < 3; ++k) {
            reference_[3 * i + k] = w.wrapped[int(k)];
            build_jumps_[3 * i + k] = -w.image[int(k)];
            if (jumps != nullptr) {
                jumps[3 * i + k] = -w.image[int(k)];
                unwrapped[3 * i + k] = r[int(k)];
            }
        }
    }
    atom_count_ = n;
    build_box_ = box;
}

bool DisplacementTracker::compatible(const Box& box, PointsView positions) const {
    return build_box_.has_value() && positions.size() == atom_count_ &&
           box.periodicity() == build_box_->periodicity();
}

double DisplacementTracker::budget(const Box& box, double skin, double cutoff) const {
    if (!build_box_ || box.periodicity() != build_box_->periodicity()) {
        return -std::numeric_limits<double>::infinity();
    }
    return 0.5 * (skin - box_growth(*build_box_, box) * cutoff);
}

double DisplacementTracker::track(const Box& box, PointsView positions, double stop_above,
                                  bool exact, std::int32_t* jumps, double* unwrapped) const {
    check_view(positions);
    const Box& built = *build_box_;
    const Eigen::Matrix3d& h0 = built.matrix();
    const Eigen::Matrix3d& h = box.matrix();
    const Eigen::Matrix3d& h_inv = box.inverse();
    const Periodicity& pbc = built.periodicity();
    const double stop_above_sq = stop_above * stop_above;
    double max_sq = 0;
    for (std::size_t i = 0; i < atom_count_; ++i) {
        check_finite(positions, i);
        const Eigen::Vector3d x = positions[i];
        // u = s - s0; the jump m cancels its integer part along periodic axes.
        const Eigen::Vector3d u = h_inv * x - Eigen::Map<const Eigen::Vector3d>(&reference_[3 * i]);
        if (!(u.cwiseAbs().maxCoeff() < max_tracked)) {
            return std::numeric_limits<double>::infinity();
        }
        Eigen::Vector3d m = Eigen::Vector3d::Zero();
        for (int k = 0; k < 3; ++k) {
            if (pbc[k]) {
                m[k] = -std::nearbyint(u[k]);
            }
        }
        Eigen::Vector3d delta = h0 * (u + m);
        double delta_sq = delta.squaredNorm();
        if ((exact || delta_sq > stop_above_sq) && pbc.any()) {
            // Rounding the fractional components is not always the shortest translate in a
            // skewed box; the exact minimum image decides before the atom counts as moved.
            // (Below the budget the rounded translate is good enough: the bound holds for any
            // jump, and the shortest one is shorter still.)
            const MinimumImage mi = built.minimum_image(Cartesian(delta));
            m += mi.shift.cast<double>();
            delta = mi.vector;
            delta_sq = delta.squaredNorm();
        }
        max_sq = std::max(max_sq, delta_sq);
        if (max_sq > stop_above_sq) {
            return std::sqrt(max_sq);
        }
        if (jumps != nullptr) {
            const Eigen::Vector3d r = x + h * m;
            for (int k = 0; k < 3; ++k) {
                jumps[3 * i + std::size_t(k)] = static_cast<std::int32_t>(m[k]);
                unwrapped[3 * i + std::size_t(k)] = r[k];
            }
        }
    }
    return std::sqrt(max_sq);
}

double DisplacementTracker::max_displacement(const Box& box, PointsView positions) const {
    check_view(positions);
    if (!compatible(box, positions)) {
        return std::numeric_limits<double>::infinity();
    }
    return track(box, positions, std::numeric_limits<double>::infinity(), true, nullptr, nullptr);
}

bool DisplacementTracker::needs_rebuild(const Box& box, PointsView positions, double skin,
                                        double cutoff) const {
    check_view(positions);
    const double limit = compatible(box, positions) ? budget(box, skin, cutoff) : -1;
    if (limit < 0) {
        check_all_finite(positions);
        return true;
    }
    return track(box, positions, limit, false, nullptr, nullptr) > limit;
}

bool DisplacementTracker::jumps_since_record(const Box& box, PointsView positions, double skin,
                                             double cutoff, std::int32_t* out) const {
    check_view(positions);
    const double limit = compatible(box, positions) ? budget(box, skin, cutoff) : -1;
    if (limit < 0) {
        check_all_finite(positions);
        return false;
    }
    std::vector<double> unwrapped(3 * atom_count_);
    if (track(box, positions, limit, false, out, unwrapped.data()) > limit) {
        return false;
    }
    for (std::size_t k = 0; k < 3 * atom_count_; ++k) {
        out[k] -= build_jumps_[k];
    }
    return true;
}

} // namespace tricell
