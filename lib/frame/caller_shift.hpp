// A shift found in a reduced search frame, in the caller's frame: S = T S' (T the integer
// matrix of the reduction, frame/search_frame.hpp). The products are taken in 64 bits: the result fits
// an int (build() refuses positions more than Box::max_fractional caller box lengths away, as
// the caller's own box would), but a product of an entry of T and a component of S' alone
// need not.
#pragma once

#include <cstdint>

#include <Eigen/Core>

namespace tricell::detail {

inline Eigen::Vector3i caller_shift(const Eigen::Matrix3i& to_caller, int sa, int sb, int sc) {
    Eigen::Vector3i out;
    for (int r = 0; r < 3; ++r) {
        out[r] = int(std::int64_t(to_caller(r, 0)) * sa + std::int64_t(to_caller(r, 1)) * sb +
                     std::int64_t(to_caller(r, 2)) * sc);
    }
    return out;
}

} // namespace tricell::detail
