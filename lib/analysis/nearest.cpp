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
#include "detail/pair_rank.hpp"
#include "tricell/error.hpp"

namespace tricell {

namespace {

using Candidate = detail::RankedPair; // detail/pair_rank.hpp: the result's order

// A radius within which about k neighbours are expected, from the search's own density
// estimate (NeighborSearch::estimated_pairs: N atoms over the region they occupy, the cell
// along periodic axes and their extent along open ones), probed at the radius the cell volume
// alone suggests and scaled by the cube root of the shortfall. Only a start: the caller grows
// it until every atom has k. The probe's build also refuses non-finite positions.
double initial_radius(const Box& box, PointsView positions, std::size_t k,
                      const NeighborOptions& options) {
    const double n = double(positions.size());
    NeighborOptions probe = options;
    probe.cutoff = std::cbrt(3.0 * double(k) * std::abs(box.determinant()) / (4.0 * EIGEN_PI * n));
    NeighborSearch search;
    search.build(box, positions, probe);
    const double per_atom = search.estimated_pairs() / n;
    const double r = 1.1 * probe.cutoff * std::cbrt(double(k) / per_atom);
    return std::isfinite(r) && r > 0 ? r : probe.cutoff;
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
    search.max_pairs = 0; // nothing is stored but the heaps
    search.max_bytes = 0;
    search.cutoff = initial_radius(box, positions, k, search);
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
