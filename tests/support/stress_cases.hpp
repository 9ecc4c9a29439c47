// Cases for the concurrency and fork tests: dense random triclinic systems below and above the
// size at which compute_neighbors() reuses its thread-local search (lib/policy/policy.hpp), with
// option sets that vary the backend, the orders, the quantities and the thread count; and a
// bit-for-bit comparison of two lists (memcmp of every column, so -0.0 and NaN patterns count).
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <random>
#include <string>
#include <vector>

#include "tricell/neighbor_list.hpp"

namespace tricell::testing {

struct StressCase {
    Eigen::Matrix3d h;
    Periodicity pbc;
    std::vector<Eigen::Vector3d> positions;
    NeighborOptions options; ///< threads = 1; the tests set other counts
    Box box() const { return Box::from_columns(h, pbc); }
};

/// `count` cases from one seed: sizes from 60 to `max_atoms` atoms at about 0.1 atoms per unit
/// volume, cutoffs 2.5 to 4.
inline std::vector<StressCase> stress_cases(std::size_t count, std::size_t max_atoms,
                                            std::uint64_t seed = 20261203) {
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> unit(0, 1);
    const std::vector<SearchBackend>& backends = search_backends();
    std::vector<StressCase> out;
    for (std::size_t c = 0; c < count; ++c) {
        StressCase s;
        const std::size_t n =
            60 + static_cast<std::size_t>(unit(rng) * static_cast<double>(max_atoms - 60));
        const double side = std::cbrt(static_cast<double>(n) / 0.1);
        s.h = Eigen::Matrix3d::Identity() * side;
        s.h(0, 1) = 0.3 * side * (unit(rng) - 0.5);
        s.h(0, 2) = 0.3 * side * (unit(rng) - 0.5);
        s.h(1, 2) = 0.3 * side * (unit(rng) - 0.5);
        s.pbc = Periodicity{{{true, c % 3 != 1, c % 4 != 2}}};
        for (std::size_t a = 0; a < n; ++a) {
            s.positions.push_back(s.h * Eigen::Vector3d(unit(rng), unit(rng), unit(rng)));
        }
        s.options.cutoff = 2.5 + 1.5 * unit(rng);
        s.options.backend = backends[c % backends.size()];
        s.options.half = c % 2 == 1;
        s.options.sorted = c % 3 == 0;
        s.options.grouped = c % 3 == 1;
        s.options.quantities.vectors = c % 2 == 0;
        out.push_back(std::move(s));
    }
    return out;
}

template <class A> bool same_bits(const A& a, const A& b) {
    return a.size() == b.size() &&
           (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(a[0])) == 0);
}

/// Empty when the lists are identical bit for bit, else the first column that differs.
inline std::string list_difference(const NeighborList& a, const NeighborList& b) {
    if (a.size() != b.size()) {
        return "sizes " + std::to_string(a.size()) + " and " + std::to_string(b.size());
    }
    if (!same_bits(a.i(), b.i()))
        return "i";
    if (!same_bits(a.j(), b.j()))
        return "j";
    if (!same_bits(a.shifts(), b.shifts()))
        return "shifts";
    if (!same_bits(a.distances(), b.distances()))
        return "distances";
    if (!same_bits(a.vectors(), b.vectors()))
        return "vectors";
    if (!same_bits(a.offsets(), b.offsets()))
        return "offsets";
    return "";
}

} // namespace tricell::testing
