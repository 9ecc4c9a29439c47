// Which pairs count: within one cutoff, or, when the cutoff varies, within per-atom radii
// (d < r_i + r_j) or a per-species-pair table (d < r(s_i, s_j); a missing species pair never
// counts). The scan tests every candidate against the largest cutoff first, through the strict
// threshold of the distance kernel (distance_kernel.hpp); a variable rule then decides.
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "tricell/neighbor_list.hpp"

namespace tricell::detail {

class CutoffRule {
  public:
    /// Validates radii / species against the atom count and builds the lookup tables.
    void set(const NeighborOptions& options, std::size_t atom_count);
    bool uniform() const { return kind_ == Kind::uniform; }
    /// The largest cutoff any pair can have (0: no pair can count).
    double max_cutoff() const { return max_cutoff_; }
    /// The scan's threshold: d^2 below it exactly when d < max_cutoff() (0 when that is 0).
    double threshold_sq() const { return threshold_sq_max_; }
    /// For a candidate already within max_cutoff(): does it count?
    bool accepts(std::uint32_t i, std::uint32_t j, double d_sq) const {
        if (kind_ == Kind::radii) {
            return std::sqrt(d_sq) < radii_[i] + radii_[j];
        }
        return d_sq < threshold_sq_[std::size_t(species_index_[i]) * kinds_ +
                                    std::size_t(species_index_[j])];
    }

  private:
    enum class Kind { uniform, radii, species };
    Kind kind_ = Kind::uniform;
    double max_cutoff_ = 0;
    double threshold_sq_max_ = 0;
    std::vector<double> radii_;
    std::vector<std::uint32_t> species_index_; // dense index of each atom's species
    std::size_t kinds_ = 0;
    std::vector<double> threshold_sq_; // kinds_ x kinds_ strict thresholds (0: never)
};

} // namespace tricell::detail
