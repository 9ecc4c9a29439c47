#include "tricell/neighbor_list.hpp"

#include <algorithm>
#include <cmath>
#include <exception>
#include <limits>
#include <numeric>
#include <thread>

#include "detail/lattice_reduction.hpp"
#include "tricell/error.hpp"

namespace tricell {

namespace {

constexpr double pi = 3.14159265358979323846;
// The grid and stencil are built for a radius this much larger than the cutoff, so rounding
// in fractional coordinates can never push a pair just inside the cutoff out of the stencil.
constexpr double search_margin = 1e-9;

// Reorders v in place so that v[k] becomes old v[perm[k]], for `width` values per pair.
template <class T>
void gather(PairArray<T>& v, const std::vector<std::size_t>& perm, std::size_t width) {
    if (v.empty()) {
        return;
    }
    PairArray<T> out(v.size());
    for (std::size_t k = 0; k < perm.size(); ++k) {
        for (std::size_t w = 0; w < width; ++w) {
            out[width * k + w] = v[width * perm[k] + w];
        }
    }
    v.swap(out);
}

// Runs task(0) .. task(count - 1), each on its own thread (task 0 on the calling thread).
template <class Task> void run_in_threads(std::size_t count, Task&& task) {
    std::vector<std::thread> workers;
    workers.reserve(count > 0 ? count - 1 : 0);
    try {
        for (std::size_t t = 1; t < count; ++t) {
            workers.emplace_back([&task, t] { task(t); });
        }
    } catch (...) { // could not start a thread: finish the started ones, then report
        for (std::thread& w : workers) {
            w.join();
        }
        throw;
    }
    if (count > 0) {
        task(0);
    }
    for (std::thread& w : workers) {
        w.join();
    }
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
    if (threads < 0 || threads > 1024) {
        detail::fail<InvalidArgument>("threads must be in [0, 1024] (got ", threads, ")");
    }
    if (max_cells > (std::size_t(1) << 31)) {
        detail::fail<InvalidArgument>("max_cells must be at most 2^31 (got ", max_cells, ")");
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

namespace {

// The box the search runs in: the caller's box, or, when its periodic vectors are strongly
// skewed, the reduced cell spanning the same lattice (wider perpendicular widths, so fewer and
// rounder cells). Shifts found in the reduced frame map back with S = transform * S'.
Box search_frame(const Box& box, bool allow_reduction, Eigen::Matrix3i& transform) {
    transform.setIdentity();
    if (!allow_reduction || !box.periodicity().any()) {
        return box;
    }
    const detail::ReducedCell reduced = detail::reduce_cell(box.matrix(), box.periodicity().axes);
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
    transform = reduced.transform;
    return candidate;
}

} // namespace

void NeighborSearch::build(const Box& caller_box, PointsView positions,
                           const NeighborOptions& options) {
    // Until this build succeeds the object holds no usable search (a failed build must not
    // leave a grid of one configuration with the cell lists of another).
    built_ = false;
    sorted_ = SortedCellList();
    linked_ = LinkedCellList();
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
    const Box box = search_frame(caller_box, options.reduce_cell, to_caller_);
    reduced_frame_ = to_caller_ != Eigen::Matrix3i::Identity();
    h_ = box.matrix();
    cutoff_sq_ = detail::strict_threshold_sq(options.cutoff);
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
        } catch (const InvalidArgument& e) {
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

    // Exact pruning solves a small quadratic problem per boundary offset (~1000 instructions);
    // worth it only when an offset leads to more distance tests than that, about N^2 / C / 5.
    const bool exact_pruning = double(n) * double(n) / double(grid_.cell_count()) > 200;
    stencil_ = options.half ? Stencil::half(grid_, box, search_radius, exact_pruning)
                            : Stencil::full(grid_, box, search_radius, exact_pruning);
    // Rows of the stencil: for each (da, db), the hull of its dc (a superset of the kept
    // offsets is always correct; in practice the kept dc already form an interval).
    rows_.clear();
    for (const CellOffset& d : stencil_.offsets()) {
        auto row = std::find_if(rows_.begin(), rows_.end(),
                                [&](const StencilRow& r) { return r.da == d[0] && r.db == d[1]; });
        if (row == rows_.end()) {
            rows_.push_back(StencilRow{d[0], d[1], d[2], d[2]});
        } else {
            row->dc_lo = std::min(row->dc_lo, d[2]);
            row->dc_hi = std::max(row->dc_hi, d[2]);
        }
    }

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
    built_ = true;
}

namespace {

// Appends pairs to the arrays of a NeighborList through raw pointers, growing them
// geometrically (a push_back per field would re-check capacity five times per pair). Refuses to
// grow past `limit` pairs (0: no limit).
class PairSink {
  public:
    PairSink(PairArray<std::uint32_t>& i, PairArray<std::uint32_t>& j,
             PairArray<std::int32_t>* shifts, PairArray<double>* distances,
             PairArray<double>* vectors, std::size_t limit, std::size_t initial)
        : i_(i), j_(j), shifts_(shifts), distances_(distances), vectors_(vectors), limit_(limit) {
        resize(limit_ != 0 ? std::min(initial, limit_) : initial);
    }

    void add(std::uint32_t i, std::uint32_t j, int sa, int sb, int sc, double dx, double dy,
             double dz, double d_sq) {
        if (size_ == capacity_) {
            grow();
        }
        pi_[size_] = i;
        pj_[size_] = j;
        if (ps_ != nullptr) {
            ps_[3 * size_] = sa;
            ps_[3 * size_ + 1] = sb;
            ps_[3 * size_ + 2] = sc;
        }
        if (pd_ != nullptr) {
            pd_[size_] = std::sqrt(d_sq);
        }
        if (pv_ != nullptr) {
            pv_[3 * size_] = dx;
            pv_[3 * size_ + 1] = dy;
            pv_[3 * size_ + 2] = dz;
        }
        ++size_;
    }

    std::size_t size() const { return size_; }
    /// Trims the arrays to the pairs actually added.
    void finish() { resize(size_); }

  private:
    void grow() {
        if (limit_ != 0 && capacity_ >= limit_) {
            detail::fail<InvalidArgument>("the neighbour list has more than max_pairs = ", limit_,
                                          " pairs; raise NeighborOptions::max_pairs to allow it");
        }
        std::size_t next = std::max<std::size_t>(1024, capacity_ * 2);
        if (limit_ != 0) {
            next = std::min(next, limit_);
        }
        resize(next);
    }

    void resize(std::size_t capacity) {
        capacity_ = capacity;
        i_.resize(capacity);
        j_.resize(capacity);
        pi_ = i_.data();
        pj_ = j_.data();
        if (shifts_ != nullptr) {
            shifts_->resize(3 * capacity);
            ps_ = shifts_->data();
        }
        if (distances_ != nullptr) {
            distances_->resize(capacity);
            pd_ = distances_->data();
        }
        if (vectors_ != nullptr) {
            vectors_->resize(3 * capacity);
            pv_ = vectors_->data();
        }
    }

    PairArray<std::uint32_t>& i_;
    PairArray<std::uint32_t>& j_;
    PairArray<std::int32_t>* shifts_;
    PairArray<double>* distances_;
    PairArray<double>* vectors_;
    std::uint32_t* pi_ = nullptr;
    std::uint32_t* pj_ = nullptr;
    std::int32_t* ps_ = nullptr;
    double* pd_ = nullptr;
    double* pv_ = nullptr;
    std::size_t size_ = 0, capacity_ = 0, limit_ = 0;
};

// Sorts a list by i, then j, then S (counting sort by i, then each atom's pairs by (j, S)) and
// fills its CSR offsets.
void sort_pairs(PairArray<std::uint32_t>& is, PairArray<std::uint32_t>& js,
                PairArray<std::int32_t>& ss, PairArray<double>& ds, PairArray<double>& vs,
                std::vector<std::size_t>& offsets, std::size_t atom_count) {
    const std::size_t pairs = is.size();
    offsets.assign(atom_count + 1, 0);
    for (const std::uint32_t i : is) {
        ++offsets[i + 1];
    }
    std::partial_sum(offsets.begin(), offsets.end(), offsets.begin());
    std::vector<std::size_t> perm(pairs);
    std::vector<std::size_t> cursor(offsets.begin(), offsets.end() - 1);
    for (std::size_t k = 0; k < pairs; ++k) {
        perm[cursor[is[k]]++] = k;
    }
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
    for (std::size_t i = 0; i < atom_count; ++i) {
        std::sort(perm.begin() + std::ptrdiff_t(offsets[i]),
                  perm.begin() + std::ptrdiff_t(offsets[i + 1]), before);
    }
    gather(is, perm, 1);
    gather(js, perm, 1);
    gather(ss, perm, 3);
    gather(ds, perm, 1);
    gather(vs, perm, 3);
}

} // namespace

std::vector<double> NeighborSearch::cell_costs() const {
    const std::size_t cells = grid_.cell_count();
    std::vector<double> cost(cells, 0.0);
    if (options_.cell_list == CellListKind::sorted) {
        for (std::size_t c = 0; c < cells; ++c) {
            const double atoms = sorted_.cell_end(c) - sorted_.cell_start(c);
            if (atoms == 0) {
                continue;
            }
            double candidates = 0;
            for_each_row_piece(c, [&](std::uint32_t begin, std::uint32_t end, bool, int, int, int) {
                candidates += end - begin;
            });
            cost[c] = atoms * (candidates + 1);
        }
    } else {
        for (std::size_t c = 0; c < cells; ++c) {
            for (auto a = linked_.head(c); a != LinkedCellList::end; a = linked_.next(a)) {
                cost[c] += 1;
            }
        }
    }
    return cost;
}

void NeighborSearch::compute(NeighborList& out) const {
    out.clear();
    if (!built_) {
        detail::fail<InvalidArgument>("NeighborSearch::compute() needs a successful build() first");
    }
    const Quantities& q = options_.quantities;
    const bool keep_shifts = q.shifts || options_.sorted; // sorting needs S
    const std::size_t cells = grid_.cell_count();
    std::size_t threads = options_.threads > 0
                              ? std::size_t(options_.threads)
                              : std::max<std::size_t>(1, std::thread::hardware_concurrency());
    // With automatic threads, small searches are not worth a thread.
    if (options_.threads == 0 && (estimated_pairs_ < 20000 || cells < 4 * threads)) {
        threads = 1;
    }
    threads = std::min(threads, cells);
    try {
        // Contiguous chunks of cells of about equal cost; chunk t goes to thread t and the
        // chunks are concatenated in cell order, so the result does not depend on `threads`.
        std::vector<std::size_t> bounds{0};
        if (threads > 1) {
            const std::vector<double> cost = cell_costs();
            const double total = std::accumulate(cost.begin(), cost.end(), 0.0);
            double running = 0;
            for (std::size_t c = 0; c < cells && bounds.size() < threads; ++c) {
                running += cost[c];
                if (running >= total * double(bounds.size()) / double(threads)) {
                    bounds.push_back(c + 1);
                }
            }
        }
        bounds.push_back(cells);
        const std::size_t chunks = bounds.size() - 1;

        // Chunk 0 writes straight into `out`, the others into their own lists.
        std::vector<NeighborList> partial;
        partial.swap(out.partial_);
        partial.resize(chunks - 1);
        std::vector<std::size_t> sizes(chunks, 0);
        std::vector<std::exception_ptr> errors(chunks);
        const double share = std::min(estimated_pairs_ * 1.05 + 16, 1e8) / double(chunks);
        auto run_chunk = [&](std::size_t t) {
            try {
                NeighborList& list = t == 0 ? out : partial[t - 1];
                PairSink sink(list.i_, list.j_, keep_shifts ? &list.shifts_ : nullptr,
                              q.distances ? &list.distances_ : nullptr,
                              q.vectors ? &list.vectors_ : nullptr, options_.max_pairs,
                              static_cast<std::size_t>(share));
                traverse([&](std::uint32_t i, std::uint32_t j, int sa, int sb, int sc, double dx,
                             double dy, double dz,
                             double d_sq) { sink.add(i, j, sa, sb, sc, dx, dy, dz, d_sq); },
                         bounds[t], bounds[t + 1]);
                sink.finish();
                sizes[t] = sink.size();
            } catch (...) {
                errors[t] = std::current_exception();
            }
        };
        run_in_threads(chunks, run_chunk);
        for (const std::exception_ptr& e : errors) {
            if (e) {
                std::rethrow_exception(e);
            }
        }
        if (chunks > 1) {
            const std::size_t total = std::accumulate(sizes.begin(), sizes.end(), std::size_t(0));
            if (options_.max_pairs != 0 && total > options_.max_pairs) {
                detail::fail<InvalidArgument>(
                    "the neighbour list has more than max_pairs = ", options_.max_pairs,
                    " pairs; raise NeighborOptions::max_pairs to allow it");
            }
            append_in_order(out, partial, sizes, keep_shifts, q.distances, q.vectors);
        }
        for (NeighborList& list : partial) {
            list.clear();
        }
        out.partial_.swap(partial);
        if (reduced_frame_ && keep_shifts) {
            to_caller_frame(out.shifts_);
        }
        if (options_.sorted) {
            sort_pairs(out.i_, out.j_, out.shifts_, out.distances_, out.vectors_, out.offsets_,
                       atom_count_);
        }
        if (!q.shifts) {
            out.shifts_.clear();
        }
    } catch (...) {
        out.clear();
        throw;
    }
}

void NeighborSearch::append_in_order(NeighborList& out, std::vector<NeighborList>& partial,
                                     const std::vector<std::size_t>& sizes, bool shifts,
                                     bool distances, bool vectors) {
    std::vector<std::size_t> offset(sizes.size(), 0);
    for (std::size_t t = 1; t < sizes.size(); ++t) {
        offset[t] = offset[t - 1] + sizes[t - 1];
    }
    const std::size_t total = offset.back() + sizes.back();
    out.i_.resize(total);
    out.j_.resize(total);
    if (shifts) {
        out.shifts_.resize(3 * total);
    }
    if (distances) {
        out.distances_.resize(total);
    }
    if (vectors) {
        out.vectors_.resize(3 * total);
    }
    // Each partial list is copied to its place by its own thread.
    run_in_threads(sizes.size() - 1, [&](std::size_t k) {
        const NeighborList& from = partial[k];
        const std::size_t at = offset[k + 1];
        std::copy(from.i_.begin(), from.i_.end(), out.i_.begin() + std::ptrdiff_t(at));
        std::copy(from.j_.begin(), from.j_.end(), out.j_.begin() + std::ptrdiff_t(at));
        std::copy(from.shifts_.begin(), from.shifts_.end(),
                  out.shifts_.begin() + std::ptrdiff_t(3 * at));
        std::copy(from.distances_.begin(), from.distances_.end(),
                  out.distances_.begin() + std::ptrdiff_t(at));
        std::copy(from.vectors_.begin(), from.vectors_.end(),
                  out.vectors_.begin() + std::ptrdiff_t(3 * at));
    });
}

void NeighborSearch::to_caller_frame(PairArray<std::int32_t>& shifts) const {
    const Eigen::Matrix3i& t = to_caller_;
    for (std::size_t k = 0; k < shifts.size(); k += 3) {
        const Eigen::Vector3i s = t * Eigen::Vector3i(shifts[k], shifts[k + 1], shifts[k + 2]);
        shifts[k] = s[0];
        shifts[k + 1] = s[1];
        shifts[k + 2] = s[2];
    }
}

NeighborList compute_neighbors(const Box& box, PointsView positions,
                               const NeighborOptions& options) {
    NeighborList out;
    compute_neighbors(box, positions, options, out);
    return out;
}

void compute_neighbors(const Box& box, PointsView positions, const NeighborOptions& options,
                       NeighborList& out) {
    out.clear();
    NeighborSearch search;
    search.build(box, positions, options);
    search.compute(out);
}

} // namespace tricell
