#include "scan/cutoff_rule.hpp"

#include <algorithm>
#include <cmath>
#include <map>

#include "scan/distance_kernel.hpp"
#include "tricell/error.hpp"

namespace tricell::detail {

void CutoffRule::set(const NeighborOptions& options, std::size_t atom_count) {
    radii_.clear();
    species_index_.clear();
    threshold_sq_.clear();
    kinds_ = 0;
    if (!options.radii.empty()) {
        if (options.radii.size() != atom_count) {
            fail<InvalidArgument>("radii has ", options.radii.size(), " entries for ", atom_count,
                                  " positions");
        }
        kind_ = Kind::radii;
        radii_ = options.radii;
        const double largest = *std::max_element(radii_.begin(), radii_.end());
        max_cutoff_ = 2 * largest;
    } else if (!options.species_cutoffs.empty()) {
        if (options.species.size() != atom_count) {
            fail<InvalidArgument>("species has ", options.species.size(), " entries for ",
                                  atom_count, " positions");
        }
        kind_ = Kind::species;
        // Dense indices of the species that occur; table entries of absent species are inert.
        std::map<std::int32_t, std::uint32_t> index;
        for (const std::int32_t s : options.species) {
            index.emplace(s, 0);
        }
        for (auto& entry : index) {
            entry.second = std::uint32_t(kinds_++);
        }
        species_index_.resize(atom_count);
        for (std::size_t i = 0; i < atom_count; ++i) {
            species_index_[i] = index[options.species[i]];
        }
        threshold_sq_.assign(kinds_ * kinds_, 0.0); // d_sq < 0 never holds: no cutoff
        max_cutoff_ = 0;
        for (const SpeciesCutoff& entry : options.species_cutoffs) {
            const auto a = index.find(entry.a);
            const auto b = index.find(entry.b);
            if (a == index.end() || b == index.end()) {
                continue;
            }
            const double t = strict_threshold_sq(entry.cutoff);
            threshold_sq_[a->second * kinds_ + b->second] = t;
            threshold_sq_[b->second * kinds_ + a->second] = t;
            max_cutoff_ = std::max(max_cutoff_, entry.cutoff);
        }
    } else {
        kind_ = Kind::uniform;
        max_cutoff_ = options.cutoff;
    }
    threshold_sq_max_ = max_cutoff_ > 0 ? strict_threshold_sq(max_cutoff_) : 0;
}

} // namespace tricell::detail
