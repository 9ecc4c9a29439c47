// The reference search of verify(): the pairs (i, j, S) of a box, positions and options found
// by a method independent of the list under test (see reference.cpp).
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "scan/half_orientation.hpp"
#include "tricell/box.hpp"
#include "tricell/neighbor_list.hpp"
#include "tricell/types.hpp"

namespace tricell::detail {

/// (i, j, Sa, Sb, Sc): the identity of one entry of a list.
using PairKey = std::array<std::int64_t, 5>;

/// The cutoff of each atom pair under NeighborOptions (uniform, radii or a species table), read
/// from the options as the contract states it.
class PairCutoff {
  public:
    explicit PairCutoff(const NeighborOptions& options);
    double operator()(std::size_t i, std::size_t j) const;
    /// At least every pair's cutoff.
    double largest() const { return largest_; }

  private:
    const NeighborOptions& options_;
    std::vector<std::int32_t> kinds_; // species, as indices into table_
    std::vector<double> table_;       // kind x kind cutoffs, 0 for a missing pair
    std::size_t kind_count_ = 0;
    double largest_ = 0;
};

/// The reference's pairs as sorted keys, full or half (i < j, or i == j with S positive) as
/// options.half asks, and the name of the method that found them.
struct ReferencePairs {
    std::vector<PairKey> keys;
    std::string method;
};

/// Brute force when N^2 times the images per pair is within brute_force_budget, else the search
/// with a backend the automatic choice does not take.
ReferencePairs reference_pairs(const Box& box, PointsView positions, const NeighborOptions& options,
                               const PairCutoff& cutoff);

/// Whether (i, j, S) is the orientation of a half list (scan/half_orientation.hpp).
inline bool canonical_orientation(const PairKey& key) {
    return half_orientation(key[0], key[1], key[2], key[3], key[4]);
}

} // namespace tricell::detail
