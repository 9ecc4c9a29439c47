// The writer interface of NeighborList: how the library's own producers (the search, the
// Verlet list) reach the columns they fill, without a friend per producer.
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

} // namespace tricell::detail
