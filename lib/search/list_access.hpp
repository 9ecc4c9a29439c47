// How the library fills a NeighborList: its columns and the buffers it keeps between calls are
// private to the list (a user reads them through the const accessors), and the search, the
// Verlet list and the analysis write them through this one door.
#pragma once

#include <vector>

#include "tricell/neighbor_list.hpp"

namespace tricell::detail {

class ListAccess {
  public:
    static PairColumns& columns(NeighborList& list) { return list.columns_; }
    /// The per-thread batch columns of a threaded compute(), kept with the list.
    static std::vector<PairColumns>& thread_columns(NeighborList& list) {
        return list.thread_columns_;
    }
    /// The raw scratch column of grouping, kept with the list.
    static PairArray<unsigned char>& order_scratch(NeighborList& list) {
        return list.order_scratch_;
    }
};

} // namespace tricell::detail
