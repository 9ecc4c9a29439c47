// Two stored neighbour lists equal column by column: the same pairs in the same order, d and D
// bit for bit (the promise every backend, thread count and reused search keeps).
#pragma once

#include <gtest/gtest.h>

#include "tricell/neighbor_list.hpp"

namespace tricell::testing {

inline void expect_identical(const NeighborList& expected, const NeighborList& actual) {
    ASSERT_EQ(expected.size(), actual.size());
    ASSERT_EQ(expected.i(), actual.i());
    ASSERT_EQ(expected.j(), actual.j());
    ASSERT_EQ(expected.shifts(), actual.shifts());
    ASSERT_EQ(expected.distances(), actual.distances());
    ASSERT_EQ(expected.vectors(), actual.vectors());
}

} // namespace tricell::testing
