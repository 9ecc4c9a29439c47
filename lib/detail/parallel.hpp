// Plain threads for the library's parallel phases (no pool: a search starts a handful of threads
// per phase, which costs tens of microseconds against the milliseconds of a large search).
// run_in_threads() runs one task per thread; parallel_ranges() cuts [0, count) into contiguous
// ranges, one per thread, and reports the first exception in range order, so that an error
// names the same (lowest) item whatever the thread count.
#pragma once

#include <algorithm>
#include <cstddef>
#include <exception>
#include <thread>
#include <vector>

namespace tricell::detail {

/// Runs task(0) .. task(count - 1), each on its own thread (task 0 on the calling thread).
template <class Task> void run_in_threads(std::size_t count, Task&& task) {
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
