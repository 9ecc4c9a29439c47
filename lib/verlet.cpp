#include "tricell/verlet.hpp"

#include "detail/candidate_radius.hpp"
#include "detail/verlet_filter.hpp"
#include "scan/distance_kernel.hpp"
#include "search/list_access.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>

#include "tricell/error.hpp"

namespace tricell {

void VerletOptions::validate() const {
    if (neighbors.variable_cutoff()) {
        detail::fail<InvalidArgument>(
            "the Verlet list takes one cutoff (neighbors.cutoff); radii and species_cutoffs are "
            "for NeighborSearch");
    }
    if (neighbors.max_neighbors != 0) {
        detail::fail<InvalidArgument>("the Verlet list keeps every pair within the cutoff: "
                                      "max_neighbors is for NeighborSearch");
    }
    neighbors.validate();
    if (!std::isfinite(skin)) {
        detail::fail<InvalidArgument>("skin must be finite (got ", skin, ")");
    }
    if (!(skin >= 0)) {
        detail::fail<InvalidArgument>("skin must be >= 0 (got ", skin, ")");
    }
}

VerletList::VerletList(const VerletOptions& options) : options_(options) {
    options_.validate();
}

void VerletList::reset() {
    tracker_.reset();
    candidate_offsets_.clear();
    candidate_j_.clear();
    candidate_shift_.clear();
    updates_since_build_ = 0;
    clear_pairs();
}

void VerletList::clear_pairs() {
    pairs_.clear();
}

double VerletList::displacement_budget(const Box& box) const {
    return tracker_.budget(box, options_.skin, options_.neighbors.cutoff);
}

double VerletList::max_displacement(const Box& box, PointsView positions) const {
    return tracker_.max_displacement(box, positions);
}

bool VerletList::needs_rebuild(const Box& box, PointsView positions) const {
    options_.validate();
    return tracker_.needs_rebuild(box, positions, options_.skin, options_.neighbors.cutoff);
}

bool VerletList::update(const Box& box, PointsView positions) {
    try {
        options_.validate();
        clear_pairs();
        bool rebuilt = true;
        if (tracker_.compatible(box, positions)) {
            const double budget = displacement_budget(box);
            jumps_.resize(3 * tracker_.atom_count());
            unwrapped_.resize(3 * tracker_.atom_count());
            rebuilt = budget < 0 || tracker_.track(box, positions, budget, false, jumps_.data(),
                                                   unwrapped_.data()) > budget;
        }
        if (rebuilt) {
            build(box, positions);
        } else {
            ++updates_since_build_;
        }
        refresh(box);
        return rebuilt;
    } catch (...) {
        reset();
        throw;
    }
}

void VerletList::rebuild(const Box& box, PointsView positions) {
    try {
        options_.validate();
        clear_pairs();
        build(box, positions);
        refresh(box);
    } catch (...) {
        reset();
        throw;
    }
}

void VerletList::set_query(std::optional<std::vector<std::uint32_t>> query) {
    options_.neighbors.query = std::move(query);
    reset();
}

void VerletList::build(const Box& box, PointsView positions) {
    tracker_.reset();
    NeighborOptions search_options = options_.neighbors;
    search_options.cutoff = detail::candidate_radius(list_radius(), box.matrix(), positions);
    search_options.quantities.shifts = true;
    search_options.quantities.distances = false;
    search_options.quantities.vectors = false;
    search_options.sorted = false;
    search_options.grouped = false;
    NeighborSearch search;
    search.build(box, positions, search_options); // validates the positions
    search.compute(raw_);

    // Reference: wrapped fractional positions s0 = s - image. Candidates are stored relative
    // to them, S0 = S + image_j - image_i, which keeps the shifts small (within the reach of
    // r_l) however far outside the box the caller's positions are.
    const std::size_t n = positions.size();
    jumps_.resize(3 * n);
    unwrapped_.resize(3 * n);
    // This update's m = -image: x + H m is the reference.
    tracker_.record(box, positions, jumps_.data(), unwrapped_.data());

    // S0 of every candidate, the dense table of the shifts that occur, then the candidates
    // grouped by i (counting sort).
    const std::size_t count = raw_.size();
    const std::uint32_t* is = raw_.i().data();
    const std::uint32_t* js = raw_.j().data();
    const std::int32_t* ss = raw_.shifts().data();
    const std::int32_t* jump = jumps_.data();
    scratch_.resize(3 * count);
    std::int32_t* shift0 = scratch_.data();
    candidate_offsets_.assign(n + 1, 0);
    std::int32_t lo[3] = {0, 0, 0};
    std::int32_t hi[3] = {0, 0, 0};
    for (std::size_t p = 0; p < count; ++p) {
        const std::size_t i = is[p];
        const std::size_t j = js[p];
        ++candidate_offsets_[i + 1];
        for (std::size_t k = 0; k < 3; ++k) {
            const std::int32_t v = ss[3 * p + k] + jump[3 * i + k] - jump[3 * j + k];
            shift0[3 * p + k] = v;
            lo[k] = std::min(lo[k], v);
            hi[k] = std::max(hi[k], v);
        }
    }
    const std::size_t extent[3] = {std::size_t(hi[0] - lo[0] + 1), std::size_t(hi[1] - lo[1] + 1),
                                   std::size_t(hi[2] - lo[2] + 1)};
    const std::size_t entries = extent[0] * extent[1] * extent[2];
    shift_table_.resize(3 * entries);
    for (std::size_t e = 0; e < entries; ++e) {
        shift_table_[3 * e] = lo[0] + std::int32_t(e / (extent[2] * extent[1]));
        shift_table_[3 * e + 1] = lo[1] + std::int32_t((e / extent[2]) % extent[1]);
        shift_table_[3 * e + 2] = lo[2] + std::int32_t(e % extent[2]);
    }
    shift_vectors_.resize(3 * entries);
    shift_box_ = Eigen::Matrix3d::Zero(); // recomputed by refresh()

    std::partial_sum(candidate_offsets_.begin(), candidate_offsets_.end(),
                     candidate_offsets_.begin());
    candidate_j_.resize(count);
    candidate_shift_.resize(count);
    cursor_.assign(candidate_offsets_.begin(), candidate_offsets_.end() - 1);
    for (std::size_t p = 0; p < count; ++p) {
        const std::size_t slot = cursor_[is[p]]++;
        candidate_j_[slot] = js[p];
        const std::size_t a = std::size_t(shift0[3 * p] - lo[0]);
        const std::size_t b = std::size_t(shift0[3 * p + 1] - lo[1]);
        const std::size_t c = std::size_t(shift0[3 * p + 2] - lo[2]);
        candidate_shift_[slot] = static_cast<std::uint32_t>((a * extent[1] + b) * extent[2] + c);
    }
    raw_.clear();

    ++rebuild_count_;
    updates_since_build_ = 0;
}

namespace {

// The serial list's candidates for the refresh filter (detail/verlet_filter.hpp): atom j at its
// unwrapped position x~_j = x_j + H m_j plus the candidate's lattice vector H S0, so that
// D = (x~_j + H S0) - x~_i; written as (i, j) and S = S0 + m_j - m_i, relative to the caller's
// positions. The output columns are sized for every candidate (PairArray growth does not
// zero-fill) and trimmed to the pairs found at the end.
template <bool Shifts> struct SerialCandidates {
    const std::uint32_t* cand_j;
    const std::uint32_t* cand_shift; // index into the shift tables
    const double* x;                 // unwrapped positions
    const double* shift_vectors;
    const std::int32_t* shift_table;
    const std::int32_t* jump; // m, per atom
    std::uint32_t* out_i;
    std::uint32_t* out_j;
    std::int32_t* out_shifts;

    detail::Point origin(std::size_t i) const { return {x[3 * i], x[3 * i + 1], x[3 * i + 2]}; }

    detail::Point partner(std::size_t p) const {
        const std::size_t j = cand_j[p];
        const std::size_t e = cand_shift[p];
        return {x[3 * j] + shift_vectors[3 * e], x[3 * j + 1] + shift_vectors[3 * e + 1],
                x[3 * j + 2] + shift_vectors[3 * e + 2]};
    }

    void write(std::size_t slot, std::size_t i, std::size_t p) const {
        // Every read before the first write: a write through out_j may alias cand_shift.
        const std::size_t j = cand_j[p];
        const std::size_t e = cand_shift[p];
        out_i[slot] = std::uint32_t(i);
        out_j[slot] = std::uint32_t(j);
        if constexpr (Shifts) {
            for (std::size_t k = 0; k < 3; ++k) {
                out_shifts[3 * slot + k] =
                    shift_table[3 * e + k] + jump[3 * j + k] - jump[3 * i + k];
            }
        }
    }
};

} // namespace

void VerletList::refresh(const Box& box) {
    const Eigen::Matrix3d& h = box.matrix();
    if (h != shift_box_) {
        for (std::size_t e = 0; e < shift_vectors_.size() / 3; ++e) {
            const Eigen::Vector3d v =
                h * Eigen::Vector3d(shift_table_[3 * e], shift_table_[3 * e + 1],
                                    shift_table_[3 * e + 2]);
            shift_vectors_[3 * e] = v.x();
            shift_vectors_[3 * e + 1] = v.y();
            shift_vectors_[3 * e + 2] = v.z();
        }
        shift_box_ = h;
    }
    const Quantities& q = options_.neighbors.quantities;
    const std::size_t n = tracker_.atom_count();
    const std::size_t capacity = candidate_j_.size();
    PairColumns& columns = detail::ListAccess::columns(pairs_);
    columns.i.resize(capacity);
    columns.j.resize(capacity);
    columns.shifts.resize(q.shifts ? 3 * capacity : 0);
    columns.distances.resize(q.distances ? capacity : 0);
    columns.vectors.resize(q.vectors ? 3 * capacity : 0);
    columns.offsets.resize(n + 1);
    const double cutoff_sq = detail::strict_threshold_sq(options_.neighbors.cutoff);
    const std::size_t count =
        detail::with_columns(q, [&](auto shifts, auto distances, auto vectors) {
            const SerialCandidates<decltype(shifts)::value> candidates{
                candidate_j_.data(),   candidate_shift_.data(), unwrapped_.data(),
                shift_vectors_.data(), shift_table_.data(),     jumps_.data(),
                columns.i.data(),      columns.j.data(),        columns.shifts.data()};
            return detail::filter_candidates<decltype(distances)::value, decltype(vectors)::value>(
                candidates, n, candidate_offsets_.data(), cutoff_sq, columns.distances.data(),
                columns.vectors.data(), columns.offsets.data());
        });
    columns.i.resize(count);
    columns.j.resize(count);
    columns.shifts.resize(q.shifts ? 3 * count : 0);
    columns.distances.resize(q.distances ? count : 0);
    columns.vectors.resize(q.vectors ? 3 * count : 0);
}

} // namespace tricell
