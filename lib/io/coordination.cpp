#include "tricell/io/coordination.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>

#include "tricell/error.hpp"
#include "tricell/neighbor_list.hpp"

namespace tricell::io {

namespace {

std::string canonical(const std::string& element, const BondCutoff& bond) {
    std::string symbol = element_symbol(element);
    if (symbol.empty()) {
        tricell::detail::fail<InvalidArgument>("bond ", bond.a, "-", bond.b, ": unknown element '",
                                               element, "'");
    }
    return symbol;
}

std::pair<std::string, std::string> ordered(std::string a, std::string b) {
    if (b < a) {
        std::swap(a, b);
    }
    return {a, b};
}

} // namespace

void CoordinationOptions::validate() const {
    if (!(std::isfinite(cutoff) && cutoff >= 0)) {
        tricell::detail::fail<InvalidArgument>("cutoff must be finite and >= 0 (got ", cutoff, ")");
    }
    std::map<std::pair<std::string, std::string>, double> seen;
    for (const BondCutoff& bond : bonds) {
        const auto key = ordered(canonical(bond.a, bond), canonical(bond.b, bond));
        if (!(std::isfinite(bond.cutoff) && bond.cutoff > 0)) {
            tricell::detail::fail<InvalidArgument>("bond ", bond.a, "-", bond.b,
                                                   ": cutoff must be > 0 (got ", bond.cutoff, ")");
        }
        if (!seen.emplace(key, bond.cutoff).second) {
            tricell::detail::fail<InvalidArgument>("bond ", key.first, "-", key.second,
                                                   " is given twice");
        }
    }
    if (cutoff == 0 && bonds.empty()) {
        tricell::detail::fail<InvalidArgument>(
            "no cutoff: give a cutoff for all pairs or per-element-pair bond cutoffs");
    }
}

std::vector<Coordination> coordination(const Structure& structure,
                                       const CoordinationOptions& options) {
    options.validate();
    const std::size_t n = structure.size();
    std::vector<Coordination> out(n);
    for (Coordination& c : out) {
        c.nearest = std::numeric_limits<double>::quiet_NaN();
    }

    // Species indices and a small table of squared cutoffs per pair of species.
    std::map<std::string, std::size_t> index;
    std::vector<std::size_t> species(n);
    for (std::size_t k = 0; k < n; ++k) {
        species[k] = index.emplace(structure.species[k], index.size()).first->second;
    }
    const std::size_t m = index.size();
    std::vector<double> cutoff(m * m, options.cutoff);
    double search = options.cutoff;
    for (const BondCutoff& bond : options.bonds) {
        const auto a = index.find(element_symbol(bond.a));
        const auto b = index.find(element_symbol(bond.b));
        search = std::max(search, bond.cutoff);
        if (a != index.end() && b != index.end()) {
            cutoff[a->second * m + b->second] = bond.cutoff;
            cutoff[b->second * m + a->second] = bond.cutoff;
        }
    }
    if (n == 0) {
        return out;
    }

    NeighborOptions neighbor_options;
    neighbor_options.cutoff = search;
    neighbor_options.quantities.shifts = false;
    neighbor_options.quantities.distances = true;
    neighbor_options.quantities.vectors = false;
    neighbor_options.max_pairs = options.max_pairs;
    const NeighborList list =
        compute_neighbors(structure.box, structure.positions, neighbor_options);
    for (std::size_t p = 0; p < list.size(); ++p) {
        const std::size_t i = list.i()[p];
        const std::size_t j = list.j()[p];
        const double d = list.distances()[p];
        if (d < cutoff[species[i] * m + species[j]]) {
            Coordination& c = out[i];
            ++c.count;
            if (!(c.nearest <= d)) {
                c.nearest = d;
            }
        }
    }
    return out;
}

} // namespace tricell::io
