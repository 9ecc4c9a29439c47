// The orientation a half list keeps of each pair (docs/contract.md): (i, j, S) with i < j, or,
// for an atom and its own image (i == j), S lexicographically positive. The search turns pairs
// into it and verify() turns a listed pair into it before comparing.
#pragma once

namespace tricell::detail {

/// S = (a, b, c) is lexicographically positive: its first nonzero component is > 0.
template <class Int> constexpr bool lexicographically_positive(Int a, Int b, Int c) {
    return a > 0 || (a == 0 && (b > 0 || (b == 0 && c > 0)));
}

/// (i, j, S) is in the half list's orientation (never true for (i, i, 0)).
template <class Index, class Int>
constexpr bool half_orientation(Index i, Index j, Int a, Int b, Int c) {
    return i != j ? i < j : lexicographically_positive(a, b, c);
}

} // namespace tricell::detail
