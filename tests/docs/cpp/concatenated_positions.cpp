// docs/cpp.md, "Concatenated positions": the page's example as written, on a molecule with an
// all-zero cell, a crystal and a slab in one N_total x 3 array; every pair's i and j must be rows
// of that array within one system, and each system's pairs those it gets alone.
#include "concatenated_positions_includes.inc"

#include <vector>

#include "doc_check.hpp"
#include "silicon.hpp"

int main() {
    std::vector<double> positions;
    std::vector<std::size_t> batch_ptr{0};
    std::vector<Eigen::Matrix3d> cells;
    std::vector<tricell::Periodicity> pbc;
    const auto add = [&](const std::vector<Eigen::Vector3d>& x, const Eigen::Matrix3d& rows,
                         tricell::Periodicity periodic) {
        for (const Eigen::Vector3d& r : x) {
            positions.insert(positions.end(), {r.x(), r.y(), r.z()});
        }
        batch_ptr.push_back(batch_ptr.back() + x.size());
        cells.push_back(rows);
        pbc.push_back(periodic);
    };
    add({{0, 0, 0}, {0.96, 0, 0}, {-0.24, 0.93, 0}}, Eigen::Matrix3d::Zero(),
        tricell::Periodicity::none()); // water, no cell
    add(doc::silicon(), 5.43 * Eigen::Matrix3d::Identity(), tricell::Periodicity::all());
    Eigen::Matrix3d slab = 5.43 * Eigen::Matrix3d::Identity();
    slab(2, 2) = 0; // open along c, no vector there
    add(doc::silicon(), slab, tricell::Periodicity{{true, true, false}});

#include "concatenated_positions_block.inc"

    DOC_CHECK(out.structure_count() == 3, "three systems");
    for (std::size_t s = 0; s < 3; ++s) {
        const tricell::Box box = tricell::Box::from_rows(cells[s], pbc[s]);
        const tricell::NeighborList alone =
            tricell::compute_neighbors(box,
                                       tricell::PointsView(positions.data() + 3 * batch_ptr[s],
                                                           batch_ptr[s + 1] - batch_ptr[s]),
                                       options);
        const std::size_t first = out.pair_offsets()[s];
        DOC_CHECK(out.pair_offsets()[s + 1] - first == alone.size() && alone.size() > 0,
                  "each system's pairs are those it gets alone");
        for (std::size_t k = 0; k < alone.size(); ++k) {
            const std::uint32_t i = out.i()[first + k], j = out.j()[first + k];
            DOC_CHECK(i == alone.i()[k] + batch_ptr[s] && j == alone.j()[k] + batch_ptr[s] &&
                          j < batch_ptr[s + 1],
                      "i and j are rows of the one array, within the system");
            const Eigen::Vector3d D = Eigen::Vector3d(&positions[3 * j]) -
                                      Eigen::Vector3d(&positions[3 * i]) +
                                      box.matrix() * out.columns().shift(k + first).cast<double>();
            DOC_CHECK(std::abs(D.norm() - out.distances()[first + k]) < 1e-9,
                      "D = x_j - x_i + H S from the one array");
        }
    }
    return 0;
}
