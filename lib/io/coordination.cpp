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
        c.mean = std::numeric_limits<double>::quiet_NaN();
    }
    if (n == 0) {
        return out;
    }
    // The search counts each pair by its own cutoff: a species per element and a table with the
    // bond cutoff of each element pair given, the general cutoff (when > 0) for all others.
    std::map<std::string, std::int32_t> index;
    NeighborOptions neighbor_options;
    neighbor_options.species.resize(n);
    for (std::size_t k = 0; k < n; ++k) {
        neighbor_options.species[k] =
            index.emplace(structure.species[k], std::int32_t(index.size())).first->second;
    }
    std::map<std::pair<std::int32_t, std::int32_t>, double> table;
    for (const auto& [first, a] : index) {
        for (const auto& [second, b] : index) {
            if (a <= b && options.cutoff > 0) {
                table[{a, b}] = options.cutoff;
            }
        }
    }
    for (const BondCutoff& bond : options.bonds) {
        const auto a = index.find(element_symbol(bond.a));
        const auto b = index.find(element_symbol(bond.b));
        if (a != index.end() && b != index.end()) {
            table[std::minmax(a->second, b->second)] = bond.cutoff;
        }
    }
    if (table.empty()) {
        return out; // no bond given involves elements of this structure
    }
    for (const auto& [pair, cutoff] : table) {
        neighbor_options.species_cutoffs.push_back({pair.first, pair.second, cutoff});
    }
    neighbor_options.quantities.shifts = false;
    neighbor_options.quantities.distances = true;
    neighbor_options.quantities.vectors = false;
    neighbor_options.max_pairs = options.max_pairs;
    neighbor_options.max_bytes = options.max_bytes;
    const NeighborList list =
        compute_neighbors(structure.box, structure.positions, neighbor_options);
    std::vector<double> sum(n, 0.0);
    for (std::size_t p = 0; p < list.size(); ++p) {
        Coordination& c = out[list.i()[p]];
        const double d = list.distances()[p];
        ++c.count;
        sum[list.i()[p]] += d;
        if (!(c.nearest <= d)) {
            c.nearest = d;
        }
    }
    for (std::size_t k = 0; k < n; ++k) {
        if (out[k].count > 0) {
            out[k].mean = sum[k] / double(out[k].count);
        }
    }
    return out;
}

} // namespace tricell::io
