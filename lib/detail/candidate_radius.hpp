// The radius a Verlet list searches its candidates at: the list radius r_l = r_c + skin widened
// by a relative margin (1e-10 of r_l) and by a margin relative to the size of the coordinates
// (1e-13 of the largest of the box matrix's entries and the positions' coordinates). The search
// works on wrapped positions and the displacements are rounded too; the margins make sure that
// rounding can never drop a candidate the rebuild rule (tricell/displacement.hpp) relies on. Extra
// candidates are harmless: every refresh filters them at r_c. The serial VerletList and the
// distributed one (lib/mpi/verlet.cpp) both search at this radius.
#pragma once

#include <algorithm>
#include <cmath>

#include <Eigen/Core>

#include "tricell/types.hpp"

namespace tricell::detail {

/// `h`: the box's matrix (Box::matrix()).
inline double candidate_radius(double list_radius, const Eigen::Matrix3d& h, PointsView positions) {
    constexpr double candidate_margin = 1e-10;
    constexpr double coordinate_margin = 1e-13;
    double scale = h.cwiseAbs().maxCoeff();
    for (std::size_t i = 0; i < positions.size(); ++i) {
        const double r = Eigen::Vector3d(positions[i]).cwiseAbs().maxCoeff();
        scale = std::isfinite(r) ? std::max(scale, r) : scale; // the search reports non-finite
    }
    return list_radius * (1 + candidate_margin) + coordinate_margin * scale;
}

} // namespace tricell::detail
