// Many threads searching at once through the C++ API. The reference lists come first, from
// serial calls (threads = 1) on one thread; then 12 threads each run every case several times,
// alternately through the compute_neighbors() free function (its thread-local search, below
// lib/policy/policy.hpp's reuse_search_below, and a fresh search above it) and through a
// NeighborSearch and a NeighborList of their own, reused across cases, with 1 to 4 internal
// threads (a thread team per call, lib/detail/parallel.hpp). Every list must equal the
// reference bit for bit.
#include <atomic>
#include <string>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

#include "support/stress_cases.hpp"

namespace {

using tricell::NeighborList;
using tricell::NeighborSearch;
using tricell::testing::list_difference;
using tricell::testing::stress_cases;

#ifdef TRICELL_STRESS_LIGHT // the sanitizer builds: fewer threads and rounds
constexpr int callers = 6, rounds = 1;
#else
constexpr int callers = 12, rounds = 3;
#endif

TEST(ConcurrencyStress, CxxApiMatchesSerialBitForBit) {
    const auto cases = stress_cases(10, 1600);
    std::vector<NeighborList> reference(cases.size());
    for (std::size_t c = 0; c < cases.size(); ++c) {
        tricell::compute_neighbors(cases[c].box(), cases[c].positions, cases[c].options,
                                   reference[c]);
        ASSERT_FALSE(reference[c].empty()) << c;
    }

    std::atomic<int> failures{0};
    std::vector<std::string> first_failure(callers);
    std::atomic<bool> go{false};
    auto caller = [&](int t) {
        while (!go.load()) {
            std::this_thread::yield();
        }
        NeighborSearch search;
        NeighborList own;
        try {
            for (int r = 0; r < rounds; ++r) {
                for (std::size_t k = 0; k < cases.size(); ++k) {
                    const std::size_t c = (k + static_cast<std::size_t>(t)) % cases.size();
                    auto options = cases[c].options;
                    options.threads = 1 + (t + r + static_cast<int>(c)) % 4;
                    NeighborList out;
                    if ((t + r) % 2 == 0) {
                        tricell::compute_neighbors(cases[c].box(), cases[c].positions, options,
                                                   out);
                    } else {
                        search.build(cases[c].box(), cases[c].positions, options);
                        search.compute(own);
                        out = own;
                    }
                    const std::string diff = list_difference(reference[c], out);
                    if (!diff.empty() && failures.fetch_add(1) == 0) {
                        first_failure[t] = "case " + std::to_string(c) + " threads " +
                                           std::to_string(options.threads) + ": " + diff;
                    }
                }
            }
        } catch (const std::exception& e) {
            failures.fetch_add(1);
            first_failure[t] = e.what();
        }
    };
    std::vector<std::thread> threads;
    for (int t = 0; t < callers; ++t) {
        threads.emplace_back(caller, t);
    }
    go.store(true);
    for (auto& th : threads) {
        th.join();
    }
    for (const auto& f : first_failure) {
        EXPECT_TRUE(f.empty()) << f;
    }
    EXPECT_EQ(failures.load(), 0);
}

TEST(ConcurrencyStress, ThreadLocalSearchSurvivesManyShortLivedThreads) {
    // Threads that end after one call each destroy their thread-local search; their successors
    // start from a fresh one.
    const auto cases = stress_cases(4, 900, 7);
    std::vector<NeighborList> reference(cases.size());
    for (std::size_t c = 0; c < cases.size(); ++c) {
        tricell::compute_neighbors(cases[c].box(), cases[c].positions, cases[c].options,
                                   reference[c]);
    }
    std::atomic<int> failures{0};
    for (int wave = 0; wave < 4; ++wave) {
        std::vector<std::thread> threads;
        for (int t = 0; t < callers; ++t) {
            threads.emplace_back([&, t] {
                const std::size_t c = static_cast<std::size_t>(t + wave) % cases.size();
                auto options = cases[c].options;
                options.threads = 1 + t % 3;
                const NeighborList out =
                    tricell::compute_neighbors(cases[c].box(), cases[c].positions, options);
                if (!list_difference(reference[c], out).empty()) {
                    failures.fetch_add(1);
                }
            });
        }
        for (auto& th : threads) {
            th.join();
        }
    }
    EXPECT_EQ(failures.load(), 0);
}

} // namespace
