// The brute-force oracle for neighbour lists: every pair (i, j) and every image shift S the
// perpendicular widths allow, distances computed from the caller's positions exactly as the
// contract defines them (D = x_j - x_i + H S). O(N^2 * images): for tests only.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <map>
#include <stdexcept>
#include <tuple>
#include <vector>

#include "tricell/box.hpp"
#include "tricell/neighbor_list.hpp"

namespace tricell::testing {

/// (i, j, Sa, Sb, Sc): the identity of one entry of a neighbour list.
using PairKey = std::tuple<std::uint32_t, std::uint32_t, int, int, int>;

struct PairValue {
    double distance;
    Eigen::Vector3d vector;
};

using PairMap = std::map<PairKey, PairValue>;

/// Every pair (i, j, S) with d < cutoff, handed to visit(key, value) in increasing key order
/// (i, then j, then S lexicographically): the oracle's one loop, which the map below and the
/// fuzzers' sorted rows are both filled from.
template <class Visit>
void for_each_brute_force_pair(const Box& box, const std::vector<Eigen::Vector3d>& x, double cutoff,
                               const Visit& visit) {
    const Eigen::Matrix3d& h = box.matrix();
    const Eigen::Vector3d& w = box.perpendicular_widths();
    std::vector<Eigen::Vector3d> s(x.size());
    for (std::size_t i = 0; i < x.size(); ++i) {
        s[i] = box.inverse() * x[i];
    }
    for (std::uint32_t i = 0; i < x.size(); ++i) {
        for (std::uint32_t j = 0; j < x.size(); ++j) {
            // |(s_j - s_i + S)_k| <= |D| / w_k < cutoff / w_k for a pair within the cutoff.
            int lo[3], hi[3];
            for (int k = 0; k < 3; ++k) {
                if (!box.periodic(k)) {
                    lo[k] = hi[k] = 0;
                    continue;
                }
                const double centre = s[i][k] - s[j][k];
                const double reach = cutoff / w[k] + 1e-6;
                lo[k] = static_cast<int>(std::ceil(centre - reach));
                hi[k] = static_cast<int>(std::floor(centre + reach));
            }
            for (int a = lo[0]; a <= hi[0]; ++a) {
                for (int b = lo[1]; b <= hi[1]; ++b) {
                    for (int c = lo[2]; c <= hi[2]; ++c) {
                        if (i == j && a == 0 && b == 0 && c == 0) {
                            continue;
                        }
                        const Eigen::Vector3d d = x[j] - x[i] + h * Eigen::Vector3d(a, b, c);
                        const double d_sq = d.squaredNorm();
                        // sqrt(d_sq) < cutoff, not d_sq < cutoff^2: the square of a tiny
                        // cutoff underflows to 0 (coincident atoms at d = 0 are neighbours).
                        if (std::sqrt(d_sq) < cutoff) {
                            visit(PairKey{i, j, a, b, c}, PairValue{std::sqrt(d_sq), d});
                        }
                    }
                }
            }
        }
    }
}

inline PairMap brute_force_pairs(const Box& box, const std::vector<Eigen::Vector3d>& x,
                                 double cutoff) {
    PairMap out;
    for_each_brute_force_pair(box, x, cutoff, [&](const PairKey& key, const PairValue& value) {
        out.emplace_hint(out.end(), key, value);
    });
    return out;
}

/// The oracle for variable cutoffs (per-atom radii, a species table): brute force at `largest`
/// (at least every pair's cutoff), visiting the pairs with d < cutoff_of(i, j) in key order.
template <class CutoffOf, class Visit>
void for_each_brute_force_pair(const Box& box, const std::vector<Eigen::Vector3d>& x,
                               double largest, const CutoffOf& cutoff_of, const Visit& visit) {
    for_each_brute_force_pair(box, x, largest, [&](const PairKey& key, const PairValue& value) {
        if (value.distance < cutoff_of(std::get<0>(key), std::get<1>(key))) {
            visit(key, value);
        }
    });
}

template <class CutoffOf>
PairMap brute_force_pairs(const Box& box, const std::vector<Eigen::Vector3d>& x, double largest,
                          const CutoffOf& cutoff_of) {
    PairMap out;
    for_each_brute_force_pair(box, x, largest, cutoff_of,
                              [&](const PairKey& key, const PairValue& value) {
                                  out.emplace_hint(out.end(), key, value);
                              });
    return out;
}

/// Whether a pair is in the half list that the contract's canonical orientation keeps:
/// i < j, or i == j with S lexicographically positive.
inline bool in_canonical_half(const PairKey& key) {
    const auto& [i, j, a, b, c] = key;
    const bool positive = a > 0 || (a == 0 && (b > 0 || (b == 0 && c > 0)));
    return i < j || (i == j && positive);
}

/// The half list that the contract's canonical orientation keeps from a full list.
inline PairMap canonical_half(const PairMap& full) {
    PairMap out;
    for (const auto& [key, value] : full) {
        if (in_canonical_half(key)) {
            out.emplace_hint(out.end(), key, value);
        }
    }
    return out;
}

/// A stored neighbour list as a map (requires shifts, distances and vectors to be stored).
inline PairMap to_map(const NeighborList& list) {
    if (list.shifts().size() != 3 * list.size() || list.distances().size() != list.size() ||
        list.vectors().size() != 3 * list.size()) {
        throw std::logic_error("to_map needs shifts, distances and vectors stored");
    }
    PairMap out;
    for (std::size_t k = 0; k < list.size(); ++k) {
        const Shift s = list.shift(k);
        out[PairKey{list.i()[k], list.j()[k], s[0], s[1], s[2]}] =
            PairValue{list.distances()[k], list.vector(k)};
    }
    return out;
}

} // namespace tricell::testing
