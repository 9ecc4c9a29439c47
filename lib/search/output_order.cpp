#include "search/output_order.hpp"

#include <algorithm>
#include <numeric>
#include <vector>

namespace tricell::detail {

void sort_pairs(PairColumns& columns, std::size_t atoms) {
    const PairArray<std::uint32_t>& is = columns.i;
    const PairArray<std::uint32_t>& js = columns.j;
    const PairArray<std::int32_t>& ss = columns.shifts;
    std::vector<std::size_t>& offsets = columns.offsets;
    const std::size_t pairs = is.size();
    offsets.assign(atoms + 1, 0);
    for (const std::uint32_t i : is) {
        ++offsets[i + 1];
    }
    std::partial_sum(offsets.begin(), offsets.end(), offsets.begin());
    std::vector<std::size_t> perm(pairs);
    std::vector<std::size_t> cursor(offsets.begin(), offsets.end() - 1);
    for (std::size_t k = 0; k < pairs; ++k) {
        perm[cursor[is[k]]++] = k;
    }
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
    for (std::size_t i = 0; i < atoms; ++i) {
        std::sort(perm.begin() + std::ptrdiff_t(offsets[i]),
                  perm.begin() + std::ptrdiff_t(offsets[i + 1]), before);
    }
    columns.permute(perm);
}

} // namespace tricell::detail
