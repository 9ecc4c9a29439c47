// The rank of a pair among its centre's pairs: d, then j, then S lexicographically. No two pairs
// of one centre share j and S, so this is a total order: which k pairs come first does not
// depend on the order a search found them, nor on the backend or the threads. Both ways of
// asking for the nearest pairs rank so (nearest_neighbors, NeighborOptions::max_neighbors).
#pragma once

#include <algorithm>
#include <cstdint>

namespace tricell::detail {

struct RankedPair {
    double d;
    std::uint32_t j;
    std::int32_t s[3];
};

inline bool operator<(const RankedPair& l, const RankedPair& r) {
    if (l.d != r.d) {
        return l.d < r.d;
    }
    if (l.j != r.j) {
        return l.j < r.j;
    }
    return std::lexicographical_compare(l.s, l.s + 3, r.s, r.s + 3);
}

} // namespace tricell::detail
