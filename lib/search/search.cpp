// NeighborSearch: the search as a pipeline, each step in its own room.
//
//   build:   search/options.cpp   validate the options and positions
//            frame/               choose the search frame and wrap the positions into it
//            policy/              plan the build: threads, estimated pairs, backend, cell cap;
//                                 refuse an estimate past max_pairs or max_bytes (before anything
//                                 large is allocated)
//            backends/            bin the atoms
//            scan/atom_table.cpp  store them in the backend's order
//   compute: policy/              plan the compute: threads, room, batches
//            backends/ + scan/    a backend names candidates, the scanner tests them, the sink
//                                 stores the hits (on several threads in batches written in unit
//                                 order, output/unit_ordered_batches.hpp)
//            frame/               map S back to the caller's lattice vectors
//            output/              group or sort when asked (output/grouped_and_sorted.cpp), keep
//                                 the nearest within the cutoff (output/nearest_within.cpp)
#include "tricell/neighbor_list.hpp"

#include <algorithm>
#include <limits>

#include "detail/parallel.hpp"
#include "frame/wrap.hpp"
#include "output/grouped_and_sorted.hpp"
#include "output/nearest_within.hpp"
#include "output/unit_ordered_batches.hpp"
#include "policy/cost_model.hpp"
#include "policy/list_limits.hpp"
#include "policy/policy.hpp"
#include "search/list_access.hpp"
#include "search/options.hpp"
#include "search/search_state.hpp"
#include "tricell/error.hpp"

namespace tricell {

namespace {

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
    const std::size_t threads = detail::build_threads(options, positions.size());
    const detail::TeamScope team(threads); // one team for every phase below
    if (!state) {
        state = std::make_unique<detail::SearchState>();
    }
    state->options = options;
    detail::build_search(*state, caller_box, positions, threads);
    state_ = std::move(state);
}

void NeighborSearch::compute(NeighborList& out) const {
    out.clear();
    if (!state_) {
        detail::fail<InvalidArgument>("NeighborSearch::compute() needs a successful build() first");
    }
    detail::compute_list(*state_, out);
}

namespace detail {

void build_search(SearchState& s, const Box& caller_box, PointsView positions, std::size_t threads,
                  bool rule_set) {
    const NeighborOptions& options = s.options;
    const std::size_t n = positions.size();
    s.backend = nullptr;
    check_positions(positions, threads);
    if (!rule_set) {
        s.rule.set(options, n);
    }
    s.frame = SearchFrame(caller_box, options.reduce_cell);
    s.atom_count = n;
    s.estimated_pairs = 0;
    s.most_pairs = 0;
    s.mirrored = false;
    const double cutoff = s.rule.max_cutoff();
    // At most the largest double: the margin overflows a finite cutoff near it to inf, which the
    // grid refuses and the other backends accept.
    s.search_radius = std::min(cutoff * (1 + search_margin), std::numeric_limits<double>::max());
    // A subset search scans from the query atoms only (scan/subset_scan.hpp).
    const std::vector<std::uint8_t> query = query_flags(options, n);
    s.query_atoms = query.empty() ? 0 : options.query->size();

    WrappedPositions& wrapped = s.wrapped;
    wrap_positions(s.frame, positions, threads, wrapped);
    if (!(cutoff > 0) || n == 0 || (options.query && options.query->empty())) {
        s.atoms = AtomTable();
        s.wrapped = WrappedPositions();
        return; // no pair can count: an empty search
    }
    const BuildPlan plan = plan_build(options, s.frame.box(), wrapped, cutoff, s.search_radius,
                                      query.empty() ? n : s.query_atoms);
    s.estimated_pairs = plan.estimated_pairs;
    s.most_pairs = plan.most_pairs;
    s.mirrored = plan.mirrored;
    ListLimits(options, n).check_estimate(s.estimated_pairs, cutoff);

    Backend* backend = &s.pool.get(plan.backend);
    std::vector<std::uint32_t>& order = s.order;
    backend->bin(BinningInput{s.frame.box(), wrapped.fractional, wrapped.lower, wrapped.upper,
                              s.search_radius, options, plan},
                 order);
    fill_atom_table(s.frame.box().matrix(), positions, wrapped, order, query, threads, s.atoms);
    s.backend = backend;
    if (n >= reuse_search_below) {
        s.wrapped = WrappedPositions(); // a large system's are not worth keeping
    }
}

void compute_list(const SearchState& s, NeighborList& out) {
    PairColumns& columns = ListAccess::columns(out);
    if (!s.backend) {
        if (s.options.with_offsets()) {
            columns.offsets.assign(s.atom_count + 1, 0);
        }
        return;
    }
    const Quantities& q = s.options.quantities;
    const bool nearest = s.options.max_neighbors != 0;
    const bool keep_shifts = q.shifts || s.options.sorted || nearest; // sorting and ranking need S
    const bool keep_distances = q.distances || nearest;               // ranking needs d
    const auto columns_of = [&](PairColumns& c) {
        return stored_columns(c, keep_shifts, keep_distances, q.vectors);
    };
    const ListLimits limits(s.options, s.atom_count);
    ComputeInput input;
    input.estimated_pairs = s.estimated_pairs;
    input.most_pairs = s.most_pairs;
    input.box_volume = s.frame.box().volume();
    input.max_cutoff = s.rule.max_cutoff();
    input.atoms = s.atom_count;
    input.query_atoms = s.query_atoms;
    s.backend->occupancy(input.occupancy);
    input.neighbours = [&] { return s.backend->neighbours(); };
    input.claim = PairSink::max_claim;
    const ComputePlan plan = plan_compute(s.options, input, limits);
    const TeamScope team(plan.threads);
    try {
        if (plan.threads == 1) {
            PairSink sink(columns_of(columns), limits, plan.room);
            CandidateScanner scan = s.scanner(sink);
            s.backend->visit(0, s.backend->unit_count(), scan);
            sink.finish();
        } else {
            const BatchPlan& batches = plan.batches;
            write_in_unit_order(
                columns_of(columns), batches, std::max(plan.room, columns.i.capacity()), limits,
                plan.threads, ListAccess::thread_columns(out), columns_of,
                [&](std::size_t b, PairSink& sink) {
                    CandidateScanner scan = s.scanner(sink);
                    s.backend->visit(batches.bounds[b], batches.bounds[b + 1], scan);
                });
        }
        if (keep_shifts) {
            s.frame.to_caller(columns.shifts.data(), columns.size());
        }
        if (s.options.sorted) {
            sort_pairs(columns, s.atom_count);
        } else if (nearest) { // groups the pairs it keeps
            keep_nearest_within(columns, s.atom_count, s.options, plan.threads,
                                ListAccess::order_scratch(out));
        } else if (s.options.grouped) {
            group_pairs(columns, s.atom_count, ListAccess::order_scratch(out));
        }
        if (!q.shifts) {
            columns.shifts.clear();
        }
        if (!q.distances) {
            columns.distances.clear();
        }
    } catch (...) {
        out.clear();
        throw;
    }
}

void append_pairs(const SearchState& s, PairColumns& columns, const ListLimits& limits) {
    if (!s.backend) {
        return;
    }
    const Quantities& q = s.options.quantities;
    const std::size_t start = columns.size();
    PairSink sink(stored_columns(columns, q.shifts, q.distances, q.vectors), limits,
                  pair_room(s.estimated_pairs), start);
    CandidateScanner scan = s.scanner(sink);
    s.backend->visit(0, s.backend->unit_count(), scan);
    sink.finish();
    if (q.shifts) {
        s.frame.to_caller(columns.shifts.data() + 3 * start, columns.size() - start);
    }
}

} // namespace detail

void NeighborSearch::for_each_block(void (*on_block)(void*, const PairBlock&),
                                    void* context) const {
    if (!state_) {
        detail::fail<InvalidArgument>(
            "NeighborSearch::for_each_pair() needs a successful build() first");
    }
    const detail::SearchState& s = *state_;
    if (s.options.max_neighbors != 0) {
        detail::fail<InvalidArgument>(
            "NeighborSearch::for_each_pair() visits the whole list: max_neighbors (the nearest "
            "pairs of each centre) needs compute()");
    }
    if (!s.backend) {
        return;
    }
    detail::PairSink sink(on_block, context, &s.frame);
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
    info.reduced_frame = s.frame.reduced();
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
    work.atoms.assign(occupancy.atoms.begin(), occupancy.atoms.end());
    work.estimated.resize(units);
    work.measured.resize(units);
    auto discard = [](void*, const PairBlock&) {};
    detail::PairSink sink(discard, nullptr, nullptr);
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
