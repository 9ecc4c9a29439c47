// Moment-balanced boundaries on a gas-liquid system: the moment model evens out the estimated
// work better than equal atoms and equal volume, boundaries stay valid and identical on every
// rank, and the lists are still the serial ones after rebalancing. Run under mpirun.
#include <random>

#include <gtest/gtest.h>

#include "mpi_support.hpp"
#include "policy/cost_model.hpp"
#include "support/expect_throw_msg.hpp"
#include "tricell/error.hpp"

namespace {

using tricell::Box;
using namespace tricell::testing;
using tricell::mpi::BalanceRule;

// Liquid (0.8) in the first third along a, gas (0.05) elsewhere, in a skewed box.
std::vector<Eigen::Vector3d> gas_liquid(const Box& box, std::uint64_t seed) {
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> unit(0, 1);
    std::vector<Eigen::Vector3d> x;
    const double volume = box.volume();
    for (int phase = 0; phase < 2; ++phase) {
        const double lo = phase == 0 ? 0 : 1.0 / 3, hi = phase == 0 ? 1.0 / 3 : 1;
        const auto n = std::size_t((phase == 0 ? 0.8 : 0.05) * volume * (hi - lo));
        for (std::size_t a = 0; a < n; ++a) {
            const Eigen::Vector3d s(lo + (hi - lo) * unit(rng), unit(rng), unit(rng));
            x.push_back(box.matrix() * s);
        }
    }
    return x;
}

double max_over_mean(const std::vector<double>& v) {
    double max = 0, sum = 0;
    for (double w : v) {
        max = std::max(max, w);
        sum += w;
    }
    return max / (sum / double(v.size()));
}

TEST(MpiBalance, WorkModel_ValidatesItsCosts) {
    tricell::mpi::WorkModel model;
    model.costs.per_atom = -1;
    EXPECT_THROW_MSG(model.validate(), tricell::InvalidArgument,
                     "WorkModel::costs.per_atom must be >= 0 (got -1)");
}

// The domains share the cells: the total estimate does not depend on where the boundaries are,
// and on one domain it is region_work of every cell.
TEST(MpiBalance, RankWork_SharesTheCellsWork) {
    const Box box = Box::from_lammps(30, 10, 10, 2, -1, 1);
    const std::vector<Eigen::Vector3d> x = gas_liquid(box, 9);
    tricell::mpi::Decomposition d(MPI_COMM_WORLD);
    const tricell::mpi::LocalAtoms atoms = deal(x);
    auto total = [&] {
        double sum = 0;
        for (double w : tricell::mpi::estimate_rank_work(d, box, atoms.points(), 2.0)) {
            sum += w;
        }
        return sum;
    };
    const double uniform = total();
    tricell::mpi::balance(d, box, atoms.points(), 2.0, BalanceRule::moments);
    EXPECT_NEAR(total(), uniform, 1e-9 * uniform);
    // The sum over the cells (about one cutoff per axis) of region_work of each.
    int n[3];
    for (int k = 0; k < 3; ++k) {
        n[k] = std::max(1, int(std::floor(box.perpendicular_widths()[k] / 2.0)));
    }
    std::vector<double> counts(std::size_t(n[0] * n[1] * n[2]), 0.0);
    for (const Eigen::Vector3d& p : x) {
        const tricell::Fractional s = box.wrap(box.to_fractional(tricell::Cartesian(p))).wrapped;
        int c[3];
        for (int k = 0; k < 3; ++k) {
            c[k] = std::min(n[k] - 1, int(std::floor(s[k] * n[k])));
        }
        counts[std::size_t((c[0] * n[1] + c[1]) * n[2] + c[2])] += 1;
    }
    double expected = 0;
    for (double v : counts) {
        tricell::OccupancyMoments one;
        one.add(v);
        expected += tricell::region_work(one, 27);
    }
    EXPECT_NEAR(uniform, expected, 1e-9 * expected);
}

TEST(MpiBalance, GasLiquid_MomentsBalanceBestAndListsStayExact) {
    const Box box = Box::from_lammps(30, 10, 10, 2, -1, 1);
    const double cutoff = 2.0;
    const std::vector<Eigen::Vector3d> x = gas_liquid(box, 5);
    tricell::mpi::Decomposition d(MPI_COMM_WORLD, {{world_size(), 1, 1}});
    double spread[3] = {0, 0, 0};
    for (BalanceRule rule :
         {BalanceRule::equal_volume, BalanceRule::equal_atoms, BalanceRule::moments}) {
        SCOPED_TRACE(int(rule));
        tricell::mpi::LocalAtoms atoms = deal(x);
        tricell::mpi::balance(d, box, atoms.points(), cutoff, rule);
        const std::vector<double>& b = d.bounds(0);
        ASSERT_EQ(b.size(), std::size_t(world_size()) + 1);
        for (std::size_t k = 1; k < b.size(); ++k) {
            EXPECT_GT(b[k], b[k - 1]);
        }
        EXPECT_TRUE(agreed_bounds(d));
        tricell::mpi::migrate(d, box, atoms);
        spread[int(rule)] =
            max_over_mean(tricell::mpi::estimate_rank_work(d, box, atoms.points(), cutoff));
        for (bool half : {false, true}) {
            tricell::NeighborOptions options;
            options.cutoff = cutoff;
            options.half = half;
            options.quantities = tricell::Quantities{true, true, true};
            const auto pairs = tricell::mpi::compute_neighbors(d, box, atoms, options);
            EXPECT_EQ(compare_with_serial(pairs, atoms, box, options, d.comm()), "");
        }
    }
    if (world_size() > 1) {
        EXPECT_GT(spread[0], 1.5);       // equal volume: the liquid ranks carry it
        EXPECT_LT(spread[2], spread[1]); // moments beat equal atoms
        EXPECT_LT(spread[2], 1.25);      // and come close to even
    } else {
        EXPECT_DOUBLE_EQ(spread[2], 1.0);
    }
}

} // namespace
