// NeighborSearch: the search as a pipeline, each step in its own room.
//
//   build:   options.cpp  validate the options and positions
//            frame.cpp    choose the search frame and wrap the positions into it
//            policy.cpp   estimate the pairs, choose the backend and the threads
//            list_limits.cpp  refuse an estimate past max_pairs or max_bytes (before anything
//                         large is allocated)
//            backends/    bin the atoms;  frame.cpp  store them in the backend's order
//   compute: a backend names candidates, candidate_scan.hpp tests them, pair_sink.hpp stores the
//            hits; on several threads ordered_output.hpp keeps them in unit order; frame.cpp maps
//            S back to the caller's lattice vectors; output_order.cpp sorts when asked.
#include "tricell/neighbor_list.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include <Eigen/LU>

#include "policy/cost_model.hpp"
#include "detail/parallel.hpp"
#include "frame/search_frame.hpp"
#include "policy/list_limits.hpp"
#include "search/options.hpp"
#include "output/unit_ordered_batches.hpp"
#include "output/grouped_and_sorted.hpp"
#include "policy/policy.hpp"
#include "search/search_state.hpp"
#include "tricell/error.hpp"

namespace tricell {

namespace {

constexpr double pi = 3.14159265358979323846;
// The grid and stencil are built for a radius this much larger than the cutoff, so rounding
// in fractional coordinates can never push a pair just inside the cutoff out of the stencil.
constexpr double search_margin = 1e-9;

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
    const std::size_t threads = detail::build_threads(options, n);
    const detail::TeamScope team(threads); // one team for every phase below
    detail::check_positions(positions, threads);
    if (!state) {
        state = std::make_unique<detail::SearchState>();
    }
    detail::SearchState& s = *state;
    s.backend = nullptr;
    s.rule.set(options, n);
    s.options = options;
    const Box box = detail::search_frame(caller_box, options.reduce_cell, s.to_caller);
    s.reduced_frame = s.to_caller != Eigen::Matrix3i::Identity();
    s.h = box.matrix();
    s.atom_count = n;
    s.estimated_pairs = 0;
    const double cutoff = s.rule.max_cutoff();
    // At most the largest double: the margin overflows a finite cutoff near it to inf, which the
    // grid refuses and the other backends accept.
    s.search_radius = std::min(cutoff * (1 + search_margin), std::numeric_limits<double>::max());

    // A subset search scans from the query atoms only (candidate_scan.hpp); its pairs are
    // estimated as the query's share of the full list's.
    std::vector<std::uint8_t> query = detail::query_flags(options, n);
    const bool subset = !query.empty();
    const std::size_t query_size = subset ? options.query->size() : n;

    detail::WrappedPositions wrapped;
    detail::wrap_positions(box, positions, threads, wrapped);
    detail::check_caller_range(caller_box, s.to_caller, positions, wrapped.image, threads);
    if (!(cutoff > 0) || n == 0 || query_size == 0) {
        s.atoms = detail::AtomTable();
        s.query.clear();
        state_ = std::move(state); // no pair can count: an empty search
        return;
    }
    s.cutoff_sq = detail::strict_threshold_sq(cutoff);
    s.estimated_pairs = detail::estimated_system_pairs(box, n, wrapped.lower, wrapped.upper, cutoff,
                                                       options.half && !subset) *
                        (double(query_size) / double(n));
    detail::ListLimits(options, n).check_estimate(s.estimated_pairs, cutoff);

    const SearchBackend kind =
        options.backend == SearchBackend::automatic
            ? detail::automatic_backend(box, wrapped.fractional, wrapped.lower, wrapped.upper,
                                        s.search_radius, options)
            : options.backend;
    s.backend = &s.pool.get(kind);
    std::vector<std::uint32_t> order;
    s.backend->bin(detail::BinningInput{box, wrapped.fractional, wrapped.lower, wrapped.upper,
                                        s.search_radius, options, threads,
                                        detail::cell_cap(options, n)},
                   order);
    detail::fill_atom_table(s.h, positions, wrapped.image, std::move(order), threads, s.atoms);
    s.query.resize(subset ? n : 0);
    for (std::size_t k = 0; k < s.query.size(); ++k) {
        s.query[k] = query[s.atoms.index[k]];
    }
    state_ = std::move(state);
}

void NeighborSearch::compute(NeighborList& out) const {
    out.clear();
    if (!state_) {
        detail::fail<InvalidArgument>("NeighborSearch::compute() needs a successful build() first");
    }
    const detail::SearchState& s = *state_;
    PairColumns& columns = out.columns();
    if (!s.backend) {
        if (s.options.with_offsets()) {
            columns.offsets.assign(s.atom_count + 1, 0);
        }
        return;
    }
    const Quantities& q = s.options.quantities;
    const bool keep_shifts = q.shifts || s.options.sorted; // sorting needs S
    const auto columns_of = [&](PairColumns& c) {
        return detail::stored_columns(c, keep_shifts, q.distances, q.vectors);
    };
    const std::size_t units = s.backend->unit_count();
    const std::size_t threads = detail::compute_threads(s.options, s.estimated_pairs, units);
    const detail::TeamScope team(threads);
    try {
        // Expected pairs of each unit, from its occupancy (sizes the columns).
        detail::UnitOccupancy occupancy;
        s.backend->occupancy(occupancy);
        const double sphere = 4.0 / 3.0 * pi * std::pow(s.rule.max_cutoff(), 3);
        const double box_volume = std::abs(s.h.determinant());
        // A subset search: the query's share of the pairs, for both halves of a full scan.
        const double share =
            s.query.empty() ? 1.0 : double(s.options.query->size()) / double(s.atom_count);
        std::vector<double> expected(units);
        double total = 0;
        for (std::size_t u = 0; u < units; ++u) {
            expected[u] =
                (s.options.half && s.query.empty() ? 0.5 : share) *
                expected_pairs(occupancy.atoms[u], occupancy.volume[u] * box_volume, sphere);
            total += expected[u];
        }
        // Room for one claim of hits past the limits, so that a list reaching them is refused
        // there, not by a growth it would not need.
        const detail::ListLimits limits(s.options, s.atom_count);
        const std::size_t room = detail::pair_room(
            total, limits.pairs() == 0 ? 0 : limits.pairs() + detail::PairSink::block_size);
        if (threads == 1) {
            detail::PairSink sink(columns_of(columns), limits, room);
            detail::CandidateScanner scan = s.scanner(sink);
            s.backend->visit(0, units, scan);
            sink.finish();
        } else {
            std::vector<double> work(units);
            const double neighbours = s.backend->neighbours();
            for (std::size_t u = 0; u < units; ++u) {
                work[u] = occupancy_work(occupancy.atoms[u], neighbours);
            }
            const detail::BatchPlan plan = detail::plan_batches(work, expected, threads);
            detail::ordered_search(columns_of(columns), plan, std::max(room, columns.i.capacity()),
                                   limits, threads, out.thread_columns(), columns_of,
                                   [&](std::size_t b, detail::PairSink& sink) {
                                       detail::CandidateScanner scan = s.scanner(sink);
                                       s.backend->visit(plan.bounds[b], plan.bounds[b + 1], scan);
                                   });
        }
        if (s.reduced_frame && keep_shifts) {
            detail::to_caller_frame(columns.shifts, s.to_caller);
        }
        if (s.options.sorted) {
            detail::sort_pairs(columns, s.atom_count);
        } else if (s.options.grouped) {
            detail::group_pairs(columns, s.atom_count, out.order_scratch());
        }
        if (!q.shifts) {
            columns.shifts.clear();
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
    detail::CandidateScanner scan = s.scanner(sink);
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
    const double neighbours = s.backend->neighbours();
    for (std::size_t u = 0; u < units; ++u) {
        work.estimated[u] = occupancy_work(occupancy.atoms[u], neighbours);
        detail::CandidateScanner scan = s.scanner(sink);
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
    // The build's and the search's phases share one team of threads; it starts only if a phase
    // uses more than one thread.
    const detail::TeamScope team(detail::call_threads(options));
    if (positions.size() < detail::reuse_search_below) {
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
