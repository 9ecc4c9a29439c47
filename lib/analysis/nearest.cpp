// nearest_neighbors: per atom a bounded max-heap of its k best candidates (d, j, S), filled from
// half-list searches of growing radius (nearest.hpp says why and how). The heap's order is the
// result's: d, then j, then S lexicographically, a total order on distinct candidates, so which
// k survive and their order do not depend on the order pairs arrive in. An atom whose heap is
// full after a search at radius r is final: every candidate it lacks has d >= r, farther than
// all it holds. The others are emptied and refilled by the next, wider search.
#include "tricell/analysis/nearest.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "analysis/half_pairs.hpp"
#include "tricell/error.hpp"

namespace tricell {

namespace {

constexpr double pi = 3.14159265358979323846;

struct Candidate {
    double d;
    std::uint32_t j;
    std::int32_t s[3];
};

bool operator<(const Candidate& l, const Candidate& r) {
    if (l.d != r.d) {
        return l.d < r.d;
    }
    if (l.j != r.j) {
        return l.j < r.j;
    }
    return std::lexicographical_compare(l.s, l.s + 3, r.s, r.s + 3);
}

// A radius within which about k neighbours are expected: N atoms spread over the cell along
// periodic axes and over the extent of the positions along open ones (at least a thousandth
// of the cell, so that atoms in a plane do not make the volume vanish).
double initial_radius(const Box& box, PointsView positions, std::size_t k) {
    double volume = std::abs(box.determinant());
    for (int axis = 0; axis < 3; ++axis) {
        if (box.periodic(axis)) {
            continue;
        }
        double lo = std::numeric_limits<double>::infinity();
        double hi = -lo;
        for (std::size_t i = 0; i < positions.size(); ++i) {
            const double s = box.inverse().row(axis).dot(positions[i]);
            lo = std::min(lo, s);
            hi = std::max(hi, s);
        }
        volume *= std::max(hi - lo, 1e-3);
    }
    const double density = double(positions.size()) / volume;
    const double r = 1.1 * std::cbrt(3.0 * double(k) / (4.0 * pi * density));
    // Non-finite positions give a meaningless estimate; the search then refuses them.
    return std::isfinite(r) && r > 0 ? r : 1.0;
}

} // namespace

NearestNeighbors nearest_neighbors(const Box& box, PointsView positions, std::size_t k,
                                   const NearestOptions& options) {
    const std::size_t n = positions.size();
    if (k == 0) {
        detail::fail<InvalidArgument>("nearest_neighbors: k must be >= 1 (got 0)");
    }
    if (!box.periodicity().any() && n > 0 && k > n - 1) {
        detail::fail<InvalidArgument>("nearest_neighbors: k = ", k,
                                      " neighbours per atom need at least k + 1 atoms in a "
                                      "system open along every axis (got N = ",
                                      n, ")");
    }
    if (k > std::numeric_limits<std::uint32_t>::max() ||
        (n > 0 && k > std::numeric_limits<std::size_t>::max() / (n * sizeof(Candidate)))) {
        detail::fail<InvalidArgument>("nearest_neighbors: k = ", k, " for N = ", n,
                                      " atoms does not fit in memory");
    }
    NearestNeighbors out;
    out.k = k;
    if (n == 0) {
        return out;
    }

    std::vector<Candidate> heaps(n * k);
    std::vector<std::size_t> filled(n, 0);
    std::vector<bool> open(n, true); // not final yet
    std::size_t remaining = n;
    const auto offer = [&](std::uint32_t i, const Candidate& candidate) {
        if (!open[i]) {
            return;
        }
        Candidate* heap = heaps.data() + std::size_t(i) * k;
        std::size_t& size = filled[i];
        if (size < k) {
            heap[size++] = candidate;
            std::push_heap(heap, heap + size);
        } else if (candidate < heap[0]) {
            std::pop_heap(heap, heap + k);
            heap[k - 1] = candidate;
            std::push_heap(heap, heap + k);
        }
    };

    NeighborOptions search;
    search.threads = options.threads;
    search.backend = options.backend;
    search.cutoff = initial_radius(box, positions, k);
    while (true) {
        detail::for_each_half_pair(
            box, positions, search,
            [&](std::uint32_t i, std::uint32_t j, const std::int32_t* s, double d) {
                offer(i, Candidate{d, j, {s[0], s[1], s[2]}});
                offer(j, Candidate{d, i, {-s[0], -s[1], -s[2]}});
            });
        std::size_t fewest = k;
        for (std::size_t i = 0; i < n; ++i) {
            if (!open[i]) {
                continue;
            }
            if (filled[i] == k) {
                open[i] = false;
                --remaining;
            } else {
                fewest = std::min(fewest, filled[i]);
                filled[i] = 0; // refilled by the wider search
            }
        }
        if (remaining == 0) {
            break;
        }
        // Grow by the cube root of the missing share (neighbours grow like r^3 in bulk), at
        // least 1.25 and at most 2 per step.
        const double factor =
            std::clamp(1.1 * std::cbrt(double(k + 1) / double(fewest + 1)), 1.25, 2.0);
        search.cutoff *= factor;
    }

    out.j.resize(n * k);
    out.shifts.resize(3 * n * k);
    out.distances.resize(n * k);
    for (std::size_t i = 0; i < n; ++i) {
        Candidate* heap = heaps.data() + i * k;
        std::sort_heap(heap, heap + k);
        for (std::size_t e = 0; e < k; ++e) {
            const std::size_t at = i * k + e;
            out.j[at] = heap[e].j;
            out.distances[at] = heap[e].d;
            std::copy(heap[e].s, heap[e].s + 3, out.shifts.begin() + std::ptrdiff_t(3 * at));
        }
    }
    return out;
}

} // namespace tricell
