// The shared part of every search (see include/tricell/neighbor_list.hpp): validation, the
// search frame and the wrap, the pair-count estimate, the choice of backend, threads with their
// ordered output (detail/ordered_output.hpp), sorting and the map of shifts back to the caller's
// lattice vectors.
#include "tricell/neighbor_list.hpp"

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <exception>
#include <limits>
#include <map>
#include <numeric>
#include <thread>

#include <Eigen/LU>

#include "backends/backend.hpp"
#include "search/registry.hpp"
#include "detail/lattice_reduction.hpp"
#include "detail/list_writer.hpp"
#include "detail/ordered_output.hpp"
#include "detail/parallel.hpp"
#include "tricell/cost_model.hpp"
#include "tricell/error.hpp"

namespace tricell {

namespace detail {

/// Everything a built search holds.
struct SearchState {
    NeighborOptions options;
    Eigen::Matrix3d h = Eigen::Matrix3d::Identity(); // of the search frame
    // Shifts in the search frame map to the caller's as S = to_caller * S' (identity unless
    // the cell was reduced).
    Eigen::Matrix3i to_caller = Eigen::Matrix3i::Identity();
    bool reduced_frame = false;
    double search_radius = 0;
    double cutoff_sq = 0; // the scan's threshold (of the largest cutoff)
    std::size_t atom_count = 0;
    double estimated_pairs = 0;
    CutoffRule rule;
    AtomTable atoms;
    // The backend of the last build, null when no pair can count (all radii zero, ...). Each
    // kind's object is kept between builds so that its buffers are reused.
    Backend* backend = nullptr;
    BackendPool pool;
};

} // namespace detail

namespace {

constexpr double pi = 3.14159265358979323846;
// The grid and stencil are built for a radius this much larger than the cutoff, so rounding
// in fractional coordinates can never push a pair just inside the cutoff out of the stencil.
constexpr double search_margin = 1e-9;

using detail::gather;
using detail::ListWriter;

} // namespace

void NeighborOptions::validate() const {
    if (!std::isfinite(cutoff)) {
        detail::fail<InvalidArgument>("cutoff must be finite (got ", cutoff, ")");
    }
    if (!radii.empty() && !species_cutoffs.empty()) {
        detail::fail<InvalidArgument>("set radii or species_cutoffs, not both");
    }
    if (variable_cutoff()) {
        if (cutoff != 0) {
            detail::fail<InvalidArgument>("cutoff must be 0 when ",
                                          radii.empty() ? "species_cutoffs" : "radii",
                                          " decide which pairs count (got ", cutoff, ")");
        }
    } else if (!(cutoff > 0)) {
        detail::fail<InvalidArgument>("cutoff must be > 0 (got ", cutoff, ")");
    }
    for (std::size_t k = 0; k < radii.size(); ++k) {
        if (!(std::isfinite(radii[k]) && radii[k] >= 0)) {
            detail::fail<InvalidArgument>("radii[", k, "] must be finite and >= 0 (got ", radii[k],
                                          ")");
        }
    }
    if (!species.empty() && species_cutoffs.empty()) {
        detail::fail<InvalidArgument>("species is set but species_cutoffs is empty");
    }
    std::map<std::pair<std::int32_t, std::int32_t>, double> seen;
    for (std::size_t k = 0; k < species_cutoffs.size(); ++k) {
        const SpeciesCutoff& e = species_cutoffs[k];
        if (!(std::isfinite(e.cutoff) && e.cutoff > 0)) {
            detail::fail<InvalidArgument>("species_cutoffs[", k, "] (species ", e.a, "-", e.b,
                                          ") must be finite and > 0 (got ", e.cutoff, ")");
        }
        const auto key = std::minmax(e.a, e.b);
        const auto [it, fresh] = seen.emplace(key, e.cutoff);
        if (!fresh && it->second != e.cutoff) {
            detail::fail<InvalidArgument>("species pair ", e.a, "-", e.b,
                                          " has two cutoffs in species_cutoffs (", it->second,
                                          " and ", e.cutoff, ")");
        }
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
    if (hash_table_size > (std::size_t(1) << 31)) {
        detail::fail<InvalidArgument>("hash_table_size must be at most 2^31 (got ", hash_table_size,
                                      ")");
    }
    if (leaf_size > (std::size_t(1) << 20)) {
        detail::fail<InvalidArgument>("leaf_size must be at most 2^20 (got ", leaf_size, ")");
    }
    if (detail::find_backend(backend) == nullptr) {
        detail::fail<InvalidArgument>("backend must be one of ", backend_choices(),
                                      " (got the value ", static_cast<int>(backend), ")");
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

// The backend for `automatic` (cost_model.hpp): direct enumeration for a few atoms in a cell
// narrower than the cutoff (choose_direct()); else the grid choose_grid_backend() picks (dense when
// the cells the cutoff asks for fit under its cap, the compact hash otherwise), unless the
// octree is cheaper by the density model (never when the grid is cheaper at every density, as the
// dense grid is on the reference machine). That model sums each structure's cost per atom u(rho)
// over the atoms, each at its local density, estimated from a sample of at most 4096 atoms
// binned in cells of at least 2 r (the two-density model's T is this sum for two densities).
SearchBackend automatic_backend(const Box& box, const std::vector<Eigen::Vector3d>& fractional,
                                const Eigen::Vector3d& lower, const Eigen::Vector3d& upper,
                                double search_radius, const NeighborOptions& options,
                                std::size_t n) {
    double min_width = std::numeric_limits<double>::infinity();
    for (int k = 0; k < 3; ++k) {
        if (box.periodic(k)) {
            min_width = std::min(min_width, box.perpendicular_widths()[k]);
        }
    }
    if (choose_direct(n, min_width, search_radius)) {
        return SearchBackend::direct;
    }
    const double h = search_radius / options.cells_per_cutoff;
    double cells = 1;
    for (int k = 0; k < 3; ++k) {
        const double span = box.periodic(k) ? 1.0 : std::max(upper[k] - lower[k], 0.0);
        cells *= std::max(1.0, std::floor(span * box.perpendicular_widths()[k] / h));
    }
    const double cap = options.max_cells != 0 ? double(options.max_cells) : 4.0 * double(n) + 64;
    const SearchBackend grid = choose_grid_backend(cells, cap);
    const OctreeCosts costs;
    if (grid_always_cheaper(grid, search_radius, costs)) {
        return grid; // at no density does the octree win: no need to look at the atoms
    }

    // Local densities of a sample: coarse cells of side >= 2 r, keys sorted, runs counted.
    std::array<double, 3> origin{}, scale{};
    std::array<std::uint64_t, 3> dims{};
    double cell_volume = box.volume();
    for (int k = 0; k < 3; ++k) {
        const std::size_t a = std::size_t(k);
        const double span = box.periodic(k) ? 1.0 : upper[k] - lower[k];
        const double width = span * box.perpendicular_widths()[k];
        dims[a] = std::uint64_t(std::clamp(std::floor(width / (2 * search_radius)), 1.0, 1e6));
        origin[a] = box.periodic(k) ? 0.0 : lower[k];
        scale[a] = span > 0 ? double(dims[a]) / span : 0.0;
        // An open axis thinner than the cutoff counts as one cutoff thick (as the pair estimate).
        cell_volume *=
            (box.periodic(k) ? 1.0
                             : std::max(span, search_radius / box.perpendicular_widths()[k])) /
            double(dims[a]);
    }
    const std::size_t samples = std::min<std::size_t>(n, 4096);
    std::vector<std::uint64_t> keys(samples);
    for (std::size_t t = 0; t < samples; ++t) {
        const Eigen::Vector3d& s = fractional[t * n / samples];
        std::uint64_t key = 0;
        for (std::size_t a = 0; a < 3; ++a) {
            // NaN when a denormal span made the scale inf and an atom sits at the origin (0 * inf,
            // search fuzzer): that atom is in cell 0.
            const double c = std::floor((s[int(a)] - origin[a]) * scale[a]);
            key = key * dims[a] +
                  std::uint64_t(std::clamp(std::isnan(c) ? 0.0 : c, 0.0, double(dims[a] - 1)));
        }
        keys[t] = key;
    }
    std::sort(keys.begin(), keys.end());
    const double weight = double(n) / double(samples);
    double grid_cost = 0, octree_cost = 0;
    for (std::size_t t = 0; t < samples;) {
        std::size_t u = t;
        while (u < samples && keys[u] == keys[t]) {
            ++u;
        }
        const double count = double(u - t);
        // The atom itself, plus the others of its cell the sample stands for.
        const double density = (1 + (count - 1) * weight) / cell_volume;
        grid_cost += count * grid_cost_per_atom(grid, density, search_radius, costs);
        octree_cost += count * octree_cost_per_atom(density, search_radius, costs);
        t = u;
    }
    // Only a clear win (30%): the per-cell estimate reads the surface cells of a dense cluster as
    // vapour, which overstates the octree's gain, and the fitted costs scatter by about 20%.
    return octree_cost < 0.7 * grid_cost ? SearchBackend::octree : grid;
}

} // namespace

NeighborSearch::NeighborSearch() = default;
NeighborSearch::~NeighborSearch() = default;
NeighborSearch::NeighborSearch(NeighborSearch&&) noexcept = default;
NeighborSearch& NeighborSearch::operator=(NeighborSearch&&) noexcept = default;

void NeighborSearch::build(const Box& caller_box, PointsView positions,
                           const NeighborOptions& options) {
    // Until this build succeeds the object holds no usable search (a failed build must not
    // leave the structure of one configuration with the atoms of another).
    std::unique_ptr<detail::SearchState> state = std::move(state_);
    options.validate();
    const std::size_t n = positions.size();
    if (n >= std::size_t(std::numeric_limits<std::int32_t>::max())) {
        detail::fail<InvalidArgument>("at most ", std::numeric_limits<std::int32_t>::max() - 1,
                                      " positions are supported (got ", n, ")");
    }
    if (n > 0 && positions.data == nullptr) {
        detail::fail<InvalidArgument>("positions: null data for ", n, " points");
    }
    // The per-atom phases of a build (checks, wrap, binning, the atom table) run on the search's
    // threads: serial, they bounded two threads well below 2x (see ordered_output.hpp). Threads
    // asked for explicitly are used from 16 atoms per thread (so that the property tests run
    // these phases on small systems), automatic ones from 16384, where a phase outweighs the
    // start of a thread.
    const std::size_t threads =
        options.threads > 0
            ? detail::threads_for(n, std::size_t(options.threads), 16)
            : detail::threads_for(n, std::max<std::size_t>(1, std::thread::hardware_concurrency()),
                                  16384);
    // One team of threads for all of them (detail/parallel.hpp: threads started per phase cost
    // as much as the phases gain on a few thousand atoms).
    const detail::TeamScope team(threads);
    detail::parallel_ranges(n, threads, [&](std::size_t begin, std::size_t end, std::size_t) {
        for (std::size_t i = begin; i < end; ++i) {
            const Eigen::Vector3d r = positions[i];
            if (!r.allFinite()) {
                detail::fail<InvalidArgument>("position ", i, " is not finite (got ", r.x(), ", ",
                                              r.y(), ", ", r.z(), ")");
            }
        }
    });
    if (!state) {
        state = std::make_unique<detail::SearchState>();
    }
    detail::SearchState& s = *state;
    s.backend = nullptr;
    s.rule.set(options, n);
    s.options = options;
    const Box box = search_frame(caller_box, options.reduce_cell, s.to_caller);
    s.reduced_frame = s.to_caller != Eigen::Matrix3i::Identity();
    s.h = box.matrix();
    s.atom_count = n;
    s.estimated_pairs = 0;
    const double cutoff = s.rule.max_cutoff();
    // At most the largest double: the margin overflowed a finite cutoff near it to inf, which
    // the grid refuses and the other backends accept (found by the search fuzzer).
    s.search_radius = std::min(cutoff * (1 + search_margin), std::numeric_limits<double>::max());

    // Wrap into the box along periodic axes, remembering the image: x = wrapped + H image.
    std::vector<Eigen::Vector3d> fractional(n);
    PairArray<std::int32_t> image(3 * n); // every entry written below
    std::vector<Eigen::Vector3d> range_lower(threads), range_upper(threads);
    detail::parallel_ranges(n, threads, [&](std::size_t begin, std::size_t end, std::size_t t) {
        // The range's bounds are kept in locals and stored once: updated in place per atom, the
        // threads' neighbouring entries shared a cache line, and this phase took 9% of a
        // two-thread search of 4096 atoms (perf), against 1% on one thread.
        Eigen::Vector3d low = Eigen::Vector3d::Zero(), high = low;
        for (std::size_t i = begin; i < end; ++i) {
            WrappedFractional w;
            try {
                w = box.wrap(box.to_fractional(Cartesian(positions[i])));
            } catch (const InvalidArgument& e) {
                detail::fail<InvalidArgument>("position ", i, ": ", e.what());
            }
            fractional[i] = w.wrapped;
            for (int k = 0; k < 3; ++k) {
                image[3 * i + std::size_t(k)] = w.image[k];
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
    Eigen::Vector3d lower = Eigen::Vector3d::Zero(), upper = Eigen::Vector3d::Zero();
    if (n > 0) {
        lower = range_lower[0];
        upper = range_upper[0];
        for (std::size_t t = 1; t < threads; ++t) {
            lower = lower.cwiseMin(range_lower[t]);
            upper = upper.cwiseMax(range_upper[t]);
        }
    }
    if (!(cutoff > 0) || n == 0) {
        s.atoms = detail::AtomTable();
        state_ = std::move(state); // no pair can count: an empty search
        return;
    }
    s.cutoff_sq = detail::strict_threshold_sq(cutoff);

    // Expected pairs for a uniform density over the region the atoms occupy (an open axis
    // counts as at least one cutoff thick). Checked before anything large is allocated.
    double volume = box.volume();
    for (int k = 0; k < 3; ++k) {
        if (!box.periodic(k)) {
            volume *= std::max(upper[k] - lower[k], cutoff / box.perpendicular_widths()[k]);
        }
    }
    const double sphere = 4.0 / 3.0 * pi * std::pow(cutoff, 3);
    s.estimated_pairs = double(n) * double(n) * sphere / volume * (options.half ? 0.5 : 1.0);
    if (std::isnan(s.estimated_pairs)) {
        s.estimated_pairs = 0; // sphere and volume both underflowed: no estimate (the sink still
                               // enforces max_pairs on the real count)
    }
    if (options.max_pairs != 0 && s.estimated_pairs > double(options.max_pairs)) {
        throw PairLimitError(detail::cat("cutoff ", cutoff, " would give about ", s.estimated_pairs,
                                         " pairs for ", n, " atoms (estimated from the density)"),
                             s.estimated_pairs, options.max_pairs);
    }

    SearchBackend kind = options.backend;
    if (kind == SearchBackend::automatic) {
        kind = automatic_backend(box, fractional, lower, upper, s.search_radius, options, n);
    }
    s.backend = &s.pool.get(kind);
    std::vector<std::uint32_t> order;
    s.backend->bin(
        detail::BinningInput{box, fractional, lower, upper, s.search_radius, options, threads},
        order);

    // Wrapped Cartesian positions, x - H image (exactly x for atoms already in the box), in the
    // backend's order.
    detail::AtomTable& atoms = s.atoms;
    atoms.x.resize(n);
    atoms.y.resize(n);
    atoms.z.resize(n);
    atoms.image.resize(3 * n);
    atoms.index = std::move(order);
    detail::parallel_ranges(n, threads, [&](std::size_t begin, std::size_t end, std::size_t) {
        for (std::size_t k = begin; k < end; ++k) {
            const std::size_t i = atoms.index[k];
            const Eigen::Vector3d img(image[3 * i], image[3 * i + 1], image[3 * i + 2]);
            const Eigen::Vector3d r = Eigen::Vector3d(positions[i]) - s.h * img;
            atoms.x[k] = r.x();
            atoms.y[k] = r.y();
            atoms.z[k] = r.z();
            for (std::size_t a = 0; a < 3; ++a) {
                atoms.image[3 * k + a] = image[3 * i + a];
            }
        }
    });
    state_ = std::move(state);
}

namespace {

// Sorts a list by i, then j, then S (counting sort by i, then each atom's pairs by (j, S)) and
// fills its CSR offsets.
void sort_pairs(NeighborList& list, std::size_t atom_count) {
    PairArray<std::uint32_t>& is = ListWriter::i(list);
    PairArray<std::uint32_t>& js = ListWriter::j(list);
    PairArray<std::int32_t>& ss = ListWriter::shifts(list);
    std::vector<std::size_t>& offsets = ListWriter::offsets(list);
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
    gather(ListWriter::distances(list), perm, 1);
    gather(ListWriter::vectors(list), perm, 3);
}

void to_caller_frame(PairArray<std::int32_t>& shifts, const Eigen::Matrix3i& t) {
    for (std::size_t k = 0; k < shifts.size(); k += 3) {
        const Eigen::Vector3i s = t * Eigen::Vector3i(shifts[k], shifts[k + 1], shifts[k + 2]);
        shifts[k] = s[0];
        shifts[k + 1] = s[1];
        shifts[k + 2] = s[2];
    }
}

} // namespace

void NeighborSearch::compute(NeighborList& out) const {
    out.clear();
    if (!state_) {
        detail::fail<InvalidArgument>("NeighborSearch::compute() needs a successful build() first");
    }
    const detail::SearchState& s = *state_;
    if (!s.backend) {
        if (s.options.sorted) {
            ListWriter::offsets(out).assign(s.atom_count + 1, 0);
        }
        return;
    }
    const Quantities& q = s.options.quantities;
    const bool keep_shifts = q.shifts || s.options.sorted; // sorting needs S
    const std::size_t units = s.backend->unit_count();
    std::size_t threads = s.options.threads > 0
                              ? std::size_t(s.options.threads)
                              : std::max<std::size_t>(1, std::thread::hardware_concurrency());
    // With automatic threads, small searches are not worth a thread.
    if (s.options.threads == 0 && (s.estimated_pairs < 20000 || units < 4 * threads)) {
        threads = 1;
    }
    threads = std::max<std::size_t>(1, std::min(threads, units));
    const detail::TeamScope team(threads);
    try {
        detail::UnitOccupancy occupancy;
        s.backend->occupancy(occupancy);
        const double sphere = 4.0 / 3.0 * pi * std::pow(s.rule.max_cutoff(), 3);
        const double box_volume = std::abs(s.h.determinant());
        const double half_factor = s.options.half ? 0.5 : 1.0;
        auto columns_of = [&](NeighborList& list) {
            return detail::PairColumns{&ListWriter::i(list), &ListWriter::j(list),
                                       keep_shifts ? &ListWriter::shifts(list) : nullptr,
                                       q.distances ? &ListWriter::distances(list) : nullptr,
                                       q.vectors ? &ListWriter::vectors(list) : nullptr};
        };
        // Room for `expected` pairs up front, at most 2^24 pairs (about 470 MB with D) per
        // list; untouched reserved memory is never resident, so the columns rarely grow.
        auto room = [](double expected) {
            return std::isfinite(expected) && expected < 1.6e7
                       ? static_cast<std::size_t>(expected * 1.1) + 1024
                       : std::size_t(1) << 24;
        };
        auto expected_in = [&](std::size_t u) {
            return half_factor *
                   expected_pairs(occupancy.atoms[u], occupancy.volume[u] * box_volume, sphere);
        };
        double total = 0;
        for (std::size_t u = 0; u < units; ++u) {
            total += expected_in(u);
        }
        // One thread writes straight into `out`. (Batches streamed out with non-temporal stores
        // were tried on one thread for large lists too, and dropped: interleaved in-process A/B,
        // random triclinic 1e5 atoms 2-9% slower than storing directly, diamond the same.)
        if (threads == 1) {
            detail::PairSink sink(columns_of(out), s.options.max_pairs, room(total));
            detail::CandidateScanner scan(s.atoms, s.h, s.cutoff_sq, s.rule, s.options.half,
                                          s.to_caller, s.reduced_frame, sink);
            s.backend->visit(0, units, scan);
            sink.finish();
        } else {
            // Batches of units of about equal work (from the occupancy moments), about
            // batch_pairs pairs each, filled in place in unit order (ordered_output.hpp), so the
            // result does not depend on `threads`. A batch's own columns (with i, j, S, d about
            // 230 KB) stay in the core's L2 until they are copied out.
            constexpr double batch_pairs = 8192;
            constexpr std::size_t max_pending = 16; // scanned batches a thread holds, at most
            std::vector<double> work(units), expected(units);
            for (std::size_t u = 0; u < units; ++u) {
                work[u] = occupancy_work(occupancy.atoms[u], occupancy.neighbours);
                expected[u] = expected_in(u);
            }
            const double wanted = std::isfinite(total) ? std::ceil(total / batch_pairs) : 1e9;
            const auto batches_wanted =
                static_cast<std::size_t>(std::clamp(wanted, 4.0 * double(threads), 1e9));
            const std::vector<std::size_t> bounds = split_work(work, batches_wanted);
            const std::size_t batches = bounds.size() - 1;
            std::vector<std::size_t> reserve(batches);
            for (std::size_t b = 0; b < batches; ++b) {
                double e = 0;
                for (std::size_t u = bounds[b]; u < bounds[b + 1]; ++u) {
                    e += expected[u];
                }
                reserve[b] = room(e);
            }
            const detail::PairColumns final_columns = columns_of(out);
            detail::OrderedOutput output(final_columns, batches,
                                         std::max(room(total), ListWriter::i(out).capacity()),
                                         s.options.max_pairs);
            // Each thread's batch columns, kept in `out` between calls so they are not faulted
            // in again.
            std::vector<NeighborList> local;
            local.swap(ListWriter::partial(out));
            local.resize(threads);
            std::vector<std::exception_ptr> errors(threads);
            std::atomic<std::size_t> next{0};
            detail::run_in_threads(threads, [&](std::size_t t) {
                try {
                    const detail::PairColumns columns = columns_of(local[t]);
                    // This thread's scanned batches not yet copied out: (batch, first pair in
                    // `columns`, pairs), in batch order; `used` pairs of `columns` are taken.
                    struct Pending {
                        std::size_t batch, start, size;
                    };
                    std::vector<Pending> pending;
                    std::size_t used = 0;
                    auto copy_placed = [&](std::size_t placed) {
                        std::size_t k = 0;
                        for (; k < pending.size() && pending[k].batch < placed; ++k) {
                            output.write(output.offset(pending[k].batch), columns, pending[k].start,
                                         pending[k].size);
                        }
                        pending.erase(pending.begin(), pending.begin() + std::ptrdiff_t(k));
                        if (pending.empty()) {
                            used = 0;
                        }
                    };
                    for (;;) {
                        const std::size_t b = next.fetch_add(1);
                        if (b >= batches || output.aborted()) {
                            break;
                        }
                        detail::PairSink sink(columns, s.options.max_pairs, reserve[b], used);
                        detail::CandidateScanner scan(s.atoms, s.h, s.cutoff_sq, s.rule,
                                                      s.options.half, s.to_caller, s.reduced_frame,
                                                      sink);
                        s.backend->visit(bounds[b], bounds[b + 1], scan);
                        pending.push_back(Pending{b, used, sink.size() - used});
                        used = sink.size();
                        copy_placed(output.finished(b, pending.back().size));
                        // Run ahead of a stalled neighbour (a descheduled thread on a loaded
                        // machine) by a bounded amount only: past that, wait for it, so the
                        // batch columns stay a few MB instead of growing towards the list.
                        if (pending.size() >= max_pending) {
                            const std::size_t placed = output.wait_placed(pending.front().batch);
                            if (placed == 0) {
                                break; // another thread failed
                            }
                            copy_placed(placed);
                        }
                    }
                    while (!pending.empty()) {
                        const std::size_t placed = output.wait_placed(pending.front().batch);
                        if (placed == 0) {
                            break; // another thread failed
                        }
                        copy_placed(placed);
                    }
                } catch (...) {
                    errors[t] = std::current_exception();
                    output.abort();
                }
            });
            for (NeighborList& list : local) {
                list.clear();
            }
            ListWriter::partial(out).swap(local);
            for (const std::exception_ptr& e : errors) {
                if (e) {
                    std::rethrow_exception(e);
                }
            }
            output.finish();
        }
        if (s.reduced_frame && keep_shifts) {
            to_caller_frame(ListWriter::shifts(out), s.to_caller);
        }
        if (s.options.sorted) {
            sort_pairs(out, s.atom_count);
        }
        if (!q.shifts) {
            ListWriter::shifts(out).clear();
        }
    } catch (...) {
        out.clear();
        throw;
    }
}

void NeighborSearch::for_each_block(void (*on_block)(void*, const PairBlock&),
                                    void* context) const {
    if (!state_) {
        detail::fail<InvalidArgument>(
            "NeighborSearch::for_each_pair() needs a successful build() first");
    }
    const detail::SearchState& s = *state_;
    if (!s.backend) {
        return;
    }
    detail::PairSink sink(on_block, context, s.to_caller, s.reduced_frame);
    detail::CandidateScanner scan(s.atoms, s.h, s.cutoff_sq, s.rule, s.options.half, s.to_caller,
                                  s.reduced_frame, sink);
    s.backend->visit(0, s.backend->unit_count(), scan);
    sink.finish();
}

SearchInfo NeighborSearch::info() const {
    SearchInfo info;
    if (!state_) {
        return info;
    }
    const detail::SearchState& s = *state_;
    info.reduced_frame = s.reduced_frame;
    info.estimated_pairs = s.estimated_pairs;
    info.search_radius = s.search_radius;
    if (s.backend) {
        s.backend->describe(info);
        info.work_units = s.backend->unit_count();
    } else {
        info.backend = s.options.backend == SearchBackend::automatic ? SearchBackend::dense
                                                                     : s.options.backend;
    }
    return info;
}

UnitWork NeighborSearch::unit_work() const {
    UnitWork work;
    if (!state_ || !state_->backend) {
        return work;
    }
    const detail::SearchState& s = *state_;
    detail::UnitOccupancy occupancy;
    s.backend->occupancy(occupancy);
    const std::size_t units = s.backend->unit_count();
    work.atoms = occupancy.atoms;
    work.estimated.resize(units);
    work.measured.resize(units);
    auto discard = [](void*, const PairBlock&) {};
    detail::PairSink sink(discard, nullptr, s.to_caller, false);
    for (std::size_t u = 0; u < units; ++u) {
        work.estimated[u] = occupancy_work(occupancy.atoms[u], occupancy.neighbours);
        detail::CandidateScanner scan(s.atoms, s.h, s.cutoff_sq, s.rule, s.options.half,
                                      s.to_caller, s.reduced_frame, sink);
        s.backend->visit(u, u + 1, scan);
        work.measured[u] = double(scan.tests());
    }
    sink.finish();
    return work;
}

double NeighborSearch::estimated_pairs() const {
    return state_ ? state_->estimated_pairs : 0;
}

std::size_t NeighborSearch::atom_count() const {
    return state_ ? state_->atom_count : 0;
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
    // Small systems are called millions of times (one cell per step of a potential): they reuse
    // one search object per thread, whose buffers (atoms, images, the backends) then stop being
    // allocated once grown. Larger ones use a fresh object, so that no large buffer outlives
    // its call.
    constexpr std::size_t reuse_below = 1024; // atoms
    // The build's and the search's phases share one team of threads (detail/parallel.hpp); it
    // starts only if a phase uses more than one thread.
    const detail::TeamScope team(
        options.threads > 0 ? std::size_t(options.threads)
                            : std::max<std::size_t>(1, std::thread::hardware_concurrency()));
    if (positions.size() < reuse_below) {
        thread_local NeighborSearch search;
        search.build(box, positions, options);
        search.compute(out);
        return;
    }
    NeighborSearch search;
    search.build(box, positions, options);
    search.compute(out);
}

} // namespace tricell
