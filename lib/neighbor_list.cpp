#include "tricell/neighbor_list.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

#include "tricell/error.hpp"

namespace tricell {

namespace {

constexpr double pi = 3.14159265358979323846;
// The grid and stencil are built for a radius this much larger than the cutoff, so rounding
// in fractional coordinates can never push a pair just inside the cutoff out of the stencil.
constexpr double search_margin = 1e-9;

// Reorders v in place so that v[k] becomes old v[perm[k]], for `width` values per pair.
template <class T>
void gather(std::vector<T> &v, const std::vector<std::size_t> &perm, std::size_t width) {
    if (v.empty()) {
        return;
    }
    std::vector<T> out(v.size());
    for (std::size_t k = 0; k < perm.size(); ++k) {
        for (std::size_t w = 0; w < width; ++w) {
            out[width * k + w] = v[width * perm[k] + w];
        }
    }
    v.swap(out);
}

} // namespace

void NeighborOptions::validate() const {
    if (!std::isfinite(cutoff)) {
        detail::fail<InvalidArgument>("cutoff must be finite (got ", cutoff, ")");
    }
    if (!(cutoff > 0)) {
        detail::fail<InvalidArgument>("cutoff must be > 0 (got ", cutoff, ")");
    }
    if (!(std::isfinite(cells_per_cutoff) && cells_per_cutoff >= 1)) {
        detail::fail<InvalidArgument>("cells_per_cutoff must be >= 1 (got ", cells_per_cutoff, ")");
    }
}

void NeighborList::clear() {
    i_.clear();
    j_.clear();
    shifts_.clear();
    distances_.clear();
    vectors_.clear();
    offsets_.clear();
}

void NeighborSearch::build(const Box &box, PointsView positions, const NeighborOptions &options) {
    options.validate();
    const std::size_t n = positions.size();
    if (n >= std::size_t(std::numeric_limits<std::int32_t>::max())) {
        detail::fail<InvalidArgument>("at most ", std::numeric_limits<std::int32_t>::max() - 1,
                                      " positions are supported (got ", n, ")");
    }
    if (n > 0 && positions.data == nullptr) {
        detail::fail<InvalidArgument>("positions: null data for ", n, " points");
    }
    for (std::size_t i = 0; i < n; ++i) {
        const Eigen::Vector3d r = positions[i];
        if (!r.allFinite()) {
            detail::fail<InvalidArgument>("position ", i, " is not finite (got ", r.x(), ", ",
                                          r.y(), ", ", r.z(), ")");
        }
    }
    options_ = options;
    h_ = box.matrix();
    cutoff_sq_ = options.cutoff * options.cutoff;
    atom_count_ = n;
    const double search_radius = options.cutoff * (1 + search_margin);

    // Wrap into the box along periodic axes, remembering the image: x = wrapped + H image.
    std::vector<Eigen::Vector3d> fractional(n);
    image_.assign(3 * n, 0);
    Eigen::Vector3d lower = Eigen::Vector3d::Zero(), upper = Eigen::Vector3d::Zero();
    for (std::size_t i = 0; i < n; ++i) {
        WrappedFractional w;
        try {
            w = box.wrap(box.to_fractional(Cartesian(positions[i])));
        } catch (const InvalidArgument &e) {
            detail::fail<InvalidArgument>("position ", i, ": ", e.what());
        }
        fractional[i] = w.wrapped;
        for (int k = 0; k < 3; ++k) {
            image_[3 * i + std::size_t(k)] = w.image[k];
        }
        if (i == 0) {
            lower = upper = w.wrapped;
        } else {
            lower = lower.cwiseMin(w.wrapped);
            upper = upper.cwiseMax(w.wrapped);
        }
    }

    GridOptions grid_options;
    grid_options.search_radius = search_radius;
    grid_options.cells_per_cutoff = options.cells_per_cutoff;
    grid_options.max_cells = options.max_cells != 0 ? options.max_cells : 4 * n + 64;
    grid_ = CellGrid(box, grid_options, lower, upper);

    // Expected pairs for a uniform density over the region the atoms occupy (an open axis
    // counts as at least one cutoff thick). Checked before anything large is allocated.
    double volume = box.volume();
    for (int k = 0; k < 3; ++k) {
        if (!box.periodic(k)) {
            volume *= std::max(upper[k] - lower[k], options.cutoff / box.perpendicular_widths()[k]);
        }
    }
    const double sphere = 4.0 / 3.0 * pi * std::pow(options.cutoff, 3);
    estimated_pairs_ = double(n) * double(n) * sphere / volume * (options.half ? 0.5 : 1.0);
    if (options.max_pairs != 0 && estimated_pairs_ > double(options.max_pairs)) {
        detail::fail<InvalidArgument>(
            "cutoff ", options.cutoff, " would give about ", estimated_pairs_, " pairs for ", n,
            " atoms (estimated from the density), more than max_pairs = ", options.max_pairs,
            "; raise NeighborOptions::max_pairs to allow it");
    }

    stencil_ = options.half ? Stencil::half(grid_, box, search_radius)
                            : Stencil::full(grid_, box, search_radius);

    // Neighbour-cell tables per axis.
    for (int k = 0; k < 3; ++k) {
        const int cells = grid_.dims()[std::size_t(k)];
        const int reach = grid_.reach()[std::size_t(k)];
        neighbor_cell_[k].resize(std::size_t(cells + 2 * reach));
        neighbor_shift_[k].resize(std::size_t(cells + 2 * reach));
        for (int t = -reach; t < cells + reach; ++t) {
            const std::size_t slot = std::size_t(t + reach);
            if (box.periodic(k)) {
                neighbor_cell_[k][slot] = floor_mod(t, cells);
                neighbor_shift_[k][slot] = floor_div(t, cells);
            } else {
                neighbor_cell_[k][slot] = (t >= 0 && t < cells) ? t : -1;
                neighbor_shift_[k][slot] = 0;
            }
        }
    }

    std::vector<std::uint32_t> cell_of(n);
    for (std::size_t i = 0; i < n; ++i) {
        cell_of[i] = static_cast<std::uint32_t>(grid_.cell_of(fractional[i]));
    }
    // Wrapped Cartesian positions, x - H image (exactly x for atoms already in the box).
    wrapped_.resize(3 * n);
    for (std::size_t i = 0; i < n; ++i) {
        const Eigen::Vector3d img(image_[3 * i], image_[3 * i + 1], image_[3 * i + 2]);
        const Eigen::Vector3d r = Eigen::Vector3d(positions[i]) - h_ * img;
        wrapped_[3 * i] = r.x();
        wrapped_[3 * i + 1] = r.y();
        wrapped_[3 * i + 2] = r.z();
    }

    if (options.cell_list == CellListKind::sorted) {
        sorted_.build(cell_of, grid_.cell_count());
        x_.resize(n);
        y_.resize(n);
        z_.resize(n);
        sorted_image_.resize(3 * n);
        for (std::size_t k = 0; k < n; ++k) {
            const std::size_t i = sorted_.original(k);
            x_[k] = wrapped_[3 * i];
            y_[k] = wrapped_[3 * i + 1];
            z_[k] = wrapped_[3 * i + 2];
            for (std::size_t a = 0; a < 3; ++a) {
                sorted_image_[3 * k + a] = image_[3 * i + a];
            }
        }
        linked_ = LinkedCellList();
    } else {
        linked_.build(cell_of, grid_.cell_count());
        sorted_ = SortedCellList();
    }
}

void NeighborSearch::compute(NeighborList &out) const {
    out.clear();
    const Quantities &q = options_.quantities;
    const bool keep_shifts = q.shifts || options_.sorted; // sorting needs S
    const std::size_t limit = options_.max_pairs;
    try {
        const double expected = std::min(estimated_pairs_ * 1.05 + 16, 1e8);
        const std::size_t reserve = static_cast<std::size_t>(expected);
        out.i_.reserve(reserve);
        out.j_.reserve(reserve);
        if (keep_shifts) {
            out.shifts_.reserve(3 * reserve);
        }
        if (q.distances) {
            out.distances_.reserve(reserve);
        }
        if (q.vectors) {
            out.vectors_.reserve(3 * reserve);
        }
        traverse([&](std::uint32_t i, std::uint32_t j, int sa, int sb, int sc, double dx, double dy,
                     double dz, double d_sq) {
            if (limit != 0 && out.i_.size() >= limit) {
                detail::fail<InvalidArgument>(
                    "the neighbour list has more than max_pairs = ", limit,
                    " pairs; raise NeighborOptions::max_pairs to "
                    "allow it");
            }
            out.i_.push_back(i);
            out.j_.push_back(j);
            if (keep_shifts) {
                out.shifts_.insert(out.shifts_.end(), {sa, sb, sc});
            }
            if (q.distances) {
                out.distances_.push_back(std::sqrt(d_sq));
            }
            if (q.vectors) {
                out.vectors_.insert(out.vectors_.end(), {dx, dy, dz});
            }
        });
        if (options_.sorted) {
            // Counting sort by i, then each atom's pairs by (j, S).
            const std::size_t pairs = out.i_.size();
            out.offsets_.assign(atom_count_ + 1, 0);
            for (const std::uint32_t i : out.i_) {
                ++out.offsets_[i + 1];
            }
            std::partial_sum(out.offsets_.begin(), out.offsets_.end(), out.offsets_.begin());
            std::vector<std::size_t> perm(pairs);
            std::vector<std::size_t> cursor(out.offsets_.begin(), out.offsets_.end() - 1);
            for (std::size_t k = 0; k < pairs; ++k) {
                perm[cursor[out.i_[k]]++] = k;
            }
            const std::vector<std::uint32_t> &js = out.j_;
            const std::vector<std::int32_t> &ss = out.shifts_;
            auto before = [&](std::size_t l, std::size_t r) {
                if (js[l] != js[r]) {
                    return js[l] < js[r];
                }
                for (std::size_t a = 0; a < 3; ++a) {
                    if (ss[3 * l + a] != ss[3 * r + a]) {
                        return ss[3 * l + a] < ss[3 * r + a];
                    }
                }
                return false;
            };
            for (std::size_t i = 0; i < atom_count_; ++i) {
                std::sort(perm.begin() + std::ptrdiff_t(out.offsets_[i]),
                          perm.begin() + std::ptrdiff_t(out.offsets_[i + 1]), before);
            }
            gather(out.i_, perm, 1);
            gather(out.j_, perm, 1);
            gather(out.shifts_, perm, 3);
            gather(out.distances_, perm, 1);
            gather(out.vectors_, perm, 3);
        }
        if (!q.shifts) {
            out.shifts_.clear();
        }
    } catch (...) {
        out.clear();
        throw;
    }
}

NeighborList compute_neighbors(const Box &box, PointsView positions,
                               const NeighborOptions &options) {
    NeighborList out;
    compute_neighbors(box, positions, options, out);
    return out;
}

void compute_neighbors(const Box &box, PointsView positions, const NeighborOptions &options,
                       NeighborList &out) {
    out.clear();
    NeighborSearch search;
    search.build(box, positions, options);
    search.compute(out);
}

} // namespace tricell
