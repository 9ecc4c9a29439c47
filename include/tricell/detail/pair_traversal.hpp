// Template part of NeighborSearch: the loops over cells, stencil entries and atom pairs.
// Included at the end of tricell/neighbor_list.hpp; not a public header on its own.
//
// Sorted layout: for each cell and each stencil row (da, db, dc_lo..dc_hi), the neighbour
// cells of the row are consecutive in the sorted order, so the row is one contiguous range of
// atoms, split only where it wraps around the c axis (each piece with its own image shift).
// The distance test runs over those contiguous struct-of-arrays ranges (vectorisable), and the
// Cartesian shift vector is subtracted from atom a once per range. Linked layout: one chain per
// stencil offset. Each hit is reported with the caller's atom indices and the image shift
// relative to the caller's positions; half lists are then turned into the canonical orientation.
#pragma once

#include <cstddef>
#include <cstdint>
#include <utility>

#include "tricell/detail/distance_kernel.hpp"

namespace tricell {

namespace detail {

/// Calls hit(b, dx, dy, dz, d_sq) for every b in [from, to) with |x_b - a| < cutoff, in blocks
/// through the run-time selected distance kernel (tricell/detail/distance_kernel.hpp).
template <class Hit>
inline void scan_range(const double* x, const double* y, const double* z, std::uint32_t from,
                       std::uint32_t to, double ax, double ay, double az, double cutoff_sq,
                       Hit&& hit) {
    std::uint32_t hits[kernel_block + 4];
    double hit_d_sq[kernel_block + 4];
    for (std::uint32_t start = from; start < to; start += kernel_block) {
        const std::uint32_t count = std::min(kernel_block, to - start);
        const double* xs = x + start;
        const double* ys = y + start;
        const double* zs = z + start;
        const std::uint32_t found =
            within_cutoff(xs, ys, zs, count, ax, ay, az, cutoff_sq, hits, hit_d_sq);
        for (std::uint32_t h = 0; h < found; ++h) {
            const std::uint32_t k = hits[h];
            hit(start + k, xs[k] - ax, ys[k] - ay, zs[k] - az, hit_d_sq[h]);
        }
    }
}

} // namespace detail

template <class CellPair>
void NeighborSearch::for_each_cell_pair(CellPair&& cell_pair, std::size_t cell_begin,
                                        std::size_t cell_end) const {
    const std::array<int, 3>& n = grid_.dims();
    const std::array<int, 3>& m = grid_.reach();
    const std::vector<CellOffset>& offsets = stencil_.offsets();
    for (std::size_t c1 = cell_begin; c1 < cell_end; ++c1) {
        const int cc = int(c1 % std::size_t(n[2]));
        const int cb = int((c1 / std::size_t(n[2])) % std::size_t(n[1]));
        const int ca = int(c1 / (std::size_t(n[2]) * std::size_t(n[1])));
        for (const CellOffset& d : offsets) {
            const std::size_t ta = std::size_t(ca + d[0] + m[0]);
            const std::size_t tb = std::size_t(cb + d[1] + m[1]);
            const std::size_t tc = std::size_t(cc + d[2] + m[2]);
            const int na = neighbor_cell_[0][ta];
            const int nb = neighbor_cell_[1][tb];
            const int nc = neighbor_cell_[2][tc];
            if (na < 0 || nb < 0 || nc < 0) {
                continue; // beyond the end of an open axis
            }
            const int shift[3] = {neighbor_shift_[0][ta], neighbor_shift_[1][tb],
                                  neighbor_shift_[2][tc]};
            const Eigen::Vector3d shift_vector =
                h_.col(0) * shift[0] + h_.col(1) * shift[1] + h_.col(2) * shift[2];
            const bool own = d[0] == 0 && d[1] == 0 && d[2] == 0;
            cell_pair(c1, grid_.flat(na, nb, nc), own, shift, shift_vector);
        }
    }
}

template <class Piece>
void NeighborSearch::for_each_row_piece(std::size_t c1, Piece&& piece) const {
    const std::array<int, 3>& n = grid_.dims();
    const std::array<int, 3>& m = grid_.reach();
    const bool periodic_c = grid_.periodicity()[2];
    const int cc = int(c1 % std::size_t(n[2]));
    const int cb = int((c1 / std::size_t(n[2])) % std::size_t(n[1]));
    const int ca = int(c1 / (std::size_t(n[2]) * std::size_t(n[1])));
    for (const StencilRow& row : rows_) {
        const std::size_t ta = std::size_t(ca + row.da + m[0]);
        const std::size_t tb = std::size_t(cb + row.db + m[1]);
        const int na = neighbor_cell_[0][ta];
        const int nb = neighbor_cell_[1][tb];
        if (na < 0 || nb < 0) {
            continue; // beyond the end of an open axis
        }
        const int sa = neighbor_shift_[0][ta];
        const int sb = neighbor_shift_[1][tb];
        const std::size_t column = grid_.flat(na, nb, 0);
        const bool own_row = row.da == 0 && row.db == 0;
        // Walk t = cc + dc over the row, one piece per image along c.
        int t = cc + row.dc_lo;
        const int t_end = cc + row.dc_hi;
        if (!periodic_c) {
            t = std::max(t, 0);
        }
        while (t <= t_end) {
            int sc = 0, first = t, last = t_end;
            if (periodic_c) {
                sc = floor_div(t, n[2]);
                first = t - sc * n[2];
                last = std::min(t_end - sc * n[2], n[2] - 1);
            } else {
                last = std::min(t_end, n[2] - 1);
                if (first > last) {
                    break;
                }
            }
            t += last - first + 1;
            const std::uint32_t begin2 = sorted_.cell_start(column + std::size_t(first));
            const std::uint32_t end2 = sorted_.cell_end(column + std::size_t(last));
            if (begin2 != end2) {
                const bool own = own_row && sc == 0 && first <= cc && cc <= last;
                piece(begin2, end2, own, sa, sb, sc);
            }
        }
    }
}

template <bool Half, class Emit>
void NeighborSearch::traverse_sorted(Emit&& emit, std::size_t cell_begin,
                                     std::size_t cell_end) const {
    const double* x = x_.data();
    const double* y = y_.data();
    const double* z = z_.data();
    const std::int32_t* image = sorted_image_.data();
    const std::uint32_t* order = sorted_.order().data();
    const double cutoff_sq = cutoff_sq_;
    for (std::size_t c1 = cell_begin; c1 < cell_end; ++c1) {
        const std::uint32_t begin1 = sorted_.cell_start(c1), end1 = sorted_.cell_end(c1);
        if (begin1 == end1) {
            continue;
        }
        for_each_row_piece(c1, [&](std::uint32_t begin2, std::uint32_t end2, bool own, int sa,
                                   int sb, int sc) {
            const Eigen::Vector3d shift_vector = h_.col(0) * sa + h_.col(1) * sb + h_.col(2) * sc;
            for (std::uint32_t a = begin1; a < end1; ++a) {
                // D = x_b + H shift - x_a = x_b - (x_a - H shift)
                const double ax = x[a] - shift_vector.x();
                const double ay = y[a] - shift_vector.y();
                const double az = z[a] - shift_vector.z();
                const int base[3] = {sa + image[3 * a], sb + image[3 * a + 1],
                                     sc + image[3 * a + 2]};
                const std::uint32_t i = order[a];
                auto hit = [&](std::uint32_t b, double dx, double dy, double dz, double d_sq) {
                    emit(i, order[b], base[0] - image[3 * b], base[1] - image[3 * b + 1],
                         base[2] - image[3 * b + 2], dx, dy, dz, d_sq);
                };
                if (!own) {
                    detail::scan_range(x, y, z, begin2, end2, ax, ay, az, cutoff_sq, hit);
                } else if (Half) {
                    // The half row starts at the own cell: pairs with later atoms only.
                    detail::scan_range(x, y, z, a + 1, end2, ax, ay, az, cutoff_sq, hit);
                } else {
                    detail::scan_range(x, y, z, begin2, a, ax, ay, az, cutoff_sq, hit);
                    detail::scan_range(x, y, z, a + 1, end2, ax, ay, az, cutoff_sq, hit);
                }
            }
        });
    }
}

template <bool Half, class Emit>
void NeighborSearch::traverse_linked(Emit&& emit, std::size_t cell_begin,
                                     std::size_t cell_end) const {
    const double* r = wrapped_.data();
    const std::int32_t* image = image_.data();
    const double cutoff_sq = cutoff_sq_;
    auto cell_pair = [&](std::size_t c1, std::size_t c2, bool own, const int* shift,
                         const Eigen::Vector3d& shift_vector) {
        const std::int32_t head2 = linked_.head(c2);
        if (head2 == LinkedCellList::end) {
            return;
        }
        for (std::int32_t a = linked_.head(c1); a != LinkedCellList::end; a = linked_.next(a)) {
            const double ax = r[3 * a] - shift_vector.x();
            const double ay = r[3 * a + 1] - shift_vector.y();
            const double az = r[3 * a + 2] - shift_vector.z();
            const std::int32_t first = (own && Half) ? linked_.next(a) : head2;
            for (std::int32_t b = first; b != LinkedCellList::end; b = linked_.next(b)) {
                if (!Half && own && b == a) {
                    continue;
                }
                const double dx = r[3 * b] - ax, dy = r[3 * b + 1] - ay, dz = r[3 * b + 2] - az;
                const double d_sq = dx * dx + dy * dy + dz * dz;
                if (d_sq < cutoff_sq) {
                    emit(std::uint32_t(a), std::uint32_t(b), shift[0] + image[3 * a] - image[3 * b],
                         shift[1] + image[3 * a + 1] - image[3 * b + 1],
                         shift[2] + image[3 * a + 2] - image[3 * b + 2], dx, dy, dz, d_sq);
                }
            }
        }
    };
    for_each_cell_pair(cell_pair, cell_begin, cell_end);
}

template <class Emit>
void NeighborSearch::traverse(Emit&& emit, std::size_t cell_begin, std::size_t cell_end) const {
    const bool sorted = options_.cell_list == CellListKind::sorted;
    if (!options_.half) {
        if (sorted) {
            traverse_sorted<false>(emit, cell_begin, cell_end);
        } else {
            traverse_linked<false>(emit, cell_begin, cell_end);
        }
        return;
    }
    // Half list: report (i, j, S) with i < j, or i == j and S lexicographically positive.
    // Whether to flip is a coin toss per pair, so it selects values instead of branching.
    auto canonical = [&](std::uint32_t i, std::uint32_t j, int sa, int sb, int sc, double dx,
                         double dy, double dz, double d_sq) {
        bool flip = i > j;
        if (i == j) { // an atom and its own image: orient by S in the caller's frame
            Eigen::Vector3i s(sa, sb, sc);
            if (reduced_frame_) {
                s = to_caller_ * s;
            }
            flip = s[0] < 0 || (s[0] == 0 && (s[1] < 0 || (s[1] == 0 && s[2] < 0)));
        }
        const int sign = flip ? -1 : 1;
        const double real_sign = flip ? -1.0 : 1.0;
        emit(flip ? j : i, flip ? i : j, sign * sa, sign * sb, sign * sc, real_sign * dx,
             real_sign * dy, real_sign * dz, d_sq);
    };
    if (sorted) {
        traverse_sorted<true>(canonical, cell_begin, cell_end);
    } else {
        traverse_linked<true>(canonical, cell_begin, cell_end);
    }
}

template <class Visit> void NeighborSearch::for_each_pair(Visit&& visit) const {
    traverse(
        [&](std::uint32_t i, std::uint32_t j, int sa, int sb, int sc, double dx, double dy,
            double dz, double d_sq) {
            Pair pair{i, j, Shift(sa, sb, sc), Eigen::Vector3d(dx, dy, dz), d_sq};
            if (reduced_frame_) {
                pair.shift = to_caller_ * pair.shift;
            }
            visit(pair);
        },
        0, grid_.cell_count());
}

} // namespace tricell
