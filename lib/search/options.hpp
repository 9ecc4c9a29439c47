// The checks of a search's inputs that need more than the options alone.
#pragma once

#include <cstddef>

#include "tricell/types.hpp"

namespace tricell::detail {

/// Refuses too many positions, null data and a non-finite position (naming its index), on
/// `threads` threads.
void check_positions(PointsView positions, std::size_t threads);

} // namespace tricell::detail
