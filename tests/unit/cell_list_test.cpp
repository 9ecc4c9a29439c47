#include <algorithm>
#include <cstdint>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "tricell/cell_list.hpp"

TEST(CellLists, LinkedAndSortedListTheSameAtomsPerCell) {
    std::mt19937_64 rng(3);
    for (int trial = 0; trial < 50; ++trial) {
        SCOPED_TRACE(trial);
        const std::size_t cells = 1 + std::size_t(trial);
        std::uniform_int_distribution<std::uint32_t> pick(0, std::uint32_t(cells - 1));
        std::vector<std::uint32_t> cell_of(std::size_t(trial) * 7);
        for (auto& c : cell_of) {
            c = pick(rng);
        }
        tricell::LinkedCellList linked;
        tricell::SortedCellList sorted;
        linked.build(cell_of, cells);
        sorted.build(cell_of, cells);
        ASSERT_EQ(sorted.cell_count(), cells);
        ASSERT_EQ(sorted.atom_count(), cell_of.size());
        std::size_t total = 0;
        for (std::size_t c = 0; c < cells; ++c) {
            std::vector<std::uint32_t> from_chain, from_range;
            for (auto a = linked.head(c); a != tricell::LinkedCellList::end; a = linked.next(a)) {
                from_chain.push_back(std::uint32_t(a));
            }
            for (auto k = sorted.cell_start(c); k < sorted.cell_end(c); ++k) {
                from_range.push_back(sorted.original(k));
                EXPECT_EQ(cell_of[sorted.original(k)], c);
            }
            EXPECT_EQ(from_chain, from_range); // both in increasing original index
            total += from_range.size();
        }
        EXPECT_EQ(total, cell_of.size());
    }
}

TEST(CellLists, EmptyInputGivesEmptyCells) {
    tricell::LinkedCellList linked;
    tricell::SortedCellList sorted;
    linked.build({}, 4);
    sorted.build({}, 4);
    for (std::size_t c = 0; c < 4; ++c) {
        EXPECT_EQ(linked.head(c), tricell::LinkedCellList::end);
        EXPECT_EQ(sorted.cell_start(c), sorted.cell_end(c));
    }
}

TEST(CellLists, ThreadedSortEqualsAStableSortByCell) {
    // Oracle: std::stable_sort of the atom indices by cell. Cell counts from 1 (every atom in one
    // cell) to more cells than atoms (most empty), atom counts from 0, threads from 1 to 5; once
    // by a fresh list and once by one list rebuilt every time (it keeps its tables).
    tricell::SortedCellList reused;
    for (std::uint64_t seed = 0; seed < 200; ++seed) {
        SCOPED_TRACE(seed);
        std::mt19937_64 rng(seed);
        const std::size_t atoms = rng() % 300;
        const std::size_t cells = 1 + rng() % 400;
        std::vector<std::uint32_t> cell_of(atoms);
        for (std::uint32_t& c : cell_of) {
            c = static_cast<std::uint32_t>(rng() % cells);
        }
        std::vector<std::uint32_t> expected(atoms);
        for (std::size_t i = 0; i < atoms; ++i) {
            expected[i] = static_cast<std::uint32_t>(i);
        }
        std::stable_sort(expected.begin(), expected.end(),
                         [&](std::uint32_t a, std::uint32_t b) { return cell_of[a] < cell_of[b]; });
        const std::size_t threads = 1 + seed % 5;
        tricell::SortedCellList sorted;
        sorted.build(cell_of, cells, threads);
        ASSERT_EQ(sorted.order(), expected) << threads << " threads";
        ASSERT_EQ(sorted.cell_count(), cells);
        for (std::size_t c = 0; c < cells; ++c) {
            for (std::uint32_t k = sorted.cell_start(c); k < sorted.cell_end(c); ++k) {
                ASSERT_EQ(cell_of[sorted.original(k)], c);
            }
        }
        ASSERT_EQ(sorted.cell_end(cells - 1), atoms);
        reused.build(cell_of, cells, threads);
        ASSERT_EQ(reused.order(), expected) << threads << " threads, reused";
        for (std::size_t c = 0; c <= cells; ++c) {
            ASSERT_EQ(reused.cell_start(c), sorted.cell_start(c));
        }
    }
}
