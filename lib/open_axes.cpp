#include "detail/open_axes.hpp"

#include <cmath>

#include <Eigen/Geometry>
#include <Eigen/LU>

namespace tricell::detail {

double unit_flatness(const Eigen::Matrix3d& h, const std::array<bool, 3>& keep) {
    Eigen::Matrix3d unit = Eigen::Matrix3d::Zero();
    int count = 0;
    int kept[3] = {0, 0, 0};
    for (int axis = 0; axis < 3; ++axis) {
        if (keep[std::size_t(axis)]) {
            const double length = h.col(axis).stableNorm();
            if (!(length > 0)) {
                return 0;
            }
            unit.col(axis) = h.col(axis) / length;
            kept[count++] = axis;
        }
    }
    if (count == 3) {
        return std::abs(unit.determinant());
    }
    if (count == 2) {
        return Eigen::Vector3d(unit.col(kept[0])).cross(Eigen::Vector3d(unit.col(kept[1]))).norm();
    }
    return 1;
}

Eigen::Matrix3d complete_open_axes(const Eigen::Matrix3d& h, const Periodicity& pbc) {
    std::array<bool, 3> keep{};
    for (int axis = 0; axis < 3; ++axis) {
        keep[std::size_t(axis)] = pbc[axis] || h.col(axis).squaredNorm() > 0;
    }
    if (!(unit_flatness(h, keep) > flatness_tolerance)) {
        keep = pbc.axes; // the given open vectors do not span with the others: replace them all
    }
    Eigen::Matrix3d out = h;
    int kept[3] = {0, 0, 0};
    int count = 0;
    for (int axis = 0; axis < 3; ++axis) {
        if (keep[std::size_t(axis)]) {
            kept[count++] = axis;
        }
    }
    if (count == 3) {
        return h;
    }
    if (count == 0) {
        return Eigen::Matrix3d::Identity();
    }
    if (count == 1) {
        // Two unit vectors orthogonal to the kept one a, in the order that makes the frame
        // right-handed: (a, b, c) cyclic from a's axis.
        const int p = kept[0];
        const Eigen::Vector3d a = h.col(p).normalized();
        const Eigen::Vector3d helper =
            std::abs(a.y()) > 0.9 ? Eigen::Vector3d::UnitZ() : Eigen::Vector3d::UnitY();
        const Eigen::Vector3d c = a.cross(helper).normalized();
        out.col((p + 1) % 3) = c.cross(a).normalized();
        out.col((p + 2) % 3) = c;
        return out;
    }
    // Two kept: the missing one is their normalised cross product, right-handed.
    const int m = 3 - kept[0] - kept[1];
    out.col(m) =
        Eigen::Vector3d(h.col((m + 1) % 3)).cross(Eigen::Vector3d(h.col((m + 2) % 3))).normalized();
    return out;
}

} // namespace tricell::detail
