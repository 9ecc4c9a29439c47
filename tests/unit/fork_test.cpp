// fork() after threaded searches: the child computes threaded and serial lists, compares them
// with the lists the parent computed before the fork, bit for bit, and exits with the result as
// its status. The parent polls waitpid() against a deadline and kills a child that has not
// finished (a deadlock: a helper thread or a mutex that did not survive the fork). The thread
// team of a call (lib/detail/parallel.hpp) ends with the call, so no helper thread or lock of
// the library outlives it. A fork while other threads of the parent search is checked too: the
// library holds no process-wide lock, and glibc's malloc is fork-safe (POSIX itself promises a
// child of a multithreaded process only async-signal-safe functions).
#include <chrono>
#include <thread>
#include <vector>

#include <csignal>
#include <sys/types.h>
#include <sys/wait.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include "support/stress_cases.hpp"

namespace {

using tricell::NeighborList;
using tricell::testing::list_difference;
using tricell::testing::stress_cases;

/// Waits for `child` up to `seconds`; kills it then. Its exit status, or -1 after a kill or a
/// signal.
int wait_with_deadline(pid_t child, double seconds) {
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
    for (;;) {
        int status = 0;
        const pid_t done = waitpid(child, &status, WNOHANG);
        if (done == child) {
            return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
        }
        if (std::chrono::steady_clock::now() > deadline) {
            kill(child, SIGKILL);
            waitpid(child, &status, 0);
            ADD_FAILURE() << "the child did not finish within " << seconds << " s (deadlock?)";
            return -1;
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
}

/// In the child: every case threaded (2 and 4 threads) and serial, free function and own search,
/// against the parent's lists. 0 when all agree. Only _exit() leaves (no gtest, no atexit).
int child_checks(const std::vector<tricell::testing::StressCase>& cases,
                 const std::vector<NeighborList>& reference) {
    int bad = 0;
    tricell::NeighborSearch search;
    for (std::size_t c = 0; c < cases.size(); ++c) {
        for (const int threads : {4, 1, 2}) {
            auto options = cases[c].options;
            options.threads = threads;
            const NeighborList free_list =
                tricell::compute_neighbors(cases[c].box(), cases[c].positions, options);
            NeighborList own;
            search.build(cases[c].box(), cases[c].positions, options);
            search.compute(own);
            bad += !list_difference(reference[c], free_list).empty();
            bad += !list_difference(reference[c], own).empty();
        }
    }
    return bad == 0 ? 0 : 1;
}

class ForkSafety : public ::testing::Test {
  protected:
    void SetUp() override {
        cases_ = stress_cases(6, 2500, 11);
        for (const auto& s : cases_) {
            auto options = s.options;
            options.threads = 3; // threaded in the parent before any fork
            reference_.push_back(tricell::compute_neighbors(s.box(), s.positions, options));
            const NeighborList serial = tricell::compute_neighbors(s.box(), s.positions, s.options);
            ASSERT_EQ(list_difference(reference_.back(), serial), "");
        }
    }
    std::vector<tricell::testing::StressCase> cases_;
    std::vector<NeighborList> reference_;
};

TEST_F(ForkSafety, ChildOfThreadedCallComputesCorrectLists) {
    const pid_t child = fork();
    ASSERT_GE(child, 0);
    if (child == 0) {
        _exit(child_checks(cases_, reference_));
    }
    EXPECT_EQ(wait_with_deadline(child, 60), 0);
}

TEST_F(ForkSafety, SeveralChildrenAndGrandchildren) {
    // Four children at once, each forking a grandchild after its own threaded call.
    std::vector<pid_t> children;
    for (int k = 0; k < 4; ++k) {
        const pid_t child = fork();
        ASSERT_GE(child, 0);
        if (child == 0) {
            int status = child_checks(cases_, reference_);
            const pid_t grandchild = fork();
            if (grandchild == 0) {
                _exit(child_checks(cases_, reference_));
            }
            int g = 0;
            if (grandchild < 0 || waitpid(grandchild, &g, 0) != grandchild || !WIFEXITED(g) ||
                WEXITSTATUS(g) != 0) {
                status = 1;
            }
            _exit(status);
        }
        children.push_back(child);
    }
    for (const pid_t child : children) {
        EXPECT_EQ(wait_with_deadline(child, 120), 0);
    }
}

// The sanitizers' runtimes are not fork-safe with other threads running: ThreadSanitizer does not
// support threads in such a child, and under GCC 12's AddressSanitizer the child hangs (a lock of
// the runtime copied held). The test runs in the uninstrumented build only.
#if defined(__SANITIZE_THREAD__) || defined(__SANITIZE_ADDRESS__)
#define TRICELL_SANITIZER_RUNTIME 1
#elif defined(__has_feature)
#if __has_feature(thread_sanitizer) || __has_feature(address_sanitizer)
#define TRICELL_SANITIZER_RUNTIME 1
#endif
#endif

TEST_F(ForkSafety, ForkWhileOtherThreadsSearch) {
#ifdef TRICELL_SANITIZER_RUNTIME
    GTEST_SKIP() << "the sanitizer runtime is not fork-safe with other threads running";
#endif
    // Other threads of the parent run threaded searches while the main thread forks: the child
    // has only the forking thread, and that thread's own calls work (the library keeps no
    // process-wide lock a search of another thread could hold across the fork).
    std::atomic<bool> stop{false};
    std::vector<std::thread> busy;
    for (int t = 0; t < 3; ++t) {
        busy.emplace_back([&, t] {
            while (!stop.load()) {
                auto options = cases_[static_cast<std::size_t>(t)].options;
                options.threads = 2;
                const auto& s = cases_[static_cast<std::size_t>(t)];
                (void)tricell::compute_neighbors(s.box(), s.positions, options);
            }
        });
    }
    std::vector<pid_t> children;
    for (int k = 0; k < 3; ++k) {
        std::this_thread::sleep_for(std::chrono::milliseconds(20));
        const pid_t child = fork();
        if (child == 0) {
            _exit(child_checks(cases_, reference_));
        }
        children.push_back(child);
    }
    stop.store(true);
    for (auto& th : busy) {
        th.join();
    }
    for (const pid_t child : children) {
        ASSERT_GE(child, 0);
        EXPECT_EQ(wait_with_deadline(child, 60), 0);
    }
}

} // namespace
