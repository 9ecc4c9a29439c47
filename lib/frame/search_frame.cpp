#include "frame/search_frame.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include "detail/lattice_reduction.hpp"
#include "detail/parallel.hpp"
#include "frame/caller_shift.hpp"
#include "tricell/error.hpp"

namespace tricell::detail {

Box search_frame(const Box& box, bool allow_reduction, Eigen::Matrix3i& to_caller) {
    to_caller.setIdentity();
    if (!allow_reduction || !box.periodicity().any()) {
        return box;
    }
    const ReducedCell reduced = reduce_cell(box.matrix(), box.periodicity().axes);
    if (reduced.transform == Eigen::Matrix3i::Identity()) {
        return box;
    }
    const Box candidate = Box::from_columns(reduced.h, box.periodicity());
    double before = std::numeric_limits<double>::infinity(), after = before;
    for (int k = 0; k < 3; ++k) {
        if (box.periodic(k)) {
            before = std::min(before, box.perpendicular_widths()[k]);
            after = std::min(after, candidate.perpendicular_widths()[k]);
        }
    }
    if (after < 1.05 * before) {
        return box; // not worth a change of frame
    }
    to_caller = reduced.transform;
    return candidate;
}

void wrap_positions(const Box& frame, PointsView positions, std::size_t threads,
                    WrappedPositions& out) {
    const std::size_t n = positions.size();
    out.fractional.resize(n);
    out.image.resize(3 * n); // every entry written below
    std::vector<Eigen::Vector3d> range_lower(threads), range_upper(threads);
    parallel_ranges(n, threads, [&](std::size_t begin, std::size_t end, std::size_t t) {
        // Each range's bounds are kept in locals and stored once: updated in place per atom,
        // neighbouring threads' entries would share a cache line.
        Eigen::Vector3d low = Eigen::Vector3d::Zero(), high = low;
        for (std::size_t i = begin; i < end; ++i) {
            WrappedFractional w;
            try {
                w = frame.wrap(frame.to_fractional(Cartesian(positions[i])));
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

void check_caller_range(const Box& caller_box, const Eigen::Matrix3i& to_caller,
                        PointsView positions, const PairArray<std::int32_t>& image,
                        std::size_t threads) {
    if (to_caller == Eigen::Matrix3i::Identity()) {
        return;
    }
    std::array<double, 3> largest{{0, 0, 0}};
    for (std::size_t k = 0; k < image.size(); ++k) {
        largest[k % 3] = std::max(largest[k % 3], std::abs(double(image[k])));
    }
    bool within = true;
    for (int row = 0; row < 3; ++row) {
        if (!caller_box.periodic(row)) {
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
        wrap_positions(caller_box, positions, threads, caller); // throws as the caller's box does
    }
}

void fill_atom_table(const Eigen::Matrix3d& h, PointsView positions,
                     const PairArray<std::int32_t>& image, std::vector<std::uint32_t> order,
                     std::size_t threads, AtomTable& atoms) {
    const std::size_t n = positions.size();
    atoms.x.resize(n);
    atoms.y.resize(n);
    atoms.z.resize(n);
    atoms.image.resize(3 * n);
    atoms.index = std::move(order);
    parallel_ranges(n, threads, [&](std::size_t begin, std::size_t end, std::size_t) {
        for (std::size_t k = begin; k < end; ++k) {
            const std::size_t i = atoms.index[k];
            const Eigen::Vector3d img(image[3 * i], image[3 * i + 1], image[3 * i + 2]);
            const Eigen::Vector3d r = Eigen::Vector3d(positions[i]) - h * img;
            atoms.x[k] = r.x();
            atoms.y[k] = r.y();
            atoms.z[k] = r.z();
            for (std::size_t a = 0; a < 3; ++a) {
                atoms.image[3 * k + a] = image[3 * i + a];
            }
        }
    });
    atoms.zero_images = std::all_of(image.data(), image.data() + image.size(),
                                    [](std::int32_t v) { return v == 0; });
}

void to_caller_frame(PairArray<std::int32_t>& shifts, const Eigen::Matrix3i& to_caller) {
    for (std::size_t k = 0; k < shifts.size(); k += 3) {
        const Eigen::Vector3i s = caller_shift(to_caller, shifts[k], shifts[k + 1], shifts[k + 2]);
        shifts[k] = s[0];
        shifts[k + 1] = s[1];
        shifts[k + 2] = s[2];
    }
}

} // namespace tricell::detail
