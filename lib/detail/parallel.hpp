// Plain threads for the library's parallel phases. run_in_threads() runs one task per thread;
// parallel_ranges() cuts [0, count) into contiguous ranges, one per thread, and reports the first
// exception in range order, so that an error names the same (lowest) item whatever the thread
// count.
//
// A threaded build has eight phases (checks, wrap, binning, the three passes of the cell sort,
// the atom table) plus the search itself, and starting and joining threads per phase costs as
// much as a search of a few thousand atoms gains from them. A ThreadTeam therefore starts its
// helpers once, on its first phase, and hands
// them each later phase (they spin briefly, then sleep, between phases); a TeamScope makes a team
// the one every run_in_threads() and parallel_ranges() of the calling thread uses until the scope
// ends, so a search's phases in other files (the backends' binning, the cell sort) share it
// without taking it as an argument. A call made while the team is busy (from inside one of its
// tasks) or that needs more threads than it has starts its own threads, as without a team.
#pragma once

#include <algorithm>
#include <atomic>
#include <condition_variable>
#include <cstddef>
#include <cstdint>
#include <exception>
#include <memory>
#include <mutex>
#include <thread>
#include <vector>

namespace tricell::detail {

/// `size` threads (the calling one and size - 1 helpers started on the first run()) that run
/// phase after phase. Not for concurrent use: one caller at a time.
class ThreadTeam {
  public:
    explicit ThreadTeam(std::size_t size) : size_(std::max<std::size_t>(1, size)) {}
    ThreadTeam(const ThreadTeam&) = delete;
    ThreadTeam& operator=(const ThreadTeam&) = delete;
    ~ThreadTeam() {
        {
            std::lock_guard<std::mutex> lock(mutex_);
            stop_.store(true, std::memory_order_relaxed);
        }
        wake_.notify_all();
        for (std::thread& w : helpers_) {
            w.join();
        }
    }

    std::size_t size() const { return size_; }
    bool busy() const { return busy_; }

    /// Runs task(0) .. task(count - 1), count <= size(), task 0 on the calling thread; returns
    /// when all have finished. An exception of a task is rethrown then (the lowest task's).
    template <class Task> void run(std::size_t count, Task& task) {
        if (helpers_.size() + 1 < size_) {
            start();
        }
        busy_ = true;
        errors_.assign(count, nullptr);
        count_ = count;
        context_ = const_cast<void*>(static_cast<const void*>(&task));
        call_ = [](void* context, std::size_t t) { (*static_cast<Task*>(context))(t); };
        remaining_.store(size_ - 1, std::memory_order_relaxed);
        {
            std::lock_guard<std::mutex> lock(mutex_);
            generation_.store(generation_.load(std::memory_order_relaxed) + 1,
                              std::memory_order_release);
        }
        wake_.notify_all();
        perform(0);
        // The helpers' phases end within microseconds of ours when the work is balanced: spin a
        // little before sleeping.
        for (int k = 0; k < spin_rounds && remaining_.load(std::memory_order_acquire) != 0; ++k) {
            std::this_thread::yield();
        }
        if (remaining_.load(std::memory_order_acquire) != 0) {
            std::unique_lock<std::mutex> lock(mutex_);
            done_.wait(lock, [&] { return remaining_.load(std::memory_order_acquire) == 0; });
        }
        busy_ = false;
        for (const std::exception_ptr& e : errors_) {
            if (e) {
                std::rethrow_exception(e);
            }
        }
    }

  private:
    static constexpr int spin_rounds = 200; // yields, about as long as a thread start

    void start() {
        try {
            for (std::size_t t = helpers_.size() + 1; t < size_; ++t) {
                helpers_.emplace_back([this, t] { serve(t); });
            }
        } catch (...) { // could not start a thread: stop the started ones, then report
            {
                std::lock_guard<std::mutex> lock(mutex_);
                stop_.store(true, std::memory_order_relaxed);
            }
            wake_.notify_all();
            for (std::thread& w : helpers_) {
                w.join();
            }
            helpers_.clear();
            stop_.store(false, std::memory_order_relaxed);
            throw;
        }
    }

    void perform(std::size_t t) {
        if (t < count_) {
            try {
                call_(context_, t);
            } catch (...) {
                errors_[t] = std::current_exception();
            }
        }
    }

    void serve(std::size_t t) {
        std::uint64_t seen = 0;
        for (;;) {
            // Stopping is checked too: the team ends right after a call's last phase, and its
            // end should not wait out the spin.
            for (int k = 0;
                 k < spin_rounds && generation_.load(std::memory_order_acquire) == seen &&
                 !stop_.load(std::memory_order_relaxed);
                 ++k) {
                std::this_thread::yield();
            }
            {
                std::unique_lock<std::mutex> lock(mutex_);
                wake_.wait(lock, [&] {
                    return stop_.load(std::memory_order_relaxed) ||
                           generation_.load(std::memory_order_relaxed) != seen;
                });
                if (stop_.load(std::memory_order_relaxed)) {
                    return;
                }
            }
            seen = generation_.load(std::memory_order_acquire);
            perform(t);
            if (remaining_.fetch_sub(1, std::memory_order_acq_rel) == 1) {
                std::lock_guard<std::mutex> lock(mutex_); // the caller may be about to sleep
                done_.notify_one();
            }
        }
    }

    std::size_t size_;
    std::vector<std::thread> helpers_;
    std::mutex mutex_;
    std::condition_variable wake_, done_;
    std::atomic<bool> stop_{false}; // written under mutex_
    std::atomic<std::uint64_t> generation_{0};
    std::atomic<std::size_t> remaining_{0};
    // The phase being run, set before generation_ moves on.
    void (*call_)(void*, std::size_t) = nullptr;
    void* context_ = nullptr;
    std::size_t count_ = 0;
    std::vector<std::exception_ptr> errors_;
    bool busy_ = false;
};

/// The team the calling thread's parallel phases use, null outside a TeamScope.
inline ThreadTeam*& current_team() {
    thread_local ThreadTeam* team = nullptr;
    return team;
}

/// Makes a team of `threads` threads (none when threads <= 1, or when the calling thread already
/// has one) the calling thread's until the scope ends; its helpers start on its first phase.
class TeamScope {
  public:
    explicit TeamScope(std::size_t threads) {
        if (threads > 1 && current_team() == nullptr) {
            team_ = std::make_unique<ThreadTeam>(threads);
            current_team() = team_.get();
        }
    }
    TeamScope(const TeamScope&) = delete;
    TeamScope& operator=(const TeamScope&) = delete;
    ~TeamScope() {
        if (team_) {
            current_team() = nullptr;
        }
    }

  private:
    std::unique_ptr<ThreadTeam> team_;
};

/// Runs task(0) .. task(count - 1), each on its own thread (task 0 on the calling thread): on the
/// calling thread's team when it has a free one large enough, else on threads started here.
template <class Task> void run_in_threads(std::size_t count, Task&& task) {
    ThreadTeam* team = current_team();
    if (count > 1 && team != nullptr && !team->busy() && count <= team->size()) {
        team->run(count, task);
        return;
    }
    std::vector<std::thread> workers;
    workers.reserve(count > 0 ? count - 1 : 0);
    try {
        for (std::size_t t = 1; t < count; ++t) {
            workers.emplace_back([&task, t] { task(t); });
        }
    } catch (...) { // could not start a thread: finish the started ones, then report
        for (std::thread& w : workers) {
            w.join();
        }
        throw;
    }
    if (count > 0) {
        task(0);
    }
    for (std::thread& w : workers) {
        w.join();
    }
}

/// Threads to start for `count` items: `threads`, but at least `grain` items per thread.
inline std::size_t threads_for(std::size_t count, std::size_t threads, std::size_t grain) {
    return std::max<std::size_t>(1, std::min(threads, count / grain));
}

/// Calls body(begin, end, t) for `threads` contiguous ranges covering [0, count), range t on
/// thread t. An exception thrown by a body is rethrown after all have finished: the one of the
/// lowest range.
template <class Body> void parallel_ranges(std::size_t count, std::size_t threads, Body&& body) {
    threads = std::max<std::size_t>(1, threads);
    if (threads == 1) {
        body(std::size_t(0), count, std::size_t(0));
        return;
    }
    std::vector<std::exception_ptr> errors(threads);
    run_in_threads(threads, [&](std::size_t t) {
        try {
            body(count * t / threads, count * (t + 1) / threads, t);
        } catch (...) {
            errors[t] = std::current_exception();
        }
    });
    for (const std::exception_ptr& e : errors) {
        if (e) {
            std::rethrow_exception(e);
        }
    }
}

} // namespace tricell::detail
