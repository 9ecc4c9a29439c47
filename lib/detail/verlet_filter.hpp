// The refresh filter of the Verlet lists: every update() that keeps the build measures every
// candidate again and keeps those with d < r_c (d^2 below the distance kernel's strict
// threshold). The candidates are grouped by their first atom; the filter writes each one at the
// next free slot and advances the slot only for a pair within the cutoff, so it has no branch
// per candidate and a hit rate near 70 % costs no mispredictions. Each set of columns (S, d, D)
// is its own instantiation. The serial VerletList and the distributed one
// (lib/mpi/verlet.cpp) differ only in where a candidate's second atom sits (an unwrapped
// position plus the candidate's lattice vector, or a ghost already at its image) and in the
// indices and shifts they write; each describes that in a small `Candidates` type with
// origin(a), the position of atom a (the first atom of its candidates), partner(p), where
// candidate p's second atom sits (so that D = partner - origin), and write(slot, a, p), which
// writes candidate p's indices (and shifts, if kept) at `slot`.
#pragma once

#include <cmath>
#include <cstddef>
#include <type_traits>

#include "tricell/pair_columns.hpp"

namespace tricell::detail {

/// A position, as the filter's candidates give them.
struct Point {
    double x;
    double y;
    double z;
};

/// Filters the candidates offsets[a] .. offsets[a + 1] of every atom a < atoms, in that order,
/// writing d and D (where Distances, Vectors) into arrays sized for every candidate; with
/// `first_pair` non-null, first_pair[a] is atom a's first pair kept and first_pair[atoms] the
/// count. Returns the number of pairs kept.
template <bool Distances, bool Vectors, class Candidates>
std::size_t filter_candidates(const Candidates& candidates, std::size_t atoms,
                              const std::size_t* offsets, double cutoff_sq, double* distances,
                              double* vectors, std::size_t* first_pair) {
    std::size_t count = 0;
    for (std::size_t a = 0; a < atoms; ++a) {
        if (first_pair != nullptr) {
            first_pair[a] = count;
        }
        const Point origin = candidates.origin(a);
        const std::size_t end = offsets[a + 1];
        for (std::size_t p = offsets[a]; p < end; ++p) {
            const Point partner = candidates.partner(p);
            const double dx = partner.x - origin.x;
            const double dy = partner.y - origin.y;
            const double dz = partner.z - origin.z;
            const double d_sq = dx * dx + dy * dy + dz * dz;
            candidates.write(count, a, p);
            if constexpr (Distances) {
                distances[count] = std::sqrt(d_sq);
            }
            if constexpr (Vectors) {
                vectors[3 * count] = dx;
                vectors[3 * count + 1] = dy;
                vectors[3 * count + 2] = dz;
            }
            count += d_sq < cutoff_sq ? 1 : 0;
        }
    }
    if (first_pair != nullptr) {
        first_pair[atoms] = count;
    }
    return count;
}

/// Calls f(shifts, distances, vectors), each std::true_type or std::false_type as `quantities`
/// keeps that column: one instantiation per set of columns, no branch per pair.
template <class F> std::size_t with_columns(const Quantities& quantities, F&& f) {
    const auto flag = [](bool on, auto&& g) {
        return on ? g(std::true_type{}) : g(std::false_type{});
    };
    return flag(quantities.shifts, [&](auto s) {
        return flag(quantities.distances, [&](auto d) {
            return flag(quantities.vectors, [&](auto v) { return f(s, d, v); });
        });
    });
}

} // namespace tricell::detail
