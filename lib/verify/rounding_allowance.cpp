// The rounding allowance of a pair near its cutoff: the search subtracts wrapped positions, a
// check the caller's own, so a distance within rounding of the cutoff may fall on either side.
// The allowance grows with the condition number of the box and the size of the coordinates, the
// shift and the translations that wrapped the two atoms into the box (an atom at y = -1e-12 in a
// box 5 high is stored at 5 - 1e-12, rounded to the last bit of 5). The search wraps in its own
// frame, a reduced cell, where an atom just inside the caller's box may lie just outside and be
// moved by a lattice vector: each wrapped position counts as one box length on top.
#include <cmath>
#include <limits>

#include "tricell/verify.hpp"

namespace tricell {

namespace {

// Box lengths the search's wrap moves a position by (summed over the periodic axes).
double wrap_images(const Box& box, const Eigen::Vector3d& r) {
    const Eigen::Vector3d s = box.inverse() * r;
    double sum = 0;
    for (int k = 0; k < 3; ++k) {
        sum += box.periodic(k) ? std::abs(std::floor(s[k])) : 0.0;
    }
    return sum;
}

} // namespace

double rounding_allowance(const Box& box, const Eigen::Vector3d& xi, const Eigen::Vector3d& xj,
                          const Eigen::Vector3i& shift, double cutoff) {
    const double h_norm = box.matrix().norm();
    const double kappa = h_norm * box.inverse().norm(); // condition number of H
    const double shifts =
        std::abs(double(shift[0])) + std::abs(double(shift[1])) + std::abs(double(shift[2]));
    const double size = xi.norm() + xj.norm() +
                        h_norm * (shifts + 2 + wrap_images(box, xi) + wrap_images(box, xj)) +
                        cutoff;
    return 512 * std::numeric_limits<double>::epsilon() * kappa * size;
}

} // namespace tricell
