// docs/cpp.md, "Neighbour lists": the page's example as written, on diamond silicon placed far
// outside the box, then what it promises: every pair it hands to use() has D = x[j] - x[i] + H S
// with |D| < 5 in the half list's orientation, and there are as many as brute force finds.
#include "neighbour_lists_includes.inc"

#include <cstdint>

#include "doc_check.hpp"
#include "silicon.hpp"

int main() {
    // The page's placeholders: your positions, and what you do with each pair.
    auto load_positions = [] {
        auto x = doc::silicon();
        x[3] += Eigen::Vector3d(40 * 5.43, -17 * 5.43, 3 * 5.43); // many boxes away
        return x;
    };
    std::size_t used = 0;
    std::vector<Eigen::Vector3d> seen_x;
    auto use = [&](std::uint32_t i, std::uint32_t j, const tricell::Shift& S, double d) {
        const auto x = load_positions();
        const Eigen::Vector3d D = x[j] - x[i] + 5.43 * S.cast<double>();
        DOC_CHECK(std::abs(D.norm() - d) < 1e-9, "D = x[j] - x[i] + H S and d = |D|");
        DOC_CHECK(d < 5.0, "pairs with |D| < 5");
        DOC_CHECK(
            i < j || (i == j && (S[0] > 0 || (S[0] == 0 && (S[1] > 0 || (S[1] == 0 && S[2] > 0))))),
            "half list: i < j, or i == j with S > 0 lexicographically");
        ++used;
    };

#include "neighbour_lists_block.inc"

    const std::size_t full = doc::brute_force_pairs(box, load_positions(), 5.0, 2);
    DOC_CHECK(used == list.size() && 2 * used == full, "each pair once: half the full list");
    return 0;
}
