// group_pairs() on lists built to take each of its paths: runs of an atom's pairs long enough
// to be gathered (as a search in cells writes them), runs too short for that (scattered), and
// one run per atom; each checked against a stable sort of the list by i, with every
// combination of stored columns, and with the spare column reused from a wider list.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <numeric>
#include <random>
#include <vector>

#include "output/grouped_and_sorted.hpp"

namespace {

using tricell::PairColumns;

// A list of `atoms` atoms whose pairs come in runs of 1 to 2 * mean_run - 1 pairs of one atom,
// the atoms in random order (an atom may have several runs, or none).
PairColumns random_runs(std::uint32_t atoms, std::size_t pairs, std::size_t mean_run, unsigned seed,
                        bool shifts, bool distances, bool vectors) {
    std::mt19937 rng(seed);
    std::uniform_int_distribution<std::uint32_t> atom(0, atoms - 1);
    std::uniform_int_distribution<std::size_t> length(1, 2 * mean_run - 1);
    PairColumns c;
    while (c.i.size() < pairs) {
        const std::uint32_t a = atom(rng);
        for (std::size_t n = length(rng); n > 0; --n) {
            const std::size_t k = c.i.size();
            c.i.push_back(a);
            c.j.push_back(std::uint32_t(rng() % 100000));
            for (int d = 0; d < 3; ++d) {
                if (shifts) {
                    c.shifts.push_back(std::int32_t(k % 7) - 3 + d);
                }
                if (vectors) {
                    c.vectors.push_back(double(k) + 0.25 * d);
                }
            }
            if (distances) {
                c.distances.push_back(double(k) * 0.5);
            }
        }
    }
    return c;
}

void expect_stably_grouped(const PairColumns& plain, const PairColumns& grouped,
                           std::size_t atoms) {
    std::vector<std::size_t> order(plain.size());
    std::iota(order.begin(), order.end(), std::size_t(0));
    std::stable_sort(order.begin(), order.end(),
                     [&](std::size_t a, std::size_t b) { return plain.i[a] < plain.i[b]; });
    ASSERT_EQ(grouped.size(), plain.size());
    ASSERT_EQ(grouped.shifts.size(), plain.shifts.size());
    ASSERT_EQ(grouped.distances.size(), plain.distances.size());
    ASSERT_EQ(grouped.vectors.size(), plain.vectors.size());
    for (std::size_t k = 0; k < order.size(); ++k) {
        const std::size_t p = order[k];
        ASSERT_EQ(grouped.i[k], plain.i[p]) << "pair " << k;
        ASSERT_EQ(grouped.j[k], plain.j[p]) << "pair " << k;
        if (!plain.distances.empty()) {
            ASSERT_EQ(grouped.distances[k], plain.distances[p]) << "pair " << k;
        }
        for (std::size_t d = 0; d < 3; ++d) {
            if (!plain.shifts.empty()) {
                ASSERT_EQ(grouped.shifts[3 * k + d], plain.shifts[3 * p + d]) << "pair " << k;
            }
            if (!plain.vectors.empty()) {
                ASSERT_EQ(grouped.vectors[3 * k + d], plain.vectors[3 * p + d]) << "pair " << k;
            }
        }
    }
    ASSERT_EQ(grouped.offsets.size(), atoms + 1);
    ASSERT_EQ(grouped.offsets.front(), 0u);
    for (std::size_t a = 0; a < atoms; ++a) {
        ASSERT_LE(grouped.offsets[a], grouped.offsets[a + 1]);
        for (std::size_t k = grouped.offsets[a]; k < grouped.offsets[a + 1]; ++k) {
            ASSERT_EQ(grouped.i[k], a) << "pair " << k;
        }
    }
    ASSERT_EQ(grouped.offsets.back(), grouped.size());
}

TEST(GroupPairs, LongShortAndSingleRunsAreStablyGroupedWithAnyStoredColumns) {
    // Mean run lengths on either side of the gathering threshold, and one atom's single run.
    const std::size_t mean_runs[] = {1, 3, 12, 20, 50, 400};
    tricell::PairArray<unsigned char> spare; // reused, as the list object does
    unsigned seed = 1;
    for (const std::size_t mean_run : mean_runs) {
        for (unsigned columns = 0; columns < 8; ++columns, ++seed) {
            SCOPED_TRACE(testing::Message() << "mean run " << mean_run << ", columns " << columns);
            const std::uint32_t atoms = 1 + seed * 37 % 500;
            const PairColumns plain = random_runs(atoms, 20000 + seed * 101, mean_run, seed,
                                                  columns & 1, columns & 2, columns & 4);
            PairColumns grouped = plain;
            tricell::detail::group_pairs(grouped, atoms, spare);
            expect_stably_grouped(plain, grouped, atoms);
            EXPECT_TRUE(spare.empty());
        }
    }
    // Every atom with exactly one run, in random order (a crystal's full list).
    const std::uint32_t atoms = 3000;
    std::vector<std::uint32_t> order(atoms);
    std::iota(order.begin(), order.end(), 0u);
    std::shuffle(order.begin(), order.end(), std::mt19937(7));
    PairColumns plain;
    for (const std::uint32_t a : order) {
        for (std::uint32_t n = 0; n < 28; ++n) {
            plain.i.push_back(a);
            plain.j.push_back(n);
            plain.distances.push_back(double(plain.i.size()));
        }
    }
    PairColumns grouped = plain;
    tricell::detail::group_pairs(grouped, atoms, spare);
    expect_stably_grouped(plain, grouped, atoms);
}

TEST(GroupPairs, AnAlreadyGroupedListGetsItsOffsetsAndStaysAsItIs) {
    PairColumns plain;
    for (std::uint32_t a = 0; a < 50; a += 2) {
        for (std::uint32_t n = 0; n < a % 7; ++n) {
            plain.i.push_back(a);
            plain.j.push_back(n + a);
        }
    }
    PairColumns grouped = plain;
    tricell::PairArray<unsigned char> spare;
    tricell::detail::group_pairs(grouped, 51, spare);
    expect_stably_grouped(plain, grouped, 51);
}

} // namespace
