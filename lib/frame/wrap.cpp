#include "frame/wrap.hpp"

#include <algorithm>
#include <array>
#include <cmath>

#include "detail/parallel.hpp"
#include "tricell/error.hpp"

namespace tricell::detail {

namespace {

void wrap_into(const Box& box, PointsView positions, std::size_t threads, WrappedPositions& out) {
    const std::size_t n = positions.size();
    out.fractional.resize(n);
    out.image.resize(3 * n); // every entry written below
    // Each range's bounds (on the stack for one thread, the usual small system).
    Eigen::Vector3d one_lower, one_upper;
    std::vector<Eigen::Vector3d> many_lower(threads > 1 ? threads : 0), many_upper(many_lower);
    Eigen::Vector3d* range_lower = threads > 1 ? many_lower.data() : &one_lower;
    Eigen::Vector3d* range_upper = threads > 1 ? many_upper.data() : &one_upper;
    parallel_ranges(n, threads, [&](std::size_t begin, std::size_t end, std::size_t t) {
        // Each range's bounds are kept in locals and stored once: updated in place per atom,
        // neighbouring threads' entries would share a cache line.
        Eigen::Vector3d low = Eigen::Vector3d::Zero(), high = low;
        for (std::size_t i = begin; i < end; ++i) {
            WrappedFractional w;
            try {
                w = box.wrap(box.to_fractional(Cartesian(positions[i])));
            } catch (const InvalidArgument& e) {
                fail<InvalidArgument>("position ", i, ": ", e.what());
            }
            out.fractional[i] = w.wrapped;
            for (int k = 0; k < 3; ++k) {
                out.image[3 * i + std::size_t(k)] = w.image[k];
            }
            if (i == begin) {
                low = high = w.wrapped;
            } else {
                low = low.cwiseMin(w.wrapped);
                high = high.cwiseMax(w.wrapped);
            }
        }
        range_lower[t] = low;
        range_upper[t] = high;
    });
    out.lower = out.upper = Eigen::Vector3d::Zero();
    if (n > 0) {
        out.lower = range_lower[0];
        out.upper = range_upper[0];
        for (std::size_t t = 1; t < threads; ++t) {
            out.lower = out.lower.cwiseMin(range_lower[t]);
            out.upper = out.upper.cwiseMax(range_upper[t]);
        }
    }
}

// Refuses, as the caller's box does, positions too far away for it (see wrap_positions()).
void check_caller_range(const SearchFrame& frame, PointsView positions,
                        const PairArray<std::int32_t>& image, std::size_t threads) {
    const Eigen::Matrix3i& to_caller = frame.to_caller();
    std::array<double, 3> largest{{0, 0, 0}};
    for (std::size_t k = 0; k < image.size(); ++k) {
        largest[k % 3] = std::max(largest[k % 3], std::abs(double(image[k])));
    }
    bool within = true;
    for (int row = 0; row < 3; ++row) {
        if (!frame.caller_box().periodic(row)) {
            continue;
        }
        double bound = 0;
        for (int l = 0; l < 3; ++l) {
            bound += std::abs(double(to_caller(row, l))) * (largest[std::size_t(l)] + 1);
        }
        within = within && bound <= Box::max_fractional;
    }
    if (!within) {
        WrappedPositions caller;
        wrap_into(frame.caller_box(), positions, threads, caller); // throws as the caller's box
    }
}

} // namespace

void wrap_positions(const SearchFrame& frame, PointsView positions, std::size_t threads,
                    WrappedPositions& out) {
    wrap_into(frame.box(), positions, threads, out);
    if (frame.reduced()) {
        check_caller_range(frame, positions, out.image, threads);
    }
}

} // namespace tricell::detail
