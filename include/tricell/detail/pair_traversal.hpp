// Template part of NeighborSearch: the loops over cells, stencil entries and atom pairs.
// Included at the end of tricell/neighbor_list.hpp; not a public header on its own.
//
// for_each_cell_pair() resolves every (cell, stencil offset) into the neighbour cell, its image
// shift and that shift as a Cartesian vector, once per cell pair. The layouts then loop over the
// atoms of the two cells: the sorted layout over two contiguous struct-of-arrays ranges (a
// branch-free distance test the compiler can vectorise), the linked layout along two chains.
// Each hit is reported with the caller's atom indices and the image shift relative to the
// caller's positions; half lists are then turned into the canonical orientation.
#pragma once

#include <cstddef>
#include <cstdint>
#include <utility>

namespace tricell {

template <class CellPair> void NeighborSearch::for_each_cell_pair(CellPair &&cell_pair) const {
    const std::array<int, 3> &n = grid_.dims();
    const std::array<int, 3> &m = grid_.reach();
    const std::vector<CellOffset> &offsets = stencil_.offsets();
    for (int ca = 0; ca < n[0]; ++ca) {
        for (int cb = 0; cb < n[1]; ++cb) {
            for (int cc = 0; cc < n[2]; ++cc) {
                const std::size_t c1 = grid_.flat(ca, cb, cc);
                for (const CellOffset &d : offsets) {
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
    }
}

template <bool Half, class Emit> void NeighborSearch::traverse_sorted(Emit &&emit) const {
    const double *x = x_.data();
    const double *y = y_.data();
    const double *z = z_.data();
    const std::int32_t *image = sorted_image_.data();
    const std::vector<std::uint32_t> &order = sorted_.order();
    const double cutoff_sq = cutoff_sq_;
    for_each_cell_pair([&](std::size_t c1, std::size_t c2, bool own, const int *shift,
                           const Eigen::Vector3d &shift_vector) {
        const std::uint32_t begin1 = sorted_.cell_start(c1), end1 = sorted_.cell_end(c1);
        const std::uint32_t begin2 = sorted_.cell_start(c2), end2 = sorted_.cell_end(c2);
        if (begin1 == end1 || begin2 == end2) {
            return;
        }
        for (std::uint32_t a = begin1; a < end1; ++a) {
            // D = x_b + H shift - x_a = x_b - (x_a - H shift)
            const double ax = x[a] - shift_vector.x();
            const double ay = y[a] - shift_vector.y();
            const double az = z[a] - shift_vector.z();
            auto scan = [&](std::uint32_t from, std::uint32_t to) {
                for (std::uint32_t b = from; b < to; ++b) {
                    const double dx = x[b] - ax, dy = y[b] - ay, dz = z[b] - az;
                    const double d_sq = dx * dx + dy * dy + dz * dz;
                    if (d_sq < cutoff_sq) {
                        emit(order[a], order[b], shift[0] + image[3 * a] - image[3 * b],
                             shift[1] + image[3 * a + 1] - image[3 * b + 1],
                             shift[2] + image[3 * a + 2] - image[3 * b + 2], dx, dy, dz, d_sq);
                    }
                }
            };
            if (!own) {
                scan(begin2, end2);
            } else if (Half) {
                scan(a + 1, end2);
            } else {
                scan(begin2, a);
                scan(a + 1, end2);
            }
        }
    });
}

template <bool Half, class Emit> void NeighborSearch::traverse_linked(Emit &&emit) const {
    const double *r = wrapped_.data();
    const std::int32_t *image = image_.data();
    const double cutoff_sq = cutoff_sq_;
    for_each_cell_pair([&](std::size_t c1, std::size_t c2, bool own, const int *shift,
                           const Eigen::Vector3d &shift_vector) {
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
    });
}

template <class Emit> void NeighborSearch::traverse(Emit &&emit) const {
    if (!options_.half) {
        if (options_.cell_list == CellListKind::sorted) {
            traverse_sorted<false>(emit);
        } else {
            traverse_linked<false>(emit);
        }
        return;
    }
    // Half list: report (i, j, S) with i < j, or i == j and S lexicographically positive.
    auto canonical = [&](std::uint32_t i, std::uint32_t j, int sa, int sb, int sc, double dx,
                         double dy, double dz, double d_sq) {
        const bool flip =
            i > j || (i == j && (sa < 0 || (sa == 0 && (sb < 0 || (sb == 0 && sc < 0)))));
        if (flip) {
            emit(j, i, -sa, -sb, -sc, -dx, -dy, -dz, d_sq);
        } else {
            emit(i, j, sa, sb, sc, dx, dy, dz, d_sq);
        }
    };
    if (options_.cell_list == CellListKind::sorted) {
        traverse_sorted<true>(canonical);
    } else {
        traverse_linked<true>(canonical);
    }
}

template <class Visit> void NeighborSearch::for_each_pair(Visit &&visit) const {
    traverse([&](std::uint32_t i, std::uint32_t j, int sa, int sb, int sc, double dx, double dy,
                 double dz, double d_sq) {
        const Pair pair{i, j, Shift(sa, sb, sc), Eigen::Vector3d(dx, dy, dz), d_sq};
        visit(pair);
    });
}

} // namespace tricell
