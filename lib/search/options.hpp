// The checks of a search's inputs that need more than the options alone.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "tricell/neighbor_list.hpp"
#include "tricell/types.hpp"

namespace tricell::detail {

/// Refuses too many positions, null data and a non-finite position (naming its index), on
/// `threads` threads.
void check_positions(PointsView positions, std::size_t threads);

/// Checks options.query against n positions (each index < n, none twice) and returns, per caller
/// index, 1 for a query point and 0 otherwise; empty when the query is unset or holds every
/// point (the ordinary search then runs).
std::vector<std::uint8_t> query_flags(const NeighborOptions& options, std::size_t n);

} // namespace tricell::detail
