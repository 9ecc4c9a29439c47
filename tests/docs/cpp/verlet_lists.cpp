// docs/cpp.md, "Verlet lists": the page's example as written, over atoms that move a little and
// a box that shears a little each step; after every update() the pairs must be those within the
// cutoff, as many as a fresh search finds.
#include "verlet_lists_includes.inc"

#include <random>
#include <vector>

#include <tricell/tricell.hpp>

#include "doc_check.hpp"

int main() {
    std::mt19937 random(7);
    std::uniform_real_distribution<double> uniform(0.0, 1.0);
    auto box = tricell::Box::from_parameters(9.0, 9.5, 10.0, 85, 95, 100);
    std::vector<Eigen::Vector3d> x;
    for (int k = 0; k < 80; ++k) {
        x.push_back(box.to_cartesian(
            tricell::Fractional(uniform(random), uniform(random), uniform(random))));
    }
    const int steps = 40;
    auto advance = [&](std::vector<Eigen::Vector3d>& points, tricell::Box& b) {
        for (auto& p : points) {
            p += 0.04 * Eigen::Vector3d(uniform(random) - 0.5, uniform(random) - 0.5,
                                        uniform(random) - 0.5);
        }
        Eigen::Matrix3d h = b.matrix();
        h(0, 1) += 0.01; // a small shear each step
        b = tricell::Box::from_columns(h);
    };
    std::size_t forces = 0;
    auto force = [&](std::uint32_t i, std::uint32_t j, const Eigen::Vector3d& D) {
        DOC_CHECK(i < x.size() && j < x.size() && D.norm() < 2.5, "pairs with |D| < 2.5");
        ++forces;
    };

#include "verlet_lists_block.inc"

    tricell::NeighborOptions fresh;
    fresh.cutoff = 2.5;
    fresh.half = true;
    DOC_CHECK(list.pairs().size() == tricell::compute_neighbors(box, x, fresh).size(),
              "after update(), exactly the pairs within the cutoff");
    DOC_CHECK(forces > 0, "the loop visited pairs");
    return 0;
}
