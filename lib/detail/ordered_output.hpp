// The final columns of a threaded search, filled in place in batch order. The work units are cut
// into many small batches (a few thousand pairs each) that the threads take in order from a
// ticket counter. A thread scans a batch into its own small columns (they stay in cache) and
// reports the batch's size; the place of every batch whose predecessors all have known sizes is
// then fixed (a running sum under a mutex, by whichever thread reports), and each thread copies
// its own placed batches to their places, with non-temporal stores (stream_copy.hpp). The result
// is the concatenation of the batches in unit order, whatever the thread count, with no merge
// copy of per-thread lists afterwards (that copy was a serial tail of the two-thread search: one
// thread copied the second half of the list while the other waited) and no second list in
// memory. A thread does not wait for another when a batch cannot be placed yet: the batch stays
// in its owner's columns, behind which the owner scans its next batch; usually that is one batch
// (two threads finishing neighbouring batches at about the same time). Only a thread holding many
// such batches (a stalled neighbour), or at the end, waits.
//
// The columns start at the estimated size (untouched capacity is never resident) and grow,
// rarely, under an exclusive lock while no copy is running.
#pragma once

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <limits>
#include <mutex>
#include <shared_mutex>
#include <thread>
#include <vector>

#include "detail/pair_sink.hpp"
#include "detail/stream_copy.hpp"
#include "tricell/error.hpp"

namespace tricell::detail {

class OrderedOutput {
  public:
    /// Fills `columns` (resized to `capacity` now, trimmed by finish()) with `batches` batches;
    /// at most `limit` pairs in all (0: no limit).
    OrderedOutput(const PairColumns& columns, std::size_t batches, std::size_t capacity,
                  std::size_t limit)
        : columns_(columns), limit_(limit), size_(batches, unknown), offset_(batches, 0) {
        resize(limit_ != 0 ? std::min(capacity, limit_) : capacity);
    }

    /// Records that `batch` has `size` pairs and places every batch it makes placeable. Returns
    /// how many batches are placed (batch k is placed when k < the value; offset(k) is then
    /// final).
    std::size_t finished(std::size_t batch, std::size_t size) {
        std::lock_guard<std::mutex> lock(place_mutex_);
        size_[batch] = size;
        std::size_t placed = placed_.load(std::memory_order_relaxed);
        while (placed < size_.size() && size_[placed] != unknown) {
            if (limit_ != 0 && size_[placed] > limit_ - end_) {
                abort();
                fail_list_over_limit(limit_);
            }
            offset_[placed] = end_;
            end_ += size_[placed];
            ++placed;
        }
        placed_.store(placed, std::memory_order_release);
        return placed;
    }

    /// Where placed batch `batch` starts.
    std::size_t offset(std::size_t batch) const { return offset_[batch]; }

    /// Waits until `batch` is placed; returns how many are, or 0 when another thread failed.
    std::size_t wait_placed(std::size_t batch) {
        for (;;) {
            const std::size_t placed = placed_.load(std::memory_order_acquire);
            if (placed > batch) {
                return placed;
            }
            if (aborted()) {
                return 0;
            }
            std::this_thread::yield();
        }
    }

    /// Copies pairs [start, start + size) of `from` (the same columns stored) to `offset`.
    void write(std::size_t offset, const PairColumns& from, std::size_t start, std::size_t size) {
        {
            std::shared_lock<std::shared_mutex> lock(grow_mutex_);
            if (offset + size <= capacity_) {
                copy(offset, from, start, size);
                return;
            }
        }
        std::unique_lock<std::shared_mutex> lock(grow_mutex_);
        if (offset + size > capacity_) {
            resize(std::max(offset + size, 2 * capacity_));
        }
        copy(offset, from, start, size);
    }

    /// Makes every waiting and later wait_placed() return 0.
    void abort() { aborted_.store(true, std::memory_order_relaxed); }
    bool aborted() const { return aborted_.load(std::memory_order_relaxed); }

    /// Trims the columns to the pairs placed (all threads done).
    void finish() { resize(end_); }

  private:
    static constexpr std::size_t unknown = std::numeric_limits<std::size_t>::max();

    void copy(std::size_t offset, const PairColumns& from, std::size_t start, std::size_t size) {
        if (size == 0) {
            return;
        }
        auto column = [&](const auto* source, auto* target, std::size_t width) {
            if (source != nullptr) {
                stream_copy(target->data() + width * offset, source->data() + width * start,
                            width * size * sizeof(*source->data()));
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
    std::size_t capacity_ = 0; // guarded by grow_mutex_
    std::shared_mutex grow_mutex_;
    // Guarded by place_mutex_: the size of each batch (unknown until finished) and, for placed
    // batches, its offset; end_ is the end of the last placed batch.
    std::mutex place_mutex_;
    std::vector<std::size_t> size_;
    std::vector<std::size_t> offset_;
    std::size_t end_ = 0;
    std::atomic<std::size_t> placed_{0};
    std::atomic<bool> aborted_{false};
};

} // namespace tricell::detail
