// Load balance of the thread split: how evenly three rules divide a gas-liquid system's work.
//
// The system is a liquid slab (0.1 atoms/A^3) filling 20% of a 200 x 40 x 40 A box along a,
// with gas at 0.002 atoms/A^3 (density ratio 50) elsewhere, rc 5. The units the threads split
// (cells, in visiting order) are cut into T contiguous chunks by equal cells, equal atoms and
// equal occupancy-moment work (cost_model.hpp, what NeighborSearch::compute uses), and each
// chunk's real work is the distance tests its candidates cost (NeighborSearch::unit_work). The
// program prints max/mean of that real work per chunk for each rule; 1.0 is perfect balance.
//
//     build/benchmarks/work_split [backend]
#include <algorithm>
#include <cstdio>
#include <numeric>
#include <random>
#include <string>
#include <vector>

#include "policy/cost_model.hpp"
#include <tricell/neighbor_list.hpp>

namespace {

// max / mean of the measured work over the chunks `bounds` defines.
double imbalance(const std::vector<double>& measured, const std::vector<std::size_t>& bounds) {
    std::vector<double> chunk;
    for (std::size_t t = 0; t + 1 < bounds.size(); ++t) {
        chunk.push_back(std::accumulate(measured.begin() + std::ptrdiff_t(bounds[t]),
                                        measured.begin() + std::ptrdiff_t(bounds[t + 1]), 0.0));
    }
    const double mean = std::accumulate(chunk.begin(), chunk.end(), 0.0) / double(chunk.size());
    return *std::max_element(chunk.begin(), chunk.end()) / mean;
}

} // namespace

int main(int argc, char** argv) {
    const double la = 200, lb = 40, lc = 40;
    std::mt19937_64 rng(2026);
    std::uniform_real_distribution<double> unit(0, 1);
    std::vector<Eigen::Vector3d> x;
    const auto liquid = std::size_t(0.1 * la * 0.2 * lb * lc);
    const auto gas = std::size_t(0.002 * la * 0.8 * lb * lc);
    for (std::size_t k = 0; k < liquid + gas; ++k) {
        const double a = k < liquid ? 0.2 * unit(rng) : 0.2 + 0.8 * unit(rng);
        x.emplace_back(a * la, unit(rng) * lb, unit(rng) * lc);
    }
    const tricell::Box box = tricell::Box::from_lammps(la, lb, lc, 0, 0, 0);
    tricell::NeighborOptions options;
    options.cutoff = 5;
    options.backend = tricell::parse_backend(argc > 1 ? argv[1] : "auto");
    tricell::NeighborSearch search;
    search.build(box, x, options);
    const tricell::UnitWork work = search.unit_work();
    std::printf("gas-liquid slab: %zu liquid + %zu gas atoms, rc 5, backend %s, %zu units\n",
                liquid, gas, tricell::backend_name(search.info().backend), work.atoms.size());
    std::printf("%8s %12s %12s %12s\n", "chunks", "equal cells", "equal atoms", "moments");
    for (const std::size_t threads : {2, 4, 8, 16}) {
        const std::vector<double> cells(work.atoms.size(), 1.0);
        std::printf("%8zu %12.3f %12.3f %12.3f\n", threads,
                    imbalance(work.measured, tricell::split_work(cells, threads)),
                    imbalance(work.measured, tricell::split_work(work.atoms, threads)),
                    imbalance(work.measured, tricell::split_work(work.estimated, threads)));
    }
    return 0;
}
