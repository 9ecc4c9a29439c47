// Random boxes and points for property tests, all from explicit seeds.
#pragma once

#include <cmath>
#include <random>

#include <Eigen/Geometry>

#include "tricell/box.hpp"

namespace tricell::testing {

/// A random triclinic box: edge lengths in [min_len, max_len], random tilts up to `skew`
/// times the edge lengths (skew 0 = orthorhombic; skew 5 = strongly skewed), random rotation,
/// and a random handedness when `allow_left_handed`.
inline Eigen::Matrix3d random_box_matrix(std::mt19937_64& rng, double min_len, double max_len,
                                         double skew, bool allow_left_handed = true) {
    std::uniform_real_distribution<double> len(min_len, max_len);
    std::uniform_real_distribution<double> tilt(-skew, skew);
    const double lx = len(rng), ly = len(rng), lz = len(rng);
    Eigen::Matrix3d h;
    h << lx, tilt(rng) * lx, tilt(rng) * lx, //
        0, ly, tilt(rng) * ly,               //
        0, 0, lz;
    std::normal_distribution<double> normal;
    Eigen::Vector4d q(normal(rng), normal(rng), normal(rng), normal(rng));
    const Eigen::Matrix3d rotation = Eigen::Quaterniond(q.normalized()).toRotationMatrix();
    h = rotation * h;
    if (allow_left_handed && std::uniform_int_distribution<int>(0, 3)(rng) == 0) {
        h.col(2) = -h.col(2);
    }
    return h;
}

} // namespace tricell::testing
