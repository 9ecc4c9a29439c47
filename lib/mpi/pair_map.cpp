#include "pair_map.hpp"

#include <algorithm>
#include <numeric>
#include <tuple>

#include "tricell/error.hpp"

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
    local.quantities = Quantities{false, caller.quantities.distances, caller.quantities.vectors};
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
    PairArray<std::uint32_t> owned(n), local_j(n);
    for (std::size_t k = 0; k < n; ++k) {
        owned[k] = p.owned[order[k]];
        local_j[k] = p.local_j[order[k]];
    }
    p.owned.swap(owned);
    p.local_j.swap(local_j);
    p.permute(order);
}

} // namespace

namespace {

// Every local pair a -> b, a owned (the subset search orients a pair with one owned end from
// it), and b -> a when b is owned too. With Half (an upper halo, where each owned-ghost pair is
// found on one rank only), each pair once: an owned-ghost pair as found, an owned-owned pair in
// its canonical orientation (exactly one of the two is).
template <bool Half, bool Shifts, bool Distances, bool Vectors>
std::size_t map_columns(std::size_t count, const std::uint32_t* li, const std::uint32_t* lj,
                        const double* distances, const double* vectors, std::size_t owned,
                        const std::uint64_t* ids, const std::int32_t* images, ColumnPointers out) {
    std::size_t n = 0;
    // Writes a -> b with S = sign (c_a - c_b) given as s (the pair's a -> b shift).
    auto emit = [&](std::size_t a, std::size_t b, double sign, std::size_t k,
                    const std::int32_t* s) {
        out.owned[n] = std::uint32_t(a);
        out.local_j[n] = std::uint32_t(b);
        out.i[n] = ids[a];
        out.j[n] = ids[b];
        if constexpr (Shifts) {
            for (std::size_t c = 0; c < 3; ++c) {
                out.shifts[3 * n + c] = s[c];
            }
        }
        if constexpr (Distances) {
            out.distances[n] = distances[k];
        }
        if constexpr (Vectors) {
            for (std::size_t c = 0; c < 3; ++c) {
                out.vectors[3 * n + c] = sign * vectors[3 * k + c];
            }
        }
        ++n;
    };
    for (std::size_t k = 0; k < count; ++k) {
        const std::size_t a = li[k];
        const std::size_t b = lj[k];
        // S is needed to store it, or to orient the pair of an atom with its own image.
        std::int32_t s[3] = {0, 0, 0}, r[3] = {0, 0, 0};
        if (Shifts || ids[a] == ids[b]) {
            for (std::size_t c = 0; c < 3; ++c) {
                s[c] = images[3 * a + c] - images[3 * b + c];
                r[c] = -s[c];
            }
        }
        if constexpr (Half) {
            if (b >= owned || canonical(ids[a], ids[b], s)) {
                emit(a, b, 1.0, k, s);
            } else {
                emit(b, a, -1.0, k, r);
            }
        } else {
            emit(a, b, 1.0, k, s);
            if (b < owned) {
                emit(b, a, -1.0, k, r);
            }
        }
    }
    return n;
}

} // namespace

ColumnPointers resize_columns(DistributedPairs& out, std::size_t n, bool shifts, bool distances,
                              bool vectors) {
    out.owned.resize(n);
    out.local_j.resize(n);
    out.i.resize(n);
    out.j.resize(n);
    out.shifts.resize(shifts ? 3 * n : 0);
    out.distances.resize(distances ? n : 0);
    out.vectors.resize(vectors ? 3 * n : 0);
    return {out.owned.data(),  out.local_j.data(),   out.i.data(),      out.j.data(),
            out.shifts.data(), out.distances.data(), out.vectors.data()};
}

void map_pairs(const NeighborList& local, const Halo& halo, bool half, bool sorted,
               const Quantities& quantities, DistributedPairs& out) {
    if (half != (halo.ghost_set() == GhostSet::upper)) {
        tricell::detail::fail<Error>("internal: a ", half ? "half" : "full", " list needs ",
                                     half ? "an upper" : "a full", " halo");
    }
    // Shifts are always computed (the half rule needs them) and kept when asked or sorting.
    const bool keep_shifts = quantities.shifts || sorted;
    // Sized for the most pairs there can be (both orientations of every local pair), then cut.
    const std::size_t most = 2 * local.size();
    const ColumnPointers columns =
        resize_columns(out, most, keep_shifts, quantities.distances, quantities.vectors);
    auto run = [&](auto half_rule, auto shifts, auto distances, auto vectors) {
        return map_columns<decltype(half_rule)::value, decltype(shifts)::value,
                           decltype(distances)::value, decltype(vectors)::value>(
            local.size(), local.i().data(), local.j().data(), local.distances().data(),
            local.vectors().data(), halo.owned_count(), halo.ids().data(), halo.images().data(),
            columns);
    };
    // One instantiation per combination of the rule and the columns (no branch per pair).
    const std::size_t n = with_flag(half, [&](auto h) {
        return with_flag(keep_shifts, [&](auto s) {
            return with_flag(quantities.distances, [&](auto d) {
                return with_flag(quantities.vectors, [&](auto v) { return run(h, s, d, v); });
            });
        });
    });
    resize_columns(out, n, keep_shifts, quantities.distances, quantities.vectors);
    if (sorted) {
        sort_pairs(out);
        if (!quantities.shifts) {
            out.shifts.clear();
        }
    }
}

} // namespace detail
} // namespace tricell::mpi
