// docs/cpp.md, "The k nearest within the cutoff": the page's example as written, on diamond
// silicon slightly disordered (distinct distances) and perfect (exact ties); what it promises:
// each centre's edges nearest first, the first 12 of its full list in (d, j, S) order plus those
// within the tolerance of the 12th, each edge's reverse an edge too, 4 + 12 per atom when perfect.
#include "the_k_nearest_within_the_cutoff_includes.inc"

#include <algorithm>
#include <cstdint>
#include <random>
#include <set>
#include <tuple>
#include <vector>

#include "doc_check.hpp"
#include "silicon.hpp"

namespace {

using Edge = std::tuple<std::uint32_t, std::uint32_t, int, int, int>;

std::set<Edge> run(const tricell::Box& box, const std::vector<Eigen::Vector3d>& x,
                   std::vector<double>& last_distances) {
    std::set<Edge> edges;
    std::uint32_t centre = 0;
    double previous = 0;
    auto add_edge = [&](std::uint32_t i, std::uint32_t j, const tricell::Shift& S, double d) {
        if (i != centre) {
            centre = i;
            previous = 0;
        }
        DOC_CHECK(d >= previous, "each centre's edges nearest first");
        previous = d;
        edges.insert(Edge{i, j, S[0], S[1], S[2]});
        if (i == 0) {
            last_distances.push_back(d);
        }
    };

#include "the_k_nearest_within_the_cutoff_block.inc"

    DOC_CHECK(graph.size() == edges.size(), "every edge once");
    for (const auto& [i, j, a, b, c] : edges) {
        DOC_CHECK(edges.count(Edge{j, i, -a, -b, -c}) == 1,
                  "symmetric: (j, i, -S) kept wherever (i, j, S) is");
    }
    // The definition on the full list: each centre's first 12 by (d, j, S), those within 1e-6
    // of the 12th, and the reverses of all of them.
    tricell::NeighborOptions all;
    all.cutoff = 6.0;
    const tricell::NeighborList full = tricell::compute_neighbors(box, x, all);
    std::vector<std::vector<std::tuple<double, std::uint32_t, tricell::Shift>>> ranked(x.size());
    for (std::size_t k = 0; k < full.size(); ++k) {
        ranked[full.i()[k]].emplace_back(full.distances()[k], full.j()[k], full.shift(k));
    }
    std::set<Edge> expected;
    for (std::uint32_t i = 0; i < x.size(); ++i) {
        auto& pairs = ranked[i];
        std::sort(pairs.begin(), pairs.end(), [](const auto& l, const auto& r) {
            const tricell::Shift &ls = std::get<2>(l), &rs = std::get<2>(r);
            return std::make_tuple(std::get<0>(l), std::get<1>(l), ls[0], ls[1], ls[2]) <
                   std::make_tuple(std::get<0>(r), std::get<1>(r), rs[0], rs[1], rs[2]);
        });
        for (std::size_t t = 0; t < pairs.size(); ++t) {
            const auto& [d, j, S] = pairs[t];
            if (t < 12 || (pairs.size() > 12 && d <= std::get<0>(pairs[11]) + 1e-6)) {
                expected.insert(Edge{i, j, S[0], S[1], S[2]});
                expected.insert(Edge{j, i, -S[0], -S[1], -S[2]});
            }
        }
    }
    DOC_CHECK(edges == expected, "the first 12 by (d, j, S), the ties within 1e-6, the reverses");
    return edges;
}

} // namespace

int main() {
    const tricell::Box box = tricell::Box::from_rows(5.43 * Eigen::Matrix3d::Identity());
    std::vector<double> distances;
    const std::set<Edge> perfect = run(box, doc::silicon(), distances);
    DOC_CHECK(perfect.size() == 8 * 16 && distances.size() == 16 && distances[4] > 3.8,
              "perfect diamond: the 4 nearest and all 12 second neighbours of each atom");

    std::mt19937_64 rng(7);
    std::uniform_real_distribution<double> jiggle(-0.05, 0.05);
    std::vector<Eigen::Vector3d> x = doc::silicon();
    for (Eigen::Vector3d& r : x) {
        r += Eigen::Vector3d(jiggle(rng), jiggle(rng), jiggle(rng));
    }
    distances.clear();
    const std::set<Edge> disordered = run(box, x, distances);
    DOC_CHECK(distances.size() >= 12 && disordered.size() >= 8 * 12 && disordered.size() <= 8 * 16,
              "disordered: 12 per centre and some reverses, all within the first two shells");
    return 0;
}
