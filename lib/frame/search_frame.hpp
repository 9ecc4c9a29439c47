// The search frame. A search runs in the caller's box or, when its periodic vectors are strongly
// skewed, in the reduced cell spanning the same lattice (wider perpendicular widths, so fewer and
// rounder cells; lattice reduction as in lib/lattice_reduction.cpp). Every position is wrapped
// into that box along its periodic axes, remembering the integer image it came from
// (x = wrapped + H image), and a shift S' found in the search frame maps back to the caller's
// lattice vectors as S = T S' with the reduction's unimodular transform T. That is how a
// reported S is relative to the caller's own positions, even far outside the box.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "scan/candidate_scan.hpp"
#include "tricell/box.hpp"
#include "tricell/pair_columns.hpp"
#include "tricell/types.hpp"

namespace tricell::detail {

/// The box to search in, and the transform that maps its shifts to the caller's
/// (identity when the caller's box is used).
Box search_frame(const Box& box, bool allow_reduction, Eigen::Matrix3i& to_caller);

/// Positions wrapped into the frame: fractional coordinates in [0, 1) along periodic axes, the
/// image each came from, and the extent of the wrapped coordinates per axis.
struct WrappedPositions {
    std::vector<Eigen::Vector3d> fractional;
    PairArray<std::int32_t> image; ///< 3 per atom
    Eigen::Vector3d lower = Eigen::Vector3d::Zero(), upper = Eigen::Vector3d::Zero();
};

/// Wraps every position into `frame` on `threads` threads. A position the box cannot take is
/// refused naming its index.
void wrap_positions(const Box& frame, PointsView positions, std::size_t threads,
                    WrappedPositions& out);

/// In a reduced frame (to_caller not the identity), refuses with the caller's own box's message
/// a position more than Box::max_fractional caller box lengths away along a periodic axis, as a
/// search in the caller's frame does: the reduced frame's wrap bounds only the reduced
/// coordinates, and a shift in the caller's frame must fit an int. `image` are the reduced
/// frame's images; the caller's coordinates are computed only when their bound from those
/// images, sum_l |T_kl| (|c'_l| + 1), passes the limit.
void check_caller_range(const Box& caller_box, const Eigen::Matrix3i& to_caller,
                        PointsView positions, const PairArray<std::int32_t>& image,
                        std::size_t threads);

/// Fills `atoms` in the backend's `order` with the wrapped Cartesian positions x - H image
/// (exactly x for atoms already in the box) and their images.
void fill_atom_table(const Eigen::Matrix3d& h, PointsView positions,
                     const PairArray<std::int32_t>& image, std::vector<std::uint32_t> order,
                     std::size_t threads, AtomTable& atoms);

/// Maps shifts found in the search frame to the caller's: S = to_caller * S'.
void to_caller_frame(PairArray<std::int32_t>& shifts, const Eigen::Matrix3i& to_caller);

} // namespace tricell::detail
