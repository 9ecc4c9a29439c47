// The search frame. A search runs in the caller's box or, when its periodic vectors are strongly
// skewed, in the reduced cell spanning the same lattice (wider perpendicular widths, so fewer and
// rounder cells; lattice reduction as in lib/lattice_reduction.cpp). A shift S' found in the
// search frame maps back to the caller's lattice vectors as S = T S' with the reduction's
// unimodular transform T. That is how a reported S is relative to the caller's own positions,
// even far outside the box. caller_shift() is that map, the only one: the stored columns, the
// blocks of for_each_pair() and the half list's orientation of an atom's own images all go
// through it. Its products are taken in 64 bits: the result fits an int (wrap.hpp refuses
// positions more than Box::max_fractional caller box lengths away, as the caller's own box
// would), but a product of an entry of T and a component of S' alone need not.
#pragma once

#include <cstdint>

#include <Eigen/Core>

#include "tricell/box.hpp"
#include "tricell/pair_columns.hpp"

namespace tricell::detail {

class SearchFrame {
  public:
    /// The unit cube searched as itself (the frame of a search not built yet).
    SearchFrame();
    /// The frame to search `caller` in: its reduced twin when `allow_reduction` and the reduction
    /// widens the narrowest periodic width by at least 5 %, else the caller's box itself.
    SearchFrame(const Box& caller, bool allow_reduction);

    /// The box the search runs in.
    const Box& box() const { return box_; }
    /// The caller's box.
    const Box& caller_box() const { return caller_; }
    /// Whether the search runs in the reduced cell (T is not the identity).
    bool reduced() const { return reduced_; }
    /// T: S = T S'.
    const Eigen::Matrix3i& to_caller() const { return to_caller_; }

    /// The caller's S of a shift S' = (sa, sb, sc) found in this frame.
    Eigen::Vector3i caller_shift(int sa, int sb, int sc) const {
        if (!reduced_) {
            return {sa, sb, sc};
        }
        Eigen::Vector3i out;
        for (int r = 0; r < 3; ++r) {
            out[r] = int(std::int64_t(to_caller_(r, 0)) * sa + std::int64_t(to_caller_(r, 1)) * sb +
                         std::int64_t(to_caller_(r, 2)) * sc);
        }
        return out;
    }

    /// Maps `count` shifts (3 ints each) found in this frame to the caller's, in place.
    void to_caller(std::int32_t* shifts, std::size_t count) const;

  private:
    Box caller_;
    Box box_;
    Eigen::Matrix3i to_caller_ = Eigen::Matrix3i::Identity();
    bool reduced_ = false;
};

} // namespace tricell::detail
