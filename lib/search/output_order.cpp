#include "search/output_order.hpp"

#include <algorithm>
#include <numeric>
#include <vector>

namespace tricell::detail {

namespace {

// Fills columns.offsets from the count of pairs of each atom.
void count_offsets(PairColumns& columns, std::size_t atoms) {
    std::vector<std::size_t>& offsets = columns.offsets;
    offsets.assign(atoms + 1, 0);
    for (const std::uint32_t i : columns.i) {
        ++offsets[i + 1];
    }
    std::partial_sum(offsets.begin(), offsets.end(), offsets.begin());
}

// Fills columns.offsets and returns the stable permutation that groups the pairs by i.
std::vector<std::size_t> grouping(PairColumns& columns, std::size_t atoms) {
    count_offsets(columns, atoms);
    const PairArray<std::uint32_t>& is = columns.i;
    std::vector<std::size_t> perm(is.size());
    std::vector<std::size_t> cursor(columns.offsets.begin(), columns.offsets.end() - 1);
    for (std::size_t k = 0; k < is.size(); ++k) {
        perm[cursor[is[k]]++] = k;
    }
    return perm;
}

} // namespace

void group_pairs(PairColumns& columns, std::size_t atoms) {
    // Already grouped (a few atoms, or a search that met the atoms in order): nothing moves.
    if (std::is_sorted(columns.i.begin(), columns.i.end())) {
        count_offsets(columns, atoms);
        return;
    }
    columns.permute(grouping(columns, atoms));
}

void sort_pairs(PairColumns& columns, std::size_t atoms) {
    std::vector<std::size_t> perm = grouping(columns, atoms);
    const PairArray<std::uint32_t>& js = columns.j;
    const PairArray<std::int32_t>& ss = columns.shifts;
    auto before = [&](std::size_t l, std::size_t r) {
        if (js[l] != js[r]) {
            return js[l] < js[r];
        }
        for (std::size_t a = 0; a < 3; ++a) {
            if (ss[3 * l + a] != ss[3 * r + a]) {
                return ss[3 * l + a] < ss[3 * r + a];
            }
        }
        return false;
    };
    const std::vector<std::size_t>& offsets = columns.offsets;
    for (std::size_t i = 0; i < atoms; ++i) {
        std::sort(perm.begin() + std::ptrdiff_t(offsets[i]),
                  perm.begin() + std::ptrdiff_t(offsets[i + 1]), before);
    }
    columns.permute(perm);
}

} // namespace tricell::detail
