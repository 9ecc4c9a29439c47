// Inputs of the page examples' harnesses: the 8 atoms of conventional diamond silicon (a = 5.43)
// and a brute-force count of the pairs within a cutoff over every image that can hold one.
#pragma once

#include <cmath>
#include <cstddef>
#include <vector>

#include <tricell/tricell.hpp>

namespace doc {

inline std::vector<Eigen::Vector3d> silicon(double a = 5.43) {
    const double f[8][3] = {{0, 0, 0},          {0, 0.5, 0.5},      {0.5, 0, 0.5},
                            {0.5, 0.5, 0},      {0.25, 0.25, 0.25}, {0.25, 0.75, 0.75},
                            {0.75, 0.25, 0.75}, {0.75, 0.75, 0.25}};
    std::vector<Eigen::Vector3d> x;
    for (const auto& s : f) {
        x.emplace_back(a * s[0], a * s[1], a * s[2]);
    }
    return x;
}

// Ordered pairs (i, j, S) with |x_j - x_i + H S| < cutoff, except (i, i, 0), counting every
// image within `reach` cells along periodic axes of the points wrapped into the box (the count
// does not change when a point moves by a lattice vector; enough when reach widths pass the
// cutoff plus one box).
inline std::size_t brute_force_pairs(const tricell::Box& box, std::vector<Eigen::Vector3d> x,
                                     double cutoff, int reach) {
    for (auto& p : x) {
        p = box.wrap(tricell::Cartesian(p));
    }
    std::size_t count = 0;
    const Eigen::Matrix3d& h = box.matrix();
    int r[3];
    for (int axis = 0; axis < 3; ++axis) {
        r[axis] = box.periodic(axis) ? reach : 0;
    }
    for (std::size_t i = 0; i < x.size(); ++i) {
        for (std::size_t j = 0; j < x.size(); ++j) {
            for (int a = -r[0]; a <= r[0]; ++a) {
                for (int b = -r[1]; b <= r[1]; ++b) {
                    for (int c = -r[2]; c <= r[2]; ++c) {
                        if (i == j && a == 0 && b == 0 && c == 0) {
                            continue;
                        }
                        const Eigen::Vector3d d = x[j] - x[i] + h * Eigen::Vector3d(a, b, c);
                        count += d.norm() < cutoff ? 1 : 0;
                    }
                }
            }
        }
    }
    return count;
}

} // namespace doc
