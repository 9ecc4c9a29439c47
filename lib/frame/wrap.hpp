// Positions wrapped into the search frame: every position is wrapped into the frame's box along
// its periodic axes, remembering the integer image it came from (x = wrapped + H image), so
// that the search works on positions in the cell while every pair it reports stays relative to
// the caller's own positions, even far outside the box.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "frame/search_frame.hpp"
#include "tricell/pair_columns.hpp"
#include "tricell/types.hpp"

namespace tricell::detail {

/// Fractional coordinates in [0, 1) along periodic axes, the image each came from, and the
/// extent of the wrapped coordinates per axis.
struct WrappedPositions {
    PairArray<Eigen::Vector3d> fractional;
    PairArray<std::int32_t> image; ///< 3 per atom
    Eigen::Vector3d lower = Eigen::Vector3d::Zero(), upper = Eigen::Vector3d::Zero();
};

/// Wraps every position into `frame` on `threads` threads. A position the frame's box cannot
/// take is refused naming its index; in a reduced frame, so is one the caller's own box would
/// refuse (more than Box::max_fractional caller box lengths away along a periodic axis: the
/// reduced frame's wrap bounds only the reduced coordinates, and a shift in the caller's frame
/// must fit an int), with the caller's box's message. The caller's coordinates are computed
/// only when their bound from the reduced images, sum_l |T_kl| (|c'_l| + 1), passes the limit.
void wrap_positions(const SearchFrame& frame, PointsView positions, std::size_t threads,
                    WrappedPositions& out);

} // namespace tricell::detail
