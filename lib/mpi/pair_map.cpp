#include "pair_map.hpp"

#include <algorithm>
#include <numeric>
#include <tuple>

namespace tricell::mpi {

namespace detail {

NeighborOptions local_options(const NeighborOptions& caller, std::size_t owned) {
    NeighborOptions local = caller;
    std::vector<std::uint32_t> query(owned);
    std::iota(query.begin(), query.end(), 0u);
    local.query = std::move(query);
    local.half = true;
    local.sorted = false;
    local.grouped = false;
    local.quantities = Quantities{false, true, true};
    local.radii.clear(); // per local atom: set by the caller from the halo
    local.species.clear();
    return local;
}

namespace {

// The serial list's canonical orientation: i < j, or i == j with S lexicographically positive.
bool canonical(std::uint64_t i, std::uint64_t j, const std::int32_t s[3]) {
    if (i != j) {
        return i < j;
    }
    return s[0] > 0 || (s[0] == 0 && (s[1] > 0 || (s[1] == 0 && s[2] > 0)));
}

void sort_pairs(DistributedPairs& p) {
    const std::size_t n = p.size();
    std::vector<std::size_t> order(n);
    std::iota(order.begin(), order.end(), std::size_t(0));
    auto key = [&](std::size_t k) {
        return std::make_tuple(p.i[k], p.j[k], p.shifts[3 * k], p.shifts[3 * k + 1],
                               p.shifts[3 * k + 2]);
    };
    std::sort(order.begin(), order.end(),
              [&](std::size_t a, std::size_t b) { return key(a) < key(b); });
    std::vector<std::uint32_t> owned(n), local_j(n);
    for (std::size_t k = 0; k < n; ++k) {
        owned[k] = p.owned[order[k]];
        local_j[k] = p.local_j[order[k]];
    }
    p.owned.swap(owned);
    p.local_j.swap(local_j);
    p.permute(order);
}

} // namespace

void map_pairs(const NeighborList& local, const Halo& halo, bool half, bool sorted,
               const Quantities& quantities, DistributedPairs& out) {
    const std::size_t owned = halo.owned_count();
    const auto& ids = halo.ids();
    const auto& images = halo.images();
    const auto& li = local.i();
    const auto& lj = local.j();
    const double* distances = local.distances().data();
    const double* vectors = local.vectors().data();
    // Shifts are always computed (the half rule needs them) and kept when asked or sorting.
    const bool keep_shifts = quantities.shifts || sorted;
    // Sized for the most pairs there can be (both orientations of every local pair), then cut.
    const std::size_t most = 2 * local.size();
    out.owned.resize(most);
    out.local_j.resize(most);
    out.i.resize(most);
    out.j.resize(most);
    out.shifts.resize(keep_shifts ? 3 * most : 0);
    out.distances.resize(quantities.distances ? most : 0);
    out.vectors.resize(quantities.vectors ? 3 * most : 0);
    std::size_t n = 0;
    auto emit = [&](std::size_t a, std::size_t b, double sign, std::size_t k) {
        std::int32_t s[3];
        for (std::size_t c = 0; c < 3; ++c) {
            s[c] = images[3 * a + c] - images[3 * b + c];
        }
        if (half && !canonical(ids[a], ids[b], s)) {
            return;
        }
        out.owned[n] = std::uint32_t(a);
        out.local_j[n] = std::uint32_t(b);
        out.i[n] = ids[a];
        out.j[n] = ids[b];
        if (keep_shifts) {
            std::copy(s, s + 3, &out.shifts[3 * n]);
        }
        if (quantities.distances) {
            out.distances[n] = distances[k];
        }
        if (quantities.vectors) {
            for (std::size_t c = 0; c < 3; ++c) {
                out.vectors[3 * n + c] = sign * vectors[3 * k + c];
            }
        }
        ++n;
    };
    for (std::size_t k = 0; k < local.size(); ++k) {
        const std::size_t a = li[k];
        const std::size_t b = lj[k];
        if (a < owned) {
            emit(a, b, 1.0, k);
        }
        if (b < owned) {
            emit(b, a, -1.0, k);
        }
    }
    out.owned.resize(n);
    out.local_j.resize(n);
    out.i.resize(n);
    out.j.resize(n);
    out.shifts.resize(keep_shifts ? 3 * n : 0);
    out.distances.resize(quantities.distances ? n : 0);
    out.vectors.resize(quantities.vectors ? 3 * n : 0);
    if (sorted) {
        sort_pairs(out);
        if (!quantities.shifts) {
            out.shifts.clear();
        }
    }
}

} // namespace detail
} // namespace tricell::mpi
