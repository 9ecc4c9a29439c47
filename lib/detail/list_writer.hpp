// The writer interface of NeighborList: how the library's own producers (the search, the
// Verlet list, the shells of several cutoffs) reach the columns they fill, without a friend per
// producer, and the one way they reorder them.
#pragma once

#include <vector>

#include "tricell/neighbor_list.hpp"

namespace tricell::detail {

struct ListWriter {
    static PairArray<std::uint32_t>& i(NeighborList& l) { return l.i_; }
    static PairArray<std::uint32_t>& j(NeighborList& l) { return l.j_; }
    static PairArray<std::int32_t>& shifts(NeighborList& l) { return l.shifts_; }
    static PairArray<double>& distances(NeighborList& l) { return l.distances_; }
    static PairArray<double>& vectors(NeighborList& l) { return l.vectors_; }
    static std::vector<std::size_t>& offsets(NeighborList& l) { return l.offsets_; }
    static std::vector<NeighborList>& partial(NeighborList& l) { return l.partial_; }
};

/// Reorders a column in place so that v[k] becomes old v[perm[k]], for `width` values per pair
/// (how the sort and the shells of several cutoffs permute every column alike).
template <class T>
void gather(PairArray<T>& v, const std::vector<std::size_t>& perm, std::size_t width) {
    if (v.empty()) {
        return;
    }
    PairArray<T> out(v.size());
    for (std::size_t k = 0; k < perm.size(); ++k) {
        for (std::size_t w = 0; w < width; ++w) {
            out[width * k + w] = v[width * perm[k] + w];
        }
    }
    v.swap(out);
}

} // namespace tricell::detail
