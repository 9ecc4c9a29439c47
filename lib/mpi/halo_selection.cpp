// Ghost selection at a halo build, by the rules of tricell/mpi/halo.hpp ("Selection is in
// fractional space", "Upper halos"). Each axis is handled alone, in fractional units: the
// atom's wrapped coordinate s, translated by every t the periodicity allows, hits the intervals
// whose extent widened by h contains s + t; the products of the three axes' hits are the
// (destination domain, T) pairs, of which an upper halo keeps those whose ghost is upper at its
// destination. The neighbour ranks are the products of the intervals, along each axis, that
// some translate of this rank's interval reaches. build() checks the owned atoms, places them
// in the local frame, selects, and hands the selection to the exchange (halo_exchange.cpp).
#include "tricell/mpi/halo.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <vector>

#include "collective.hpp"
#include "tricell/error.hpp"

namespace tricell::mpi {

using tricell::detail::fail;

namespace {

// One candidate along one axis: the interval of the destination and the translation.
struct AxisHit {
    int interval;
    int t;
};

// The halo half-widths in fractional units, h = reach / w per axis, widened by a few ulps so that
// a pair at exactly the limit (after rounding of s) is never lost. Extra ghosts are harmless.
Eigen::Vector3d halo_widths(const Box& box, double reach) {
    Eigen::Vector3d h;
    for (int k = 0; k < 3; ++k) {
        h[k] = reach / box.perpendicular_widths()[k] * (1 + 1e-10) + 1e-12;
    }
    return h;
}

// Extent of interval k along an axis: end intervals of an open axis reach to infinity.
double interval_lo(const Decomposition& d, int axis, int k, bool periodic) {
    return (!periodic && k == 0) ? -std::numeric_limits<double>::infinity()
                                 : d.bounds(axis)[std::size_t(k)];
}
double interval_hi(const Decomposition& d, int axis, int k, bool periodic) {
    return (!periodic && k == d.dims()[std::size_t(axis)] - 1)
               ? std::numeric_limits<double>::infinity()
               : d.bounds(axis)[std::size_t(k) + 1];
}

// The (interval, translation) pairs whose halo contains s + t along one axis.
void axis_hits(const Decomposition& d, int axis, bool periodic, double s, double h,
               std::vector<AxisHit>& out) {
    out.clear();
    const int n = d.dims()[std::size_t(axis)];
    const int t_lo = periodic ? int(std::ceil(-h - s)) - 1 : 0;
    const int t_hi = periodic ? int(std::floor(1 + h - s)) + 1 : 0;
    for (int t = t_lo; t <= t_hi; ++t) {
        const double v = s + t;
        for (int k = 0; k < n; ++k) {
            if (v >= interval_lo(d, axis, k, periodic) - h &&
                v <= interval_hi(d, axis, k, periodic) + h) {
                out.push_back({k, t});
            }
        }
    }
}

// The intervals along an axis whose halo some translate of interval `mine` reaches (a symmetric
// relation between intervals, hence between domains).
std::vector<int> axis_neighbors(const Decomposition& d, int axis, bool periodic, int mine,
                                double h) {
    std::vector<int> out;
    const double lo = interval_lo(d, axis, mine, periodic);
    const double hi = interval_hi(d, axis, mine, periodic);
    for (int k = 0; k < d.dims()[std::size_t(axis)]; ++k) {
        const double klo = interval_lo(d, axis, k, periodic) - h;
        const double khi = interval_hi(d, axis, k, periodic) + h;
        const bool hit =
            periodic ? std::ceil(klo - hi) <= std::floor(khi - lo) : (klo <= hi && lo <= khi);
        if (hit) {
            out.push_back(k);
        }
    }
    return out;
}

// Whether a ghost sent from grid position `from` through translation t is upper at grid position
// `to` (halo.hpp, "Upper halos"): from + t * dims - to lexicographically positive.
bool upper(const std::array<int, 3>& t, const std::array<int, 3>& from,
           const std::array<int, 3>& to, const std::array<int, 3>& dims) {
    for (std::size_t k = 0; k < 3; ++k) {
        const int offset = from[k] + t[k] * dims[k] - to[k];
        if (offset != 0) {
            return offset > 0;
        }
    }
    return false;
}

} // namespace

void Halo::build(const Decomposition& decomposition, const Box& box,
                 const std::vector<std::uint64_t>& ids, PointsView positions, double reach,
                 const std::vector<double>* radii, const std::vector<std::int32_t>* species,
                 GhostSet ghosts) {
    const int me = decomposition.rank();
    std::vector<Fractional> wrapped(positions.size());
    std::vector<Shift> image(positions.size());
    detail::agreed(decomposition.comm(), [&] {
        if (!(std::isfinite(reach) && reach > 0)) {
            fail<InvalidArgument>("halo reach must be > 0 (got ", reach, ")");
        }
        if (positions.size() != ids.size()) {
            fail<InvalidArgument>("halo needs one id per position (", ids.size(), " ids, ",
                                  positions.size(), " positions)");
        }
        if (radii && radii->size() != ids.size()) {
            fail<InvalidArgument>("radii must hold one value per owned atom (", ids.size(),
                                  " atoms, got ", radii->size(), ")");
        }
        if (species && species->size() != ids.size()) {
            fail<InvalidArgument>("species must hold one value per owned atom (", ids.size(),
                                  " atoms, got ", species->size(), ")");
        }
        for (std::size_t a = 0; a < positions.size(); ++a) {
            const Eigen::Vector3d x = positions[a];
            if (!x.allFinite()) {
                fail<InvalidArgument>("position of atom id ", ids[a], " is not finite");
            }
            const WrappedFractional w = box.wrap(box.to_fractional(Cartesian(x)));
            const int owner = decomposition.owner(w.wrapped);
            if (owner != me) {
                fail<InvalidArgument>("atom id ", ids[a], " at fractional (", w.wrapped[0], ", ",
                                      w.wrapped[1], ", ", w.wrapped[2], ") belongs to rank ", owner,
                                      ", not ", me, "; call tricell::mpi::migrate() first");
            }
            wrapped[a] = w.wrapped;
            image[a] = w.image;
        }
    });

    reach_ = reach;
    ghost_set_ = ghosts;
    pbc_ = box.periodicity();
    owned_ = positions.size();
    const Eigen::Vector3d h = halo_widths(box, reach);

    // The neighbour ranks: products of the per-axis neighbour intervals, without this rank.
    const std::array<int, 3> my = decomposition.coords(me);
    std::array<std::vector<int>, 3> near;
    for (int k = 0; k < 3; ++k) {
        near[std::size_t(k)] = axis_neighbors(decomposition, k, pbc_[k], my[std::size_t(k)], h[k]);
    }
    neighbors_.clear();
    for (int a : near[0]) {
        for (int b : near[1]) {
            for (int c : near[2]) {
                const int r = decomposition.rank_at({{a, b, c}});
                if (r != me) {
                    neighbors_.push_back(r);
                }
            }
        }
    }
    std::sort(neighbors_.begin(), neighbors_.end());
    std::vector<int> slot(std::size_t(decomposition.size()), -1);
    for (std::size_t n = 0; n < neighbors_.size(); ++n) {
        slot[std::size_t(neighbors_[n])] = int(n);
    }

    // Owned atoms in the local frame, and their ghosts' destinations.
    y_.resize(3 * owned_);
    images_.resize(3 * owned_);
    ids_.assign(ids.begin(), ids.end());
    with_radii_ = radii != nullptr;
    with_species_ = species != nullptr;
    radii_ = with_radii_ ? *radii : std::vector<double>();
    species_ = with_species_ ? *species : std::vector<std::int32_t>();
    reference_.resize(3 * owned_);
    sends_.assign(neighbors_.size(), {});
    self_sends_.clear();
    std::array<std::vector<AxisHit>, 3> hits;
    const std::array<int, 3>& dims = decomposition.dims();
    const bool upper_only = ghosts == GhostSet::upper;
    for (std::size_t a = 0; a < owned_; ++a) {
        const Cartesian y = box.to_cartesian(wrapped[a]);
        for (int k = 0; k < 3; ++k) {
            y_[3 * a + std::size_t(k)] = y[k];
            images_[3 * a + std::size_t(k)] = image[a][k];
            reference_[3 * a + std::size_t(k)] = wrapped[a][k];
            axis_hits(decomposition, k, pbc_[k], wrapped[a][k], h[k], hits[std::size_t(k)]);
        }
        for (const AxisHit& ha : hits[0]) {
            for (const AxisHit& hb : hits[1]) {
                for (const AxisHit& hc : hits[2]) {
                    const std::array<int, 3> to{{ha.interval, hb.interval, hc.interval}};
                    if (upper_only && !upper({{ha.t, hb.t, hc.t}}, my, to, dims)) {
                        continue;
                    }
                    const int r = decomposition.rank_at(to);
                    const Send send{std::uint32_t(a), {ha.t, hb.t, hc.t}};
                    if (r == me) {
                        if (ha.t != 0 || hb.t != 0 || hc.t != 0) {
                            self_sends_.push_back(send);
                        }
                    } else if (slot[std::size_t(r)] >= 0) {
                        sends_[std::size_t(slot[std::size_t(r)])].push_back(send);
                    } else {
                        fail<Error>("internal: rank ", r, " is not a halo neighbour of ", me);
                    }
                }
            }
        }
    }
    exchange(decomposition, box);
}

} // namespace tricell::mpi
