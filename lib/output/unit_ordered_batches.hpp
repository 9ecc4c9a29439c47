// The final columns of a threaded search, filled in place in batch order. The work units are cut
// into many small batches (a few thousand pairs each) that the threads take in order from a
// ticket counter. A thread scans a batch into its own small columns (they stay in cache) and
// reports the batch's size; the place of every batch whose predecessors all have known sizes is
// then fixed (a running sum under a mutex, by whichever thread reports), and each thread copies
// its own placed batches to their places, with non-temporal stores (stream_copy.hpp). The result
// is the concatenation of the batches in unit order, whatever the thread count, with no merge
// copy of per-thread lists afterwards (so no serial tail in which one thread copies while the
// others wait) and no second list in memory. A thread does not wait for another when a batch cannot
// be placed yet: the batch stays in its owner's columns, behind which the owner scans its next
// batch; usually that is one batch (two threads finishing neighbouring batches at about the same
// time). Only a thread holding many such batches (a stalled neighbour), or at the end, waits.
//
// write_in_unit_order() is the whole protocol: the threads, their tickets, each thread's queue of
// scanned batches not yet placed, and the copies.
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

#include "detail/parallel.hpp"
#include "detail/stream_copy.hpp"
#include "policy/policy.hpp"
#include "scan/pair_sink.hpp"
#include "tricell/error.hpp"

namespace tricell::detail {

class BatchPlacement {
  public:
    /// Fills `columns` (resized to `capacity` now, trimmed by finish()) with `batches` batches;
    /// at most what `limits` allow in all (they must outlive the output).
    BatchPlacement(const SinkColumns& columns, std::size_t batches, std::size_t capacity,
                   const ListLimits& limits)
        : columns_(columns), limits_(limits), limit_(limits.pairs()), size_(batches, unknown),
          offset_(batches, 0) {
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
                limits_.fail_size(end_ + size_[placed]);
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
    void write(std::size_t offset, const SinkColumns& from, std::size_t start, std::size_t size) {
        {
            std::shared_lock<std::shared_mutex> lock(grow_mutex_);
            if (offset + size <= capacity_) {
                copy(offset, from, start, size);
                return;
            }
        }
        std::unique_lock<std::shared_mutex> lock(grow_mutex_);
        if (offset + size > capacity_) {
            limits_.check_growth(capacity_);
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

    void copy(std::size_t offset, const SinkColumns& from, std::size_t start, std::size_t size) {
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

    SinkColumns columns_;
    const ListLimits& limits_;
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

/// Fills `final_columns` with the batches of `plan` on `threads` threads, in batch order (see
/// above): scan(b, sink) scans batch b into a PairSink. `columns_of` picks the stored columns of
/// a thread's own PairColumns; `scratch` holds those (kept between calls, one per thread).
/// `capacity` is the room to start with, `limits` those of the list. Rethrows the first
/// error of any thread after all have stopped.
template <class ColumnsOf, class Scan>
void write_in_unit_order(const SinkColumns& final_columns, const BatchPlan& plan,
                         std::size_t capacity, const ListLimits& limits, std::size_t threads,
                         std::vector<PairColumns>& scratch, const ColumnsOf& columns_of,
                         const Scan& scan) {
    const std::size_t batches = plan.size();
    BatchPlacement output(final_columns, batches, capacity, limits);
    scratch.resize(threads);
    std::vector<std::exception_ptr> errors(threads);
    std::atomic<std::size_t> next{0};
    run_in_threads(threads, [&](std::size_t t) {
        try {
            const SinkColumns columns = columns_of(scratch[t]);
            // This thread's scanned batches not yet copied out: (batch, first pair in
            // `columns`, pairs), in batch order; `used` pairs of `columns` are taken.
            struct Pending {
                std::size_t batch, start, size;
            };
            std::vector<Pending> pending;
            std::size_t used = 0;
            auto copy_placed = [&](std::size_t placed) {
                std::size_t k = 0;
                for (; k < pending.size() && pending[k].batch < placed; ++k) {
                    output.write(output.offset(pending[k].batch), columns, pending[k].start,
                                 pending[k].size);
                }
                pending.erase(pending.begin(), pending.begin() + std::ptrdiff_t(k));
                if (pending.empty()) {
                    used = 0;
                }
            };
            // Waits for the oldest pending batch to be placed; false when another thread failed.
            auto drain_oldest = [&] {
                const std::size_t placed = output.wait_placed(pending.front().batch);
                if (placed == 0) {
                    return false;
                }
                copy_placed(placed);
                return true;
            };
            for (;;) {
                const std::size_t b = next.fetch_add(1);
                if (b >= batches || output.aborted()) {
                    break;
                }
                PairSink sink(columns, limits, plan.reserve[b], used);
                scan(b, sink);
                pending.push_back(Pending{b, used, sink.size() - used});
                used = sink.size();
                copy_placed(output.finished(b, pending.back().size));
                // Run ahead of a stalled neighbour (a descheduled thread) by a bounded amount
                // only.
                if (pending.size() >= max_pending_batches && !drain_oldest()) {
                    break;
                }
            }
            while (!pending.empty() && drain_oldest()) {
            }
        } catch (...) {
            errors[t] = std::current_exception();
            output.abort();
        }
    });
    for (PairColumns& c : scratch) {
        c.clear();
    }
    for (const std::exception_ptr& e : errors) {
        if (e) {
            std::rethrow_exception(e);
        }
    }
    output.finish();
}

} // namespace tricell::detail
