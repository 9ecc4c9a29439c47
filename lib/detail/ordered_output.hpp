// The final columns of a threaded search, filled in place in batch order. The work units are cut
// into many small batches (a few thousand pairs each) that the threads take in order from a
// ticket counter. A thread scans its batch into its own small columns (they stay in cache), then
// waits until every earlier batch has claimed its place (not until it is written: only its
// size is needed), claims [offset, offset + size) and copies its pairs there while the next
// batch's owner claims the next place. The result is the concatenation of the batches in unit
// order, whatever the thread count, with no merge copy of per-thread lists afterwards (that copy
// was a serial tail of the two-thread search) and no second list in memory. Waiting is
// short: the batch before was taken earlier and costs about as much.
//
// The columns start at the estimated size (untouched capacity is never resident) and grow,
// rarely, under an exclusive lock while no copy is running.
#pragma once

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <mutex>
#include <shared_mutex>
#include <thread>

#include "detail/pair_sink.hpp"
#include "tricell/error.hpp"

namespace tricell::detail {

class OrderedOutput {
  public:
    /// Fills `columns` (resized to `capacity` now, trimmed by finish()); at most `limit` pairs
    /// in all (0: no limit).
    OrderedOutput(const PairColumns& columns, std::size_t capacity, std::size_t limit)
        : columns_(columns), limit_(limit) {
        resize(limit_ != 0 ? std::min(capacity, limit_) : capacity);
    }

    /// Waits for batches 0 .. batch - 1 to be placed, then places `batch` (`size` pairs) and
    /// sets `offset` to where it goes. False when another thread failed (abort()): stop.
    bool place(std::size_t batch, std::size_t size, std::size_t& offset) {
        while (placed_.load(std::memory_order_acquire) != batch) {
            if (aborted_.load(std::memory_order_relaxed)) {
                return false;
            }
            std::this_thread::yield();
        }
        offset = end_;
        if (limit_ != 0 && size > limit_ - end_) {
            abort();
            fail<InvalidArgument>("the neighbour list has more than max_pairs = ", limit_,
                                  " pairs; raise NeighborOptions::max_pairs to allow it");
        }
        end_ += size;
        placed_.store(batch + 1, std::memory_order_release);
        return true;
    }

    /// Copies the first `size` pairs of `from` (the same columns stored) to `offset`.
    void write(std::size_t offset, const PairColumns& from, std::size_t size) {
        {
            std::shared_lock<std::shared_mutex> lock(mutex_);
            if (offset + size <= capacity_) {
                copy(offset, from, size);
                return;
            }
        }
        std::unique_lock<std::shared_mutex> lock(mutex_);
        if (offset + size > capacity_) {
            resize(std::max(offset + size, 2 * capacity_));
        }
        copy(offset, from, size);
    }

    /// Makes every waiting and later place() return false.
    void abort() { aborted_.store(true, std::memory_order_relaxed); }

    /// Trims the columns to the pairs placed (all threads done).
    void finish() { resize(end_); }

  private:
    void copy(std::size_t offset, const PairColumns& from, std::size_t size) {
        if (size == 0) {
            return;
        }
        auto column = [&](const auto* source, auto* target, std::size_t width) {
            if (source != nullptr) {
                std::copy(source->begin(), source->begin() + std::ptrdiff_t(width * size),
                          target->begin() + std::ptrdiff_t(width * offset));
            }
        };
        column(from.i, columns_.i, 1);
        column(from.j, columns_.j, 1);
        column(from.shifts, columns_.shifts, 3);
        column(from.distances, columns_.distances, 1);
        column(from.vectors, columns_.vectors, 3);
    }

    void resize(std::size_t capacity) {
        capacity_ = capacity;
        columns_.i->resize(capacity);
        columns_.j->resize(capacity);
        if (columns_.shifts != nullptr) {
            columns_.shifts->resize(3 * capacity);
        }
        if (columns_.distances != nullptr) {
            columns_.distances->resize(capacity);
        }
        if (columns_.vectors != nullptr) {
            columns_.vectors->resize(3 * capacity);
        }
    }

    PairColumns columns_;
    std::size_t limit_ = 0;
    std::size_t capacity_ = 0;
    std::size_t end_ = 0; // guarded by placed_: only the thread placing batch placed_ touches it
    std::atomic<std::size_t> placed_{0};
    std::atomic<bool> aborted_{false};
    std::shared_mutex mutex_;
};

} // namespace tricell::detail
