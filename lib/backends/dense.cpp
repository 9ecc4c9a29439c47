// The dense backend: every cell of a CellGrid exists (at most max_cells of them, so memory
// follows the atoms), the atoms are counting-sorted by cell (SortedCellList), and each cell is
// paired with the stencil row by row. With c varying fastest, the neighbour cells of one row are
// consecutive in the sorted order, so a row is one contiguous range of atoms, split only where
// it wraps around the c axis (each piece with its own image shift). The work units are cells.
// Where the range kernel prunes (more atoms than cells, a stencil that does not wrap), the atoms
// of each cell are sorted along c and cut into clusters of at most cluster_atoms, as the
// cluster-pair search of Pall & Hess (2013) cuts its grid columns: a row then runs along c
// cluster by cluster, each a thin slab of its cell. Each range names its first and last
// cluster, and the first visit after a binning takes the bounding box of every cluster's atoms
// (from the scanner's positions, once, whichever thread comes first), by which the range kernel
// leaves out the clusters at either end of a row beyond an atom's reach.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdlib>
#include <limits>
#include <memory>
#include <mutex>

#include "backends/backend.hpp"
#include "backends/grid_neighbourhood.hpp"
#include "detail/parallel.hpp"
#include "tricell/cell_list.hpp"

namespace tricell::detail {

namespace {

// Atoms per cluster at most: the boxes the range kernel tests (see build_boxes()).
constexpr std::uint32_t cluster_atoms = 8;

class DenseBackend final : public Backend {
  public:
    void bin(const BinningInput& input, std::vector<std::uint32_t>& order) override {
        const std::size_t n = input.fractional.size();
        cells_.build(input, input.plan.cell_cap, true);
        cell_of_.resize(n);
        parallel_ranges(
            n, input.plan.threads, [&](std::size_t begin, std::size_t end, std::size_t) {
                for (std::size_t i = begin; i < end; ++i) {
                    cell_of_[i] =
                        static_cast<std::uint32_t>(cells_.grid().cell_of(input.fractional[i]));
                }
            });
        sorted_.build(cell_of_, cells_.grid().cell_count(), input.plan.threads);
        order = sorted_.order();
        // The rows as flat cell offsets, for the cells whose every row lies inside the grid.
        const std::array<int, 3>& dims = cells_.grid().dims();
        inner_rows_.clear();
        reach_ = {0, 0, 0};
        for (const StencilRow& row : cells_.rows()) {
            const std::ptrdiff_t base =
                (std::ptrdiff_t(row.da) * dims[1] + row.db) * std::ptrdiff_t(dims[2]);
            inner_rows_.push_back(
                InnerRow{base + row.dc_lo, base + row.dc_hi,
                         row.da == 0 && row.db == 0 && row.dc_lo <= 0 && 0 <= row.dc_hi});
            reach_[0] = std::max(reach_[0], std::abs(row.da));
            reach_[1] = std::max(reach_[1], std::abs(row.db));
            reach_[2] = std::max({reach_[2], std::abs(row.dc_lo), std::abs(row.dc_hi)});
        }
        wraps_ = false;
        for (std::size_t k = 0; k < 3; ++k) {
            wraps_ = wraps_ || 2 * reach_[k] + 1 > dims[k];
        }
        // Boxes only for a grid of more atoms than cells (a sparse one, a gas or a droplet in
        // vacuum, gains little from them and pays a box per empty cell) whose stencil does not
        // wrap (its pieces go through the scanner's ranges(), unpruned).
        boxes_pay_ = !wraps_ && n >= cells_.grid().cell_count();
        boxes_once_ = std::make_unique<std::once_flag>();
        if (boxes_pay_) {
            sort_along_rows(input, order);
        }
    }

    std::size_t unit_count() const override { return cells_.grid().cell_count(); }

    void occupancy(UnitOccupancy& out) const override {
        out.atoms.resize(unit_count());
        for (std::size_t c = 0; c < out.atoms.size(); ++c) {
            out.atoms[c] = double(sorted_.cell_end(c) - sorted_.cell_start(c));
        }
        out.volume.assign(unit_count(), cells_.cell_volume());
    }

    double neighbours() const override { return double(cells_.stencil().size()); }

    void visit(std::size_t begin, std::size_t end, CandidateScanner& scan) const override {
        if (boxes_pay_) {
            std::call_once(*boxes_once_, [&] { build_boxes(scan); });
            scan.prune_by_clusters(boxes_.data(), starts_.data(), bound_);
        }
        const std::array<int, 3>& n = cells_.grid().dims();
        const bool periodic_c = cells_.grid().periodicity()[2];
        std::vector<CandidateRange> pieces; // of one home cell's rows
        std::vector<CandidateRange> inner;  // of a cell inside the grid (shifts all zero)
        for (std::size_t c1 = begin; c1 < end; ++c1) {
            const std::uint32_t begin1 = sorted_.cell_start(c1), end1 = sorted_.cell_end(c1);
            if (begin1 == end1) {
                continue;
            }
            const std::array<int, 3> c = cells_.coordinates(c1);
            pieces.clear();
            if (inside(c, n)) {
                // Every row is one range through a zero shift.
                inner.resize(inner_rows_.size(),
                             CandidateRange{0, 0, {0, 0, 0}, {0, 0, 0}, false, false});
                std::uint32_t count = 0;
                for (const InnerRow& row : inner_rows_) {
                    CandidateRange& r = inner[count];
                    const auto first = std::size_t(std::ptrdiff_t(c1) + row.lo);
                    const auto last = std::size_t(std::ptrdiff_t(c1) + row.hi);
                    r.b0 = sorted_.cell_start(first);
                    r.b1 = sorted_.cell_end(last);
                    r.own = row.own;
                    r.c0 = cluster_of(first);
                    r.c1 = cluster_of(last + 1) - 1;
                    count += r.b0 != r.b1 ? 1 : 0;
                }
                scan.cell(begin1, end1, inner.data(), count);
                continue;
            }
            for (const StencilRow& row : cells_.rows()) {
                const int na = cells_.neighbour_cell(0, c[0] + row.da);
                const int nb = cells_.neighbour_cell(1, c[1] + row.db);
                if (na < 0 || nb < 0) {
                    continue; // beyond the end of an open axis
                }
                const int sa = cells_.neighbour_shift(0, c[0] + row.da);
                const int sb = cells_.neighbour_shift(1, c[1] + row.db);
                const std::size_t column = cells_.grid().flat(na, nb, 0);
                const bool own_row = row.da == 0 && row.db == 0;
                // Walk t = c + dc over the row, one piece per image along c.
                int t = c[2] + row.dc_lo;
                const int t_end = c[2] + row.dc_hi;
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
                        const bool own = own_row && sc == 0 && first <= c[2] && c[2] <= last;
                        const ImageShift s = scan.shift(sa, sb, sc);
                        pieces.push_back(
                            CandidateRange{begin2,
                                           end2,
                                           {s.s[0], s.s[1], s.s[2]},
                                           {s.v[0], s.v[1], s.v[2]},
                                           own,
                                           false,
                                           cluster_of(column + std::size_t(first)),
                                           cluster_of(column + std::size_t(last) + 1) - 1,
                                           0});
                    }
                }
            }
            if (wraps_) {
                // A stencil wider than the grid (a small cell): the rows come round as many
                // images of the same few atoms, which the scanner takes faster piece by piece.
                for (const CandidateRange& r : pieces) {
                    scan.ranges(begin1, end1, r.b0, r.b1,
                                ImageShift{{r.s[0], r.s[1], r.s[2]}, {r.v[0], r.v[1], r.v[2]}},
                                r.own);
                }
            } else {
                scan.cell(begin1, end1, pieces.data(), std::uint32_t(pieces.size()));
            }
        }
    }

    void describe(SearchInfo& info) const override {
        info.backend = SearchBackend::dense;
        info.cells = cells_.grid().dims();
        info.stored_cells = cells_.grid().cell_count();
    }

  private:
    // Sorts the atoms of each cell along the rows' axis (fractional c, then the caller's index:
    // the same order for any thread count), so that a row's atoms run along it and each cluster
    // of cluster_atoms of them is a thin slab of its cell. A cell of at most cluster_atoms is one
    // cluster whatever its order, and stays as binned.
    void sort_along_rows(const BinningInput& input, std::vector<std::uint32_t>& order) const {
        const auto& f = input.fractional;
        parallel_ranges(
            unit_count(), input.plan.threads, [&](std::size_t begin, std::size_t end, std::size_t) {
                for (std::size_t c = begin; c < end; ++c) {
                    if (sorted_.cell_end(c) - sorted_.cell_start(c) <= cluster_atoms) {
                        continue; // one cluster: its box is the same in any order
                    }
                    std::sort(order.begin() + sorted_.cell_start(c),
                              order.begin() + sorted_.cell_end(c),
                              [&](std::uint32_t a, std::uint32_t b) {
                                  return f[a][2] < f[b][2] || (f[a][2] == f[b][2] && a < b);
                              });
                }
            });
    }

    // The clusters of each cell (cluster_atoms or fewer consecutive atoms of the sorted order,
    // the cell's atoms cut into equal parts), the bounding box of each cluster's atoms from the
    // scanner's positions (the ones the kernel tests) and the clusters' starts.
    void build_boxes(const CandidateScanner& scan) const {
        const std::size_t cells = cells_.grid().cell_count();
        const double* x = scan.x();
        const double* y = scan.y();
        const double* z = scan.z();
        const double inf = std::numeric_limits<double>::infinity();
        first_cluster_.resize(cells + 1);
        starts_.clear();
        starts_.reserve(cells + sorted_.atom_count() / cluster_atoms + 1);
        for (std::size_t c = 0; c < cells; ++c) {
            first_cluster_[c] = std::uint32_t(starts_.size());
            const std::uint32_t begin = sorted_.cell_start(c), count = sorted_.cell_end(c) - begin;
            const std::uint32_t parts = (count + cluster_atoms - 1) / cluster_atoms;
            for (std::uint32_t k = 0; k < parts; ++k) {
                starts_.push_back(begin + count * k / parts);
            }
        }
        const std::size_t clusters = starts_.size();
        first_cluster_[cells] = std::uint32_t(clusters);
        starts_.push_back(cells > 0 ? sorted_.cell_end(cells - 1) : 0);
        boxes_.resize(6 * clusters);
        double bound = 0;
        for (std::size_t c = 0; c < clusters; ++c) {
            double lo[3] = {inf, inf, inf}, hi[3] = {-inf, -inf, -inf};
            for (std::uint32_t a = starts_[c]; a < starts_[c + 1]; ++a) {
                lo[0] = std::min(lo[0], x[a]), hi[0] = std::max(hi[0], x[a]);
                lo[1] = std::min(lo[1], y[a]), hi[1] = std::max(hi[1], y[a]);
                lo[2] = std::min(lo[2], z[a]), hi[2] = std::max(hi[2], z[a]);
            }
            for (int k = 0; k < 3; ++k) {
                boxes_[6 * c + k] = lo[k];
                boxes_[6 * c + 3 + k] = hi[k];
                bound = std::max({bound, std::abs(lo[k]), std::abs(hi[k])});
            }
        }
        bound_ = bound;
    }

    // The first cluster of a cell (the cell itself without boxes): cells [first, last] hold
    // clusters [cluster_of(first), cluster_of(last + 1) - 1].
    std::uint32_t cluster_of(std::size_t cell) const {
        return boxes_pay_ ? first_cluster_[cell] : std::uint32_t(cell);
    }

    // A stencil row as flat offsets from the home cell: cells [lo, hi] of the sorted order.
    struct InnerRow {
        std::ptrdiff_t lo, hi;
        bool own;
    };

    // Whether every row of cell c lies inside the grid (no wrap, no image shift, no open end).
    bool inside(const std::array<int, 3>& c, const std::array<int, 3>& n) const {
        for (std::size_t k = 0; k < 3; ++k) {
            if (c[k] < reach_[k] || c[k] + reach_[k] >= n[k]) {
                return false;
            }
        }
        return true;
    }

    GridNeighbourhood cells_;
    std::vector<std::uint32_t> cell_of_; // kept between builds: no fresh pages to fault in
    SortedCellList sorted_;
    std::vector<InnerRow> inner_rows_;
    std::array<int, 3> reach_{};
    bool wraps_ = false; ///< the stencil reaches round a periodic axis onto its own cells
    bool boxes_pay_ = false;
    mutable std::unique_ptr<std::once_flag> boxes_once_;
    mutable PairArray<double> boxes_;           // 6 per cluster, in huge pages (48 bytes a cluster)
    mutable std::vector<std::uint32_t> starts_; ///< of each cluster, and the end
    mutable std::vector<std::uint32_t> first_cluster_; ///< of each cell, and the count
    mutable double bound_ = 0;
};

} // namespace

std::unique_ptr<Backend> make_dense_backend() {
    return std::make_unique<DenseBackend>();
}

} // namespace tricell::detail
