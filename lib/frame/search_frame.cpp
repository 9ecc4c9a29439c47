#include "frame/search_frame.hpp"

#include <algorithm>
#include <limits>

#include "detail/lattice_reduction.hpp"

namespace tricell::detail {

SearchFrame::SearchFrame()
    : caller_(Box::from_columns(Eigen::Matrix3d::Identity())), box_(caller_) {}

SearchFrame::SearchFrame(const Box& caller, bool allow_reduction) : caller_(caller), box_(caller) {
    if (!allow_reduction || !caller.periodicity().any()) {
        return;
    }
    const ReducedCell reduced = reduce_cell(caller.matrix(), caller.periodicity().axes);
    if (reduced.transform == Eigen::Matrix3i::Identity()) {
        return;
    }
    const Box candidate = Box::from_columns(reduced.h, caller.periodicity());
    double before = std::numeric_limits<double>::infinity(), after = before;
    for (int k = 0; k < 3; ++k) {
        if (caller.periodic(k)) {
            before = std::min(before, caller.perpendicular_widths()[k]);
            after = std::min(after, candidate.perpendicular_widths()[k]);
        }
    }
    if (after < 1.05 * before) {
        return; // not worth a change of frame
    }
    box_ = candidate;
    to_caller_ = reduced.transform;
    reduced_ = true;
}

void SearchFrame::to_caller(std::int32_t* shifts, std::size_t count) const {
    if (!reduced_) {
        return;
    }
    for (std::size_t k = 0; k < count; ++k) {
        std::int32_t* s = shifts + 3 * k;
        const Eigen::Vector3i c = caller_shift(s[0], s[1], s[2]);
        s[0] = c[0];
        s[1] = c[1];
        s[2] = c[2];
    }
}

} // namespace tricell::detail
