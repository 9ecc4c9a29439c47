// π, and the volume of a ball, which the box (angles), the cost model and the policy (the pairs a
// search sphere holds) compute with.
#pragma once

#include <cmath>

namespace tricell::detail {

constexpr double pi = 3.14159265358979323846;

/// The volume of a ball of radius r, 4/3 π r^3.
inline double sphere_volume(double r) {
    return 4.0 / 3.0 * pi * (r * r * r);
}

} // namespace tricell::detail
