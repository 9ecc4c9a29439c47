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
