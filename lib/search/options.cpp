// Validation of NeighborOptions: every field checked in one place, each message naming the field
// and the value it got.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <map>
#include <utility>

#include "detail/parallel.hpp"
#include "search/options.hpp"
#include "search/registry.hpp"
#include "tricell/error.hpp"
#include "tricell/neighbor_list.hpp"

namespace tricell {

void NeighborOptions::validate() const {
    if (!std::isfinite(cutoff)) {
        detail::fail<InvalidArgument>("cutoff must be finite (got ", cutoff, ")");
    }
    if (!radii.empty() && !species_cutoffs.empty()) {
        detail::fail<InvalidArgument>("set radii or species_cutoffs, not both");
    }
    if (variable_cutoff()) {
        if (cutoff != 0) {
            detail::fail<InvalidArgument>("cutoff must be 0 when ",
                                          radii.empty() ? "species_cutoffs" : "radii",
                                          " decide which pairs count (got ", cutoff, ")");
        }
    } else if (!(cutoff > 0)) {
        detail::fail<InvalidArgument>("cutoff must be > 0 (got ", cutoff, ")");
    }
    for (std::size_t k = 0; k < radii.size(); ++k) {
        if (!(std::isfinite(radii[k]) && radii[k] >= 0)) {
            detail::fail<InvalidArgument>("radii[", k, "] must be finite and >= 0 (got ", radii[k],
                                          ")");
        }
    }
    if (!species.empty() && species_cutoffs.empty()) {
        detail::fail<InvalidArgument>("species is set but species_cutoffs is empty");
    }
    std::map<std::pair<std::int32_t, std::int32_t>, double> seen;
    for (std::size_t k = 0; k < species_cutoffs.size(); ++k) {
        const SpeciesCutoff& e = species_cutoffs[k];
        if (!(std::isfinite(e.cutoff) && e.cutoff > 0)) {
            detail::fail<InvalidArgument>("species_cutoffs[", k, "] (species ", e.a, "-", e.b,
                                          ") must be finite and > 0 (got ", e.cutoff, ")");
        }
        const auto key = std::minmax(e.a, e.b);
        const auto [it, fresh] = seen.emplace(key, e.cutoff);
        if (!fresh && it->second != e.cutoff) {
            detail::fail<InvalidArgument>("species pair ", e.a, "-", e.b,
                                          " has two cutoffs in species_cutoffs (", it->second,
                                          " and ", e.cutoff, ")");
        }
    }
    if (!(std::isfinite(cells_per_cutoff) && (cells_per_cutoff == 0 || cells_per_cutoff >= 1))) {
        detail::fail<InvalidArgument>(
            "cells_per_cutoff must be 0 (chosen by the search) or >= 1 (got ", cells_per_cutoff,
            ")");
    }
    if (threads < 0 || threads > 1024) {
        detail::fail<InvalidArgument>("threads must be in [0, 1024] (got ", threads, ")");
    }
    if (max_cells > (std::size_t(1) << 31)) {
        detail::fail<InvalidArgument>("max_cells must be at most 2^31 (got ", max_cells, ")");
    }
    if (hash_table_size > (std::size_t(1) << 31)) {
        detail::fail<InvalidArgument>("hash_table_size must be at most 2^31 (got ", hash_table_size,
                                      ")");
    }
    if (leaf_size > (std::size_t(1) << 20)) {
        detail::fail<InvalidArgument>("leaf_size must be at most 2^20 (got ", leaf_size, ")");
    }
    if (!(std::isfinite(tie_tolerance) && tie_tolerance >= 0)) {
        detail::fail<InvalidArgument>("tie_tolerance must be finite and >= 0 (got ", tie_tolerance,
                                      ")");
    }
    if (max_neighbors == 0 && (tie_tolerance != 0 || symmetric)) {
        detail::fail<InvalidArgument>(symmetric ? "symmetric" : "tie_tolerance",
                                      " applies to the nearest pairs kept: set max_neighbors too");
    }
    if (max_neighbors != 0) {
        if (half) {
            detail::fail<InvalidArgument>("max_neighbors keeps the nearest pairs of each centre "
                                          "of a full list: half must be false");
        }
        if (sorted) {
            detail::fail<InvalidArgument>(
                "max_neighbors orders each centre's pairs by distance (d, j, S): sorted (by j, "
                "S) cannot be asked with it");
        }
        if (symmetric && query) {
            detail::fail<InvalidArgument>(
                "symmetric needs every atom's pairs (the other end of a kept pair decides): "
                "query cannot be asked with it");
        }
    }
    if (detail::find_backend(backend) == nullptr) {
        detail::fail<InvalidArgument>("backend must be one of ", backend_choices(),
                                      " (got the value ", static_cast<int>(backend), ")");
    }
}

void detail::check_positions(PointsView positions, std::size_t threads) {
    const std::size_t n = positions.size();
    if (n >= std::size_t(std::numeric_limits<std::int32_t>::max())) {
        fail<InvalidArgument>("at most ", std::numeric_limits<std::int32_t>::max() - 1,
                              " positions are supported (got ", n, ")");
    }
    if (n > 0 && positions.data == nullptr) {
        fail<InvalidArgument>("positions: null data for ", n, " points");
    }
    parallel_ranges(n, threads, [&](std::size_t begin, std::size_t end, std::size_t) {
        for (std::size_t i = begin; i < end; ++i) {
            const Eigen::Vector3d r = positions[i];
            if (!r.allFinite()) {
                fail<InvalidArgument>("position ", i, " is not finite (got ", r.x(), ", ", r.y(),
                                      ", ", r.z(), ")");
            }
        }
    });
}

std::vector<std::uint8_t> detail::query_flags(const NeighborOptions& options, std::size_t n) {
    std::vector<std::uint8_t> flags;
    if (!options.query) {
        return flags;
    }
    const std::vector<std::uint32_t>& query = *options.query;
    flags.assign(n, 0);
    for (std::size_t k = 0; k < query.size(); ++k) {
        const std::uint32_t q = query[k];
        if (q >= n) {
            fail<InvalidArgument>("query[", k, "] is ", q, ", not the index of one of the ", n,
                                  " positions");
        }
        if (flags[q] != 0) {
            fail<InvalidArgument>("query[", k, "] is ", q, ", which the query already holds");
        }
        flags[q] = 1;
    }
    if (query.size() == n) {
        flags.clear(); // every point: the ordinary search
    }
    return flags;
}

} // namespace tricell
