// NeighborOptions::max_bytes: a list whose memory at its peak (the model of docs/memory.md,
// detail::list_memory) would pass the limit is refused, from the estimate in build() before
// anything proportional to the pairs is allocated, or while it is written when it outgrows its
// estimate, leaving the output empty; a list just within the limit runs and is the unlimited
// list. The limits here are a few hundred kilobytes: nothing large is allocated.
#include <cmath>
#include <cstdint>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "policy/list_limits.hpp"
#include "scan/pair_sink.hpp"
#include "tricell/batch.hpp"
#include "tricell/error.hpp"
#include "tricell/neighbor_list.hpp"

using tricell::Box;
using tricell::NeighborList;
using tricell::NeighborOptions;
using tricell::NeighborSearch;
using tricell::PairLimitError;

namespace {

// n uniform random atoms in a triclinic cell about `edge` wide.
std::vector<Eigen::Vector3d> uniform_atoms(std::size_t n, double edge, std::uint64_t seed) {
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> u(0, edge);
    std::vector<Eigen::Vector3d> x(n);
    for (Eigen::Vector3d& p : x) {
        p = Eigen::Vector3d(u(rng), u(rng), u(rng));
    }
    return x;
}

const Box cell = Box::from_parameters(24, 25, 26, 80, 95, 100, tricell::Periodicity::all());

// Every set of stored columns in every order, on one and two threads.
std::vector<NeighborOptions> variants(double cutoff) {
    std::vector<NeighborOptions> out;
    for (int order = 0; order < 3; ++order) {
        for (int columns = 0; columns < 4; ++columns) {
            for (int threads : {1, 2}) {
                NeighborOptions o;
                o.cutoff = cutoff;
                o.grouped = order == 1;
                o.sorted = order == 2;
                o.quantities = tricell::Quantities{columns != 1, columns != 2, columns == 3};
                o.half = columns == 2;
                o.threads = threads;
                o.max_bytes = 0;
                out.push_back(o);
            }
        }
    }
    return out;
}

std::string described(const NeighborOptions& o) {
    return tricell::detail::list_memory(o).rates() + (o.half ? ", half" : "") + ", " +
           std::to_string(o.threads) + " threads";
}

double estimate_of(const std::vector<Eigen::Vector3d>& x, const NeighborOptions& o) {
    NeighborSearch search;
    search.build(cell, x, o);
    return search.estimated_pairs();
}

} // namespace

TEST(MaxBytes, TheModelCountsEachColumnAndTheOrdersWorkingSpace) {
    NeighborOptions o;
    o.quantities = tricell::Quantities{true, true, true};
    tricell::detail::ListMemory m = tricell::detail::list_memory(o);
    EXPECT_EQ(m.per_pair, 52);
    EXPECT_EQ(m.columns(), "i, j, S, d, D");
    EXPECT_EQ(m.peak(1000, 10), 52000);
    EXPECT_EQ(m.growing(1000), 76000); // D copied while it grows
    o.sorted = true;
    m = tricell::detail::list_memory(o);
    EXPECT_EQ(m.peak(1000, 10), 1000 * (52 + 8 + 24) + 10 * 16);
    EXPECT_EQ(m.rates(), "52 bytes a pair of i, j, S, d, D + 32 a pair to sort them + 16 an atom");
    o.sorted = false;
    o.grouped = true;
    o.quantities = tricell::Quantities{false, false, false};
    m = tricell::detail::list_memory(o);
    EXPECT_EQ(m.columns(), "i, j");
    EXPECT_EQ(m.peak(1000, 10), 1000 * (8 + 4 + 1) + 10 * 16);
    EXPECT_EQ(m.rates(), "8 bytes a pair of i, j + 5 a pair to group them + 16 an atom");
    o.grouped = false;
    o.sorted = true; // sorting stores S
    EXPECT_EQ(tricell::detail::list_memory(o).columns(), "i, j, S");
}

TEST(MaxBytes, RefusesTheEstimateInBuildAndNamesPairsBytesAndLimit) {
    const std::vector<Eigen::Vector3d> x = uniform_atoms(3000, 25, 1);
    for (const NeighborOptions& base : variants(3)) {
        SCOPED_TRACE(described(base));
        const double estimate = estimate_of(x, base);
        const tricell::detail::ListMemory m = tricell::detail::list_memory(base);
        const double peak = m.peak(estimate, x.size());
        NeighborOptions o = base;
        o.max_bytes = std::size_t(std::ceil(peak)) - 1;
        NeighborSearch search;
        bool refused = false;
        try {
            search.build(cell, x, o);
        } catch (const PairLimitError& e) {
            refused = true;
            EXPECT_EQ(e.which(), PairLimitError::Limit::bytes);
            EXPECT_EQ(e.pairs(), estimate);
            EXPECT_EQ(e.bytes(), peak);
            EXPECT_EQ(e.limit(), o.max_bytes);
            const std::string what = e.what();
            EXPECT_EQ(what.find("cutoff 3 would give about "), 0u) << what;
            EXPECT_NE(what.find(" pairs for 3000 atoms (estimated from the density), " +
                                std::to_string(std::llround(peak)) + " bytes at its peak (" +
                                m.rates() +
                                "), more than max_bytes = " + std::to_string(o.max_bytes) + " ("),
                      std::string::npos)
                << what;
            EXPECT_NE(what.find(" GiB); raise NeighborOptions::max_bytes to allow it (0 = no "
                                "limit)"),
                      std::string::npos)
                << what;
        }
        EXPECT_TRUE(refused);
    }
}

TEST(MaxBytes, AListJustWithinTheLimitRunsAndOneByteLessIsRefused) {
    const std::vector<Eigen::Vector3d> x = uniform_atoms(2000, 25, 2);
    for (const NeighborOptions& base : variants(3.5)) {
        SCOPED_TRACE(described(base));
        const NeighborList unlimited = tricell::compute_neighbors(cell, x, base);
        const double estimate = estimate_of(x, base);
        const tricell::detail::ListMemory m = tricell::detail::list_memory(base);
        const double peak =
            std::max(m.peak(estimate, x.size()), m.peak(unlimited.size(), x.size()));
        NeighborOptions o = base;
        o.max_bytes = std::size_t(std::ceil(peak));
        NeighborList list;
        tricell::compute_neighbors(cell, x, o, list);
        EXPECT_EQ(list.i(), unlimited.i());
        EXPECT_EQ(list.j(), unlimited.j());
        EXPECT_EQ(list.shifts(), unlimited.shifts());
        o.max_bytes -= 1;
        bool refused = false;
        try {
            tricell::compute_neighbors(cell, x, o, list);
        } catch (const PairLimitError& e) {
            refused = e.which() == PairLimitError::Limit::bytes;
        }
        EXPECT_TRUE(refused);
        EXPECT_TRUE(list.empty());
    }
}

TEST(MaxBytes, AListPastItsEstimateIsRefusedWhileWrittenAndLeftEmpty) {
    // 400 atoms within 1.7 A of each other (at most 2.95 A apart) in a 25 A cell: the density
    // predicts a few hundred pairs, the list has 159600.
    std::vector<Eigen::Vector3d> x = uniform_atoms(400, 1.7, 3);
    for (NeighborOptions o : variants(3)) {
        SCOPED_TRACE(described(o));
        o.half = false;
        const NeighborList unlimited = tricell::compute_neighbors(cell, x, o);
        ASSERT_EQ(unlimited.size(), 400u * 399u);
        const tricell::detail::ListMemory m = tricell::detail::list_memory(o);
        ASSERT_LT(m.peak(estimate_of(x, o), x.size()), m.peak(unlimited.size(), x.size()) / 20);
        // Room for the list and for a column's copy while it grows: it runs.
        // (A column grows at most when one claim of hits past the list would not fit.)
        const double grown = double(unlimited.size() + tricell::detail::PairSink::block_size);
        o.max_bytes =
            std::size_t(std::ceil(std::max(m.peak(unlimited.size(), x.size()), m.growing(grown))));
        NeighborList list;
        tricell::compute_neighbors(cell, x, o, list);
        EXPECT_EQ(list.j(), unlimited.j());
        // Half of the list's memory: build() passes, compute() refuses and leaves nothing.
        o.max_bytes = std::size_t(m.peak(unlimited.size(), x.size()) / 2);
        NeighborSearch search;
        search.build(cell, x, o);
        bool refused = false;
        try {
            search.compute(list);
        } catch (const PairLimitError& e) {
            refused = true;
            EXPECT_EQ(e.which(), PairLimitError::Limit::bytes);
            EXPECT_EQ(e.limit(), o.max_bytes);
            EXPECT_LE(e.pairs(), double(unlimited.size()));
            EXPECT_GT(e.bytes(), double(o.max_bytes));
            EXPECT_EQ(std::string(e.what()).find("the neighbour list "), 0u) << e.what();
        }
        EXPECT_TRUE(refused);
        EXPECT_TRUE(list.empty());
        EXPECT_TRUE(list.i().empty() && list.distances().empty() && list.offsets().empty());
    }
}

TEST(MaxBytes, BoundsABatchInTotalAndNamesIt) {
    const std::vector<Eigen::Vector3d> a = uniform_atoms(500, 25, 4);
    const std::vector<Eigen::Vector3d> b = uniform_atoms(600, 25, 5);
    const std::vector<tricell::BatchStructure> batch{{cell, a}, {cell, b}};
    NeighborOptions o;
    o.cutoff = 4;
    o.max_bytes = 0;
    tricell::BatchList list;
    tricell::compute_neighbors_batch(batch, o, list);
    const double total = double(list.size()) * tricell::detail::list_memory(o).per_pair;
    o.max_bytes = std::size_t(total);
    tricell::compute_neighbors_batch(batch, o, list);
    o.max_bytes -= 1;
    try {
        tricell::compute_neighbors_batch(batch, o, list);
        ADD_FAILURE() << "not refused";
    } catch (const PairLimitError& e) {
        EXPECT_EQ(e.which(), PairLimitError::Limit::bytes);
        EXPECT_NE(std::string(e.what()).find("the batch has too many pairs in total: "),
                  std::string::npos)
            << e.what();
    }
}

TEST(MaxBytes, ThePairLimitIsNamedWhenBothArePassedAndZeroLiftsTheByteLimit) {
    const std::vector<Eigen::Vector3d> x = uniform_atoms(1000, 25, 6);
    NeighborOptions o;
    o.cutoff = 3;
    o.max_pairs = 10;
    o.max_bytes = 10;
    try {
        tricell::compute_neighbors(cell, x, o);
        ADD_FAILURE() << "not refused";
    } catch (const PairLimitError& e) {
        EXPECT_EQ(e.which(), PairLimitError::Limit::pairs);
        EXPECT_NE(std::string(e.what()).find("more than max_pairs = 10;"), std::string::npos);
    }
    o.max_pairs = 0;
    o.max_bytes = 0;
    EXPECT_GT(tricell::compute_neighbors(cell, x, o).size(), 1000u);
    // A caller that says where the list came from keeps the limit and its fields.
    const PairLimitError e("x", 5, 6, 7);
    const PairLimitError renamed = e.with_subject("y");
    EXPECT_EQ(renamed.which(), PairLimitError::Limit::bytes);
    EXPECT_EQ(renamed.limit(), 7u);
    EXPECT_EQ(std::string(renamed.what()),
              "y, more than max_bytes = 7 (6.52e-09 GiB); raise NeighborOptions::max_bytes to "
              "allow it (0 = no limit)");
}

TEST(ListRoom, NeverMoreThanTheListCanHold) {
    // The room a list starts with is capped by the pairs it can hold at all: a centre pairs with
    // every atom in each image the cutoff reaches, ceil(2 r / w) + 1 along a periodic axis of
    // width w, one along an open axis. An open molecule with a cutoff near the largest double
    // once reserved room for hundreds of millions of pairs (gigabytes of address space a call).
    std::mt19937_64 rng(41);
    std::uniform_real_distribution<double> u(0, 1);
    for (int trial = 0; trial < 200; ++trial) {
        SCOPED_TRACE(trial);
        const tricell::Periodicity pbc{{u(rng) < 0.5, u(rng) < 0.5, u(rng) < 0.5}};
        const Box box =
            Box::from_parameters(2 + 3 * u(rng), 2 + 3 * u(rng), 2 + 3 * u(rng), 75 + 30 * u(rng),
                                 75 + 30 * u(rng), 75 + 30 * u(rng), pbc);
        const std::size_t n = 1 + std::size_t(6 * u(rng));
        std::vector<Eigen::Vector3d> x(n);
        for (Eigen::Vector3d& p : x) {
            p = box.matrix() * Eigen::Vector3d(u(rng), u(rng), u(rng));
        }
        NeighborOptions o;
        o.cutoff = trial % 4 == 0 ? 1e300 : 0.5 + 8 * u(rng);
        o.half = trial % 3 == 0;
        o.threads = 1 + trial % 2;
        o.reduce_cell = false; // so the search's cell is this one
        if (pbc.axes[0] || pbc.axes[1] || pbc.axes[2]) {
            o.cutoff = std::min(o.cutoff, 9.0); // periodic images stay countable
        }
        double images = 1;
        for (int k = 0; k < 3; ++k) {
            if (pbc.axes[k]) {
                images *= std::ceil(2 * o.cutoff / box.perpendicular_widths()[k]) + 1;
            }
        }
        const double most = double(n) * double(n) * images;
        NeighborList list;
        tricell::compute_neighbors(box, x, o, list);
        EXPECT_LE(double(list.size()), most);
        EXPECT_LE(double(list.i().capacity()), 1.1 * most + 1024 + 4096) << "cutoff " << o.cutoff;
    }
}
