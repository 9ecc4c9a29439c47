// The library's thread team (lib/detail/parallel.hpp): phases share one set of helper threads,
// every range is run exactly once, the lowest task's exception is the one reported, and a call
// made from inside a phase (the team busy) starts its own threads instead of waiting for itself.
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <mutex>
#include <random>
#include <set>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "detail/parallel.hpp"

namespace {

using tricell::detail::current_team;
using tricell::detail::parallel_ranges;
using tricell::detail::run_in_threads;
using tricell::detail::TeamScope;

TEST(ThreadTeam, PhasesCoverEveryItemOnceOnTheSameThreads) {
    std::mt19937_64 rng(7);
    for (const std::size_t threads : {2u, 3u, 4u}) {
        SCOPED_TRACE(threads);
        const TeamScope scope(threads);
        ASSERT_NE(current_team(), nullptr);
        std::set<std::thread::id> seen;
        std::mutex seen_mutex;
        // Phases each helper served (a thread started per phase would serve one; thread ids can
        // be reused after a join, so the ids alone would not tell).
        const std::thread::id caller = std::this_thread::get_id();
        int most_served = 0;
        for (int phase = 0; phase < 200; ++phase) {
            const std::size_t count = rng() % 1000;
            const std::size_t used = 1 + rng() % threads; // a phase may use fewer than the team
            std::vector<int> hits(count, 0);
            parallel_ranges(count, used, [&](std::size_t begin, std::size_t end, std::size_t t) {
                ASSERT_LT(t, used);
                for (std::size_t k = begin; k < end; ++k) {
                    ++hits[k];
                }
                thread_local int served = 0;
                ++served;
                const std::lock_guard<std::mutex> lock(seen_mutex);
                seen.insert(std::this_thread::get_id());
                if (std::this_thread::get_id() != caller) {
                    most_served = std::max(most_served, served);
                }
            });
            for (std::size_t k = 0; k < count; ++k) {
                ASSERT_EQ(hits[k], 1) << "phase " << phase << " item " << k;
            }
        }
        // The calling thread and the team's helpers only: no thread was started per phase.
        EXPECT_LE(seen.size(), threads);
        EXPECT_GT(most_served, 20);
    }
    EXPECT_EQ(current_team(), nullptr);
}

TEST(ThreadTeam, ReportsTheLowestRangesErrorAndStaysUsable) {
    const TeamScope scope(4);
    for (int round = 0; round < 20; ++round) {
        try {
            parallel_ranges(400, 4, [&](std::size_t begin, std::size_t, std::size_t t) {
                if (t >= 1) {
                    throw std::runtime_error("range from " + std::to_string(begin));
                }
            });
            FAIL() << "no exception";
        } catch (const std::runtime_error& e) {
            EXPECT_STREQ(e.what(), "range from 100");
        }
        std::atomic<int> ran{0};
        run_in_threads(4, [&](std::size_t) { ++ran; });
        EXPECT_EQ(ran.load(), 4);
    }
}

TEST(ThreadTeam, CallFromInsideAPhaseStartsItsOwnThreads) {
    const TeamScope scope(2);
    std::atomic<int> inner{0};
    run_in_threads(2, [&](std::size_t) {
        // Only the calling thread has the team; there it is busy, so this starts threads.
        run_in_threads(3, [&](std::size_t) { ++inner; });
    });
    EXPECT_EQ(inner.load(), 6);
    // More threads than the team has: started here as well.
    std::atomic<int> wide{0};
    run_in_threads(5, [&](std::size_t) { ++wide; });
    EXPECT_EQ(wide.load(), 5);
}

} // namespace
