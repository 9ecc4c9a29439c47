#include "tricell/verlet.hpp"

#include "search/distance_kernel.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <type_traits>

#include <Eigen/SVD>

#include "tricell/error.hpp"

namespace tricell {

namespace {

constexpr double pi = 3.14159265358979323846;
// Candidates are searched this much beyond r_l (relative to r_l, plus relative to the size of
// the coordinates), so that rounding in the search, which works on wrapped positions, and in
// the displacements can never drop a candidate the rule relies on.
constexpr double candidate_margin = 1e-10;
constexpr double coordinate_margin = 1e-13;
// Fractional displacements beyond this are not tracked (their jump would not fit an int); such
// an atom forces a rebuild, where the search reports the position.
constexpr double max_tracked = 1e9;

// eps = max(0, ||H0 H^-1|| - 1): how much a pair vector in the current box can grow when mapped
// back to the build box. Exactly 0 for an unchanged box.
double box_growth(const Box& built, const Box& box) {
    if (built.matrix() == box.matrix()) {
        return 0;
    }
    const Eigen::Matrix3d m = built.matrix() * box.inverse();
    const double norm = Eigen::JacobiSVD<Eigen::Matrix3d>(m).singularValues()[0];
    return std::max(0.0, norm - 1);
}

void check_finite(PointsView positions, std::size_t i) {
    const Eigen::Vector3d r = positions[i];
    if (!r.allFinite()) {
        detail::fail<InvalidArgument>("position ", i, " is not finite (got ", r.x(), ", ", r.y(),
                                      ", ", r.z(), ")");
    }
}

void check_view(PointsView positions) {
    if (positions.size() > 0 && positions.data == nullptr) {
        detail::fail<InvalidArgument>("positions: null data for ", positions.size(), " points");
    }
}

} // namespace

void VerletOptions::validate() const {
    if (neighbors.variable_cutoff()) {
        detail::fail<InvalidArgument>(
            "the Verlet list takes one cutoff (neighbors.cutoff); radii and species_cutoffs are "
            "for NeighborSearch");
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
    build_box_.reset();
    atom_count_ = 0;
    candidate_offsets_.clear();
    candidate_j_.clear();
    candidate_shift_.clear();
    updates_since_build_ = 0;
    clear_pairs();
}

void VerletList::clear_pairs() {
    pairs_.clear();
}

bool VerletList::compatible(const Box& box, PointsView positions) const {
    return build_box_.has_value() && positions.size() == atom_count_ &&
           box.periodicity() == build_box_->periodicity();
}

double VerletList::displacement_budget(const Box& box) const {
    if (!build_box_ || box.periodicity() != build_box_->periodicity()) {
        return -std::numeric_limits<double>::infinity();
    }
    return 0.5 * (options_.skin - box_growth(*build_box_, box) * options_.neighbors.cutoff);
}

double VerletList::track(const Box& box, PointsView positions, double stop_above, bool exact,
                         std::int32_t* jumps, double* unwrapped) const {
    const Box& built = *build_box_;
    const Eigen::Matrix3d& h0 = built.matrix();
    const Eigen::Matrix3d& h = box.matrix();
    const Eigen::Matrix3d& h_inv = box.inverse();
    const Periodicity& pbc = built.periodicity();
    const double stop_above_sq = stop_above * stop_above;
    double max_sq = 0;
    for (std::size_t i = 0; i < atom_count_; ++i) {
        check_finite(positions, i);
        const Eigen::Vector3d x = positions[i];
        // u = s - s0; the jump m cancels its integer part along periodic axes.
        const Eigen::Vector3d u = h_inv * x - Eigen::Map<const Eigen::Vector3d>(&reference_[3 * i]);
        if (!(u.cwiseAbs().maxCoeff() < max_tracked)) {
            return std::numeric_limits<double>::infinity();
        }
        Eigen::Vector3d m = Eigen::Vector3d::Zero();
        for (int k = 0; k < 3; ++k) {
            if (pbc[k]) {
                m[k] = -std::nearbyint(u[k]);
            }
        }
        Eigen::Vector3d delta = h0 * (u + m);
        double delta_sq = delta.squaredNorm();
        if ((exact || delta_sq > stop_above_sq) && pbc.any()) {
            // Rounding the fractional components is not always the shortest translate in a
            // skewed box; the exact minimum image decides before the atom counts as moved.
            // (Below the budget the rounded translate is good enough: the bound holds for any
            // jump, and the shortest one is shorter still.)
            const MinimumImage mi = built.minimum_image(Cartesian(delta));
            m += mi.shift.cast<double>();
            delta = mi.vector;
            delta_sq = delta.squaredNorm();
        }
        max_sq = std::max(max_sq, delta_sq);
        if (max_sq > stop_above_sq) {
            return std::sqrt(max_sq);
        }
        if (jumps != nullptr) {
            const Eigen::Vector3d r = x + h * m;
            for (int k = 0; k < 3; ++k) {
                jumps[3 * i + std::size_t(k)] = static_cast<std::int32_t>(m[k]);
                unwrapped[3 * i + std::size_t(k)] = r[k];
            }
        }
    }
    return std::sqrt(max_sq);
}

double VerletList::max_displacement(const Box& box, PointsView positions) const {
    check_view(positions);
    if (!compatible(box, positions)) {
        return std::numeric_limits<double>::infinity();
    }
    return track(box, positions, std::numeric_limits<double>::infinity(), true, nullptr, nullptr);
}

bool VerletList::needs_rebuild(const Box& box, PointsView positions) const {
    options_.validate();
    check_view(positions);
    if (!compatible(box, positions)) {
        for (std::size_t i = 0; i < positions.size(); ++i) {
            check_finite(positions, i);
        }
        return true;
    }
    const double budget = displacement_budget(box);
    if (budget < 0) {
        for (std::size_t i = 0; i < positions.size(); ++i) {
            check_finite(positions, i);
        }
        return true;
    }
    return track(box, positions, budget, false, nullptr, nullptr) > budget;
}

bool VerletList::update(const Box& box, PointsView positions) {
    try {
        options_.validate();
        check_view(positions);
        clear_pairs();
        bool rebuilt = true;
        if (compatible(box, positions)) {
            const double budget = displacement_budget(box);
            jumps_.resize(3 * atom_count_);
            unwrapped_.resize(3 * atom_count_);
            rebuilt = budget < 0 || track(box, positions, budget, false, jumps_.data(),
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
        check_view(positions);
        clear_pairs();
        build(box, positions);
        refresh(box);
    } catch (...) {
        reset();
        throw;
    }
}

void VerletList::build(const Box& box, PointsView positions) {
    build_box_.reset();
    NeighborOptions search_options = options_.neighbors;
    double scale = box.matrix().cwiseAbs().maxCoeff();
    for (std::size_t i = 0; i < positions.size(); ++i) {
        const double r = Eigen::Vector3d(positions[i]).cwiseAbs().maxCoeff();
        scale = std::isfinite(r) ? std::max(scale, r) : scale; // the search reports non-finite
    }
    search_options.cutoff = list_radius() * (1 + candidate_margin) + coordinate_margin * scale;
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
    atom_count_ = n;
    reference_.resize(3 * n);
    jumps_.resize(3 * n);
    unwrapped_.resize(3 * n);
    const Eigen::Matrix3d& h = box.matrix();
    for (std::size_t i = 0; i < n; ++i) {
        const WrappedFractional w = box.wrap(box.to_fractional(Cartesian(positions[i])));
        const Eigen::Vector3d r = Eigen::Vector3d(positions[i]) - h * w.image.cast<double>();
        for (std::size_t k = 0; k < 3; ++k) {
            reference_[3 * i + k] = w.wrapped[int(k)];
            jumps_[3 * i + k] = -w.image[int(k)]; // this update's m: x + H m is the reference
            unwrapped_[3 * i + k] = r[int(k)];
        }
    }

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

    build_box_ = box;
    ++rebuild_count_;
    updates_since_build_ = 0;
}

namespace {

// Output columns of a refresh, written through raw pointers into arrays sized for every
// candidate (PairArray growth does not zero-fill), trimmed to the pairs found at the end.
struct RefreshColumns {
    std::uint32_t* i;
    std::uint32_t* j;
    std::int32_t* shifts;
    double* distances;
    double* vectors;
};

// The filter over all candidates, grouped by i. Branch-free: every candidate is written at the
// next free slot and the slot advances only for a pair within the cutoff, so a hit rate near
// 70 % costs no mispredicted branches. Returns the number of pairs.
template <bool Shifts, bool Distances, bool Vectors>
std::size_t filter_candidates(std::size_t n, const std::size_t* offsets,
                              const std::uint32_t* cand_j, const std::uint32_t* cand_shift,
                              const double* x, const double* shift_vectors,
                              const std::int32_t* shift_table, const std::int32_t* jump,
                              double cutoff_sq, std::size_t* pair_offsets, RefreshColumns out) {
    std::size_t count = 0;
    for (std::size_t i = 0; i < n; ++i) {
        pair_offsets[i] = count;
        // D = (x~_j + H S0) - x~_i, with x~ = x + H m the unwrapped positions.
        const double xi = x[3 * i];
        const double yi = x[3 * i + 1];
        const double zi = x[3 * i + 2];
        const std::size_t end = offsets[i + 1];
        for (std::size_t p = offsets[i]; p < end; ++p) {
            const std::size_t j = cand_j[p];
            const std::size_t e = cand_shift[p];
            const double dx = x[3 * j] + shift_vectors[3 * e] - xi;
            const double dy = x[3 * j + 1] + shift_vectors[3 * e + 1] - yi;
            const double dz = x[3 * j + 2] + shift_vectors[3 * e + 2] - zi;
            const double d_sq = dx * dx + dy * dy + dz * dz;
            out.i[count] = std::uint32_t(i);
            out.j[count] = std::uint32_t(j);
            if constexpr (Shifts) {
                // S = S0 + m_j - m_i, relative to the caller's positions.
                for (std::size_t k = 0; k < 3; ++k) {
                    out.shifts[3 * count + k] =
                        shift_table[3 * e + k] + jump[3 * j + k] - jump[3 * i + k];
                }
            }
            if constexpr (Distances) {
                out.distances[count] = std::sqrt(d_sq);
            }
            if constexpr (Vectors) {
                out.vectors[3 * count] = dx;
                out.vectors[3 * count + 1] = dy;
                out.vectors[3 * count + 2] = dz;
            }
            count += d_sq < cutoff_sq ? 1 : 0;
        }
    }
    pair_offsets[n] = count;
    return count;
}

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
    const std::size_t n = atom_count_;
    const std::size_t capacity = candidate_j_.size();
    PairColumns& columns = pairs_.columns();
    columns.i.resize(capacity);
    columns.j.resize(capacity);
    columns.shifts.resize(q.shifts ? 3 * capacity : 0);
    columns.distances.resize(q.distances ? capacity : 0);
    columns.vectors.resize(q.vectors ? 3 * capacity : 0);
    columns.offsets.resize(n + 1);
    const RefreshColumns out{columns.i.data(), columns.j.data(), columns.shifts.data(),
                             columns.distances.data(), columns.vectors.data()};
    const double cutoff_sq = detail::strict_threshold_sq(options_.neighbors.cutoff);
    auto run = [&](auto shifts, auto distances, auto vectors) {
        return filter_candidates<decltype(shifts)::value, decltype(distances)::value,
                                 decltype(vectors)::value>(
            n, candidate_offsets_.data(), candidate_j_.data(), candidate_shift_.data(),
            unwrapped_.data(), shift_vectors_.data(), shift_table_.data(), jumps_.data(), cutoff_sq,
            columns.offsets.data(), out);
    };
    using Yes = std::true_type;
    using No = std::false_type;
    std::size_t count = 0;
    const int which = (q.shifts ? 4 : 0) + (q.distances ? 2 : 0) + (q.vectors ? 1 : 0);
    switch (which) {
    case 0:
        count = run(No{}, No{}, No{});
        break;
    case 1:
        count = run(No{}, No{}, Yes{});
        break;
    case 2:
        count = run(No{}, Yes{}, No{});
        break;
    case 3:
        count = run(No{}, Yes{}, Yes{});
        break;
    case 4:
        count = run(Yes{}, No{}, No{});
        break;
    case 5:
        count = run(Yes{}, No{}, Yes{});
        break;
    case 6:
        count = run(Yes{}, Yes{}, No{});
        break;
    default:
        count = run(Yes{}, Yes{}, Yes{});
        break;
    }
    columns.i.resize(count);
    columns.j.resize(count);
    columns.shifts.resize(q.shifts ? 3 * count : 0);
    columns.distances.resize(q.distances ? count : 0);
    columns.vectors.resize(q.vectors ? 3 * count : 0);
}

} // namespace tricell
