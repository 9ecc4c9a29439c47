// Brute-force oracles for the analysis functions, on top of brute_force_pairs(): an RDF
// histogram per ordered species pair and the k nearest (j, S) of every atom. O(N^2 * images):
// for tests only.
#pragma once

#include <algorithm>
#include <array>
#include <cstdint>
#include <map>
#include <utility>
#include <vector>

#include "support/brute_force.hpp"

namespace tricell::testing {

/// Ordered pairs (i, j) over every image with d < edges.back(), counted per (species of i,
/// species of j) and bin (edges[k] <= d < edges[k + 1]).
inline std::map<std::pair<std::int32_t, std::int32_t>, std::vector<double>>
brute_force_rdf_counts(const Box& box, const std::vector<Eigen::Vector3d>& x,
                       const std::vector<std::int32_t>& species, const std::vector<double>& edges) {
    std::map<std::pair<std::int32_t, std::int32_t>, std::vector<double>> out;
    const std::size_t bins = edges.size() - 1;
    for (const auto& [key, value] : brute_force_pairs(box, x, edges.back())) {
        const auto i = std::get<0>(key);
        const auto j = std::get<1>(key);
        const std::size_t k = std::size_t(
            std::upper_bound(edges.begin(), edges.end(), value.distance) - edges.begin() - 1);
        auto& counts = out[{species[i], species[j]}];
        counts.resize(bins, 0.0);
        counts[std::min(k, bins - 1)] += 1;
    }
    return out;
}

/// One candidate neighbour: (d, j, S).
struct NearCandidate {
    double d;
    std::uint32_t j;
    std::array<int, 3> s;
};

/// Every candidate (j, S) of every atom within the smallest radius (from `start`, growing by
/// 1.5) that gives each atom at least k, sorted by d, then j, then S.
inline std::vector<std::vector<NearCandidate>>
brute_force_candidates(const Box& box, const std::vector<Eigen::Vector3d>& x, std::size_t k,
                       double start) {
    for (double radius = start;; radius *= 1.5) {
        std::vector<std::vector<NearCandidate>> out(x.size());
        for (const auto& [key, value] : brute_force_pairs(box, x, radius)) {
            const auto& [i, j, a, b, c] = key;
            out[i].push_back(NearCandidate{value.distance, j, {a, b, c}});
        }
        bool enough = true;
        for (auto& candidates : out) {
            enough = enough && candidates.size() >= k;
            std::sort(candidates.begin(), candidates.end(), [](const auto& l, const auto& r) {
                return std::tie(l.d, l.j, l.s) < std::tie(r.d, r.j, r.s);
            });
        }
        if (enough) {
            return out;
        }
    }
}

} // namespace tricell::testing
