// compute_neighbors at several cutoffs: one search at the largest, then a stable counting sort
// of its pairs by shell (the index of the first cutoff above d; nothing to sort for one cutoff).
// Shell membership uses the stored d = sqrt(d_sq), and the search's own test at cutoff r is exactly
// sqrt(d_sq) < r (detail::strict_threshold_sq), so the prefix up to shell k is what a search at
// cutoffs[k] stores.
#include "tricell/analysis/shells.hpp"

#include <cmath>

#include "search/list_access.hpp"
#include "tricell/error.hpp"

namespace tricell {

ShellNeighborList compute_neighbors(const Box& box, PointsView positions,
                                    const std::vector<double>& cutoffs,
                                    const NeighborOptions& options) {
    if (cutoffs.empty()) {
        detail::fail<InvalidArgument>("cutoffs must hold at least one cutoff (got none)");
    }
    for (std::size_t k = 0; k < cutoffs.size(); ++k) {
        if (!(std::isfinite(cutoffs[k]) && cutoffs[k] > 0)) {
            detail::fail<InvalidArgument>("cutoffs[", k, "] must be finite and > 0 (got ",
                                          cutoffs[k], ")");
        }
        if (k > 0 && !(cutoffs[k] > cutoffs[k - 1])) {
            detail::fail<InvalidArgument>("cutoffs must increase strictly, but cutoffs[", k,
                                          "] = ", cutoffs[k], " follows cutoffs[", k - 1,
                                          "] = ", cutoffs[k - 1]);
        }
    }
    if (options.cutoff != 0) {
        detail::fail<InvalidArgument>(
            "NeighborOptions::cutoff must stay 0 when a list of cutoffs is given (got ",
            options.cutoff, ")");
    }
    if (options.variable_cutoff()) {
        detail::fail<InvalidArgument>("several cutoffs cannot be combined with "
                                      "NeighborOptions::radii or species_cutoffs");
    }

    NeighborOptions search = options;
    search.cutoff = cutoffs.back();
    search.quantities.distances = true; // the shells need d
    ShellNeighborList out;
    out.cutoffs = cutoffs;
    compute_neighbors(box, positions, search, out.pairs);

    NeighborList& list = out.pairs;
    const PairArray<double>& d = list.distances();
    const std::size_t pairs = list.size();
    // The shell of a pair: the first cutoff above d (a few cutoffs: a linear scan is fastest).
    const std::size_t last = cutoffs.size() - 1;
    const auto shell_of = [&](std::size_t p) {
        std::size_t k = 0;
        while (k < last && d[p] >= cutoffs[k]) {
            ++k;
        }
        return k;
    };
    out.offsets.assign(cutoffs.size() + 1, 0);
    for (std::size_t p = 0; p < pairs; ++p) {
        ++out.offsets[shell_of(p) + 1];
    }
    for (std::size_t k = 1; k < out.offsets.size(); ++k) {
        out.offsets[k] += out.offsets[k - 1];
    }
    PairColumns& columns = detail::ListAccess::columns(list);
    if (cutoffs.size() > 1) {
        std::vector<std::size_t> order(pairs);
        std::vector<std::size_t> next(out.offsets.begin(), out.offsets.end() - 1);
        for (std::size_t p = 0; p < pairs; ++p) {
            order[next[shell_of(p)]++] = p;
        }
        if (!options.quantities.distances) {
            columns.distances.clear(); // not asked for: not worth reordering
        }
        columns.permute(order);
        // (permute() leaves an empty column empty)
    }
    if (!options.quantities.distances) {
        columns.distances.clear();
    }
    columns.offsets.clear();
    return out;
}

} // namespace tricell
