// docs/cpp.md, "Batches of small structures": the page's example as written, on three small
// cells; each structure's pairs must be exactly those compute_neighbors() gives it alone.
#include "batches_of_small_structures_includes.inc"

#include <vector>

#include "doc_check.hpp"
#include "silicon.hpp"

int main() {
    struct Structure {
        tricell::Box box;
        std::vector<Eigen::Vector3d> positions;
    };
    const std::vector<Structure> structures = {
        {tricell::Box::from_parameters(5.43, 5.43, 5.43, 90, 90, 90), doc::silicon()},
        {tricell::Box::from_parameters(5.6, 5.6, 5.6, 90, 90, 90), doc::silicon(5.6)},
        {tricell::Box::from_parameters(4.0, 4.5, 5.0, 80, 95, 105),
         {{0, 0, 0}, {1.1, 2.0, 0.3}, {2.5, 0.4, 3.9}}},
    };
    std::vector<std::size_t> used(structures.size(), 0);
    auto use = [&](std::size_t s, std::uint32_t i, std::uint32_t j, const std::int32_t* shift,
                   double d) {
        const auto& x = structures[s].positions;
        const Eigen::Vector3d D =
            x[j] - x[i] +
            structures[s].box.matrix() * Eigen::Vector3d(shift[0], shift[1], shift[2]);
        DOC_CHECK(std::abs(D.norm() - d) < 1e-9 && d < 5.0, "pairs of s within the cutoff");
        ++used[s];
    };

#include "batches_of_small_structures_block.inc"

    for (std::size_t s = 0; s < structures.size(); ++s) {
        tricell::NeighborOptions alone;
        alone.cutoff = 5.0;
        const auto list =
            tricell::compute_neighbors(structures[s].box, structures[s].positions, alone);
        DOC_CHECK(used[s] == list.size(), "each structure gets the list it gets alone");
        const std::size_t first = out.pair_offsets()[s];
        for (std::size_t k = 0; k < list.size(); ++k) {
            DOC_CHECK(out.i()[first + k] == list.i()[k] && out.j()[first + k] == list.j()[k] &&
                          out.distances()[first + k] == list.distances()[k],
                      "same pairs, same order, same bits");
        }
    }
    return 0;
}
