// Where found pairs go: a PairSink appends them to struct-of-arrays columns through raw
// pointers. In storing mode the columns belong to a NeighborList and grow geometrically (a
// push_back per field would re-check capacity five times per pair), refusing to grow past
// max_pairs or, in bytes, max_bytes (list_limits.hpp). In block mode they are a fixed block of
// about a thousand pairs that is handed to a visitor each time it fills (for_each_pair), with
// shifts already in the caller's frame. Either way add() is the same few stores; only the rare
// "full" path differs.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>

#include "frame/search_frame.hpp"
#include "policy/list_limits.hpp"
#include "scan/distance_kernel.hpp"
#include "scan/range_kernel.hpp"
#include "tricell/error.hpp"
#include "tricell/neighbor_list.hpp"

namespace tricell::detail {

/// The columns of a PairColumns that a storing sink fills (null: not stored).
struct SinkColumns {
    PairArray<std::uint32_t>* i = nullptr;
    PairArray<std::uint32_t>* j = nullptr;
    PairArray<std::int32_t>* shifts = nullptr;
    PairArray<double>* distances = nullptr;
    PairArray<double>* vectors = nullptr;
};

/// The columns of `c` that a search stores: i and j always, S, d and D when asked.
inline SinkColumns stored_columns(PairColumns& c, bool shifts, bool distances, bool vectors) {
    return SinkColumns{&c.i, &c.j, shifts ? &c.shifts : nullptr, distances ? &c.distances : nullptr,
                       vectors ? &c.vectors : nullptr};
}

class PairSink {
  public:
    /// Pairs per block in block mode: at least one kernel call's hits, each stored twice in a
    /// mirrored list (CandidateScanner claims them at once).
    static constexpr std::size_t block_size = 2 * kernel_group * kernel_block;

    /// Storing mode: appends to `columns` after their first `start` pairs (kept), starting with
    /// room for `initial` more, never more than `limits` allow (they must outlive the sink).
    PairSink(const SinkColumns& columns, const ListLimits& limits, std::size_t initial,
             std::size_t start = 0)
        : columns_(columns), size_(start), limit_(limits.pairs()), limits_(&limits) {
        resize(limit_ != 0 ? std::min(start + initial, std::max(start, limit_) + max_claim)
                           : start + initial);
    }

    /// Block mode: every block_size pairs (and at finish()) calls on_block(context, block),
    /// with shifts mapped to the caller's lattice vectors by `frame` (null: left as found).
    PairSink(void (*on_block)(void*, const PairBlock&), void* context, const SearchFrame* frame)
        : on_block_(on_block), context_(context), frame_(frame), store_squares_(true) {
        pi_ = block_i_;
        pj_ = block_j_;
        ps_ = block_shifts_;
        pd_ = block_d_sq_;
        pv_ = block_vectors_;
        capacity_ = block_size;
    }

    /// The next places in each column (null: a column not stored); `squares`: distances holds
    /// d^2 (block mode), not d.
    using Slots = PairSlots;

    /// The most pairs one claim() asks for in storing mode.
    static constexpr std::size_t max_claim = 8 * block_size;

    /// The most pairs one claim() may ask for: a block in block mode, max_claim in storing mode.
    std::size_t claim_limit() const { return on_block_ != nullptr ? block_size : max_claim; }

    /// Places for `count` more pairs, which the caller fills (put()) and then commit()s, at most
    /// `count` of them. Makes room first: storing mode grows the columns, block mode hands out
    /// the current block (`count` <= block_size).
    Slots claim(std::size_t count) {
        if (capacity_ - size_ < count) {
            make_room(count);
        }
        return Slots{pi_ + size_,
                     pj_ + size_,
                     ps_ != nullptr ? ps_ + 3 * size_ : nullptr,
                     pd_ != nullptr ? pd_ + size_ : nullptr,
                     pv_ != nullptr ? pv_ + 3 * size_ : nullptr,
                     store_squares_};
    }

    /// Writes pair k of claimed slots, all but its distance (put_distances()).
    static void put(const Slots& out, std::size_t k, std::uint32_t i, std::uint32_t j, int sa,
                    int sb, int sc, double dx, double dy, double dz) {
        out.i[k] = i;
        out.j[k] = j;
        if (out.shifts != nullptr) {
            out.shifts[3 * k] = sa;
            out.shifts[3 * k + 1] = sb;
            out.shifts[3 * k + 2] = sc;
        }
        if (out.vectors != nullptr) {
            out.vectors[3 * k] = dx;
            out.vectors[3 * k + 1] = dy;
            out.vectors[3 * k + 2] = dz;
        }
    }

    /// Writes the distances of the first `count` claimed pairs from their d^2 (the square roots
    /// taken together, see square_roots()).
    static void put_distances(const Slots& out, const double* d_sq, std::size_t count) {
        if (out.distances == nullptr) {
            return;
        }
        if (out.squares) {
            std::copy(d_sq, d_sq + count, out.distances);
        } else {
            square_roots(d_sq, static_cast<std::uint32_t>(count), out.distances);
        }
    }

    /// Writes pairs [count, 2 count) of claimed slots as pairs [0, count) turned around: (j, i),
    /// -S, -D (a zero component as +0) and the same distance (IEEE negation is exact, so these
    /// are the bits a search from the other atom computes, see candidate_scan.hpp).
    static void put_turned(const Slots& out, std::size_t count) {
        std::copy(out.j, out.j + count, out.i + count);
        std::copy(out.i, out.i + count, out.j + count);
        if (out.shifts != nullptr) {
            for (std::size_t k = 0; k < 3 * count; ++k) {
                out.shifts[3 * count + k] = -out.shifts[k];
            }
        }
        if (out.distances != nullptr) {
            std::copy(out.distances, out.distances + count, out.distances + count);
        }
        if (out.vectors != nullptr) {
            for (std::size_t k = 0; k < 3 * count; ++k) {
                out.vectors[3 * count + k] = -out.vectors[k] + 0.0;
            }
        }
    }

    /// Keeps the first `count` claimed pairs; a stored list refuses to pass its limits here.
    void commit(std::size_t count) {
        size_ += count;
        if (limit_ != 0 && size_ > limit_) {
            limits_->fail_size(size_);
        }
    }

    void add(std::uint32_t i, std::uint32_t j, int sa, int sb, int sc, double dx, double dy,
             double dz, double d_sq) {
        const Slots out = claim(1);
        put(out, 0, i, j, sa, sb, sc, dx, dy, dz);
        put_distances(out, &d_sq, 1);
        commit(1);
    }

    /// Pairs in the columns so far, `start` included (storing mode), or in the current block
    /// (block mode).
    std::size_t size() const { return size_; }

    /// Storing mode: trims the columns to the pairs added. Block mode: hands out the last block.
    void finish() {
        if (on_block_ != nullptr) {
            flush();
        } else {
            resize(size_);
        }
    }

  private:
    void make_room(std::size_t count) {
        if (on_block_ != nullptr) {
            flush();
            return;
        }
        // The copy of a growing column must fit max_bytes. The columns hold room for one claim
        // past the pair limit (commit() refuses when it is used), so a list that reaches the
        // limit is refused there, not by a growth it does not need; nor is one whose columns
        // already hold the room (kept from an earlier, longer list), which copies nothing.
        std::size_t next = std::max({std::size_t(1024), capacity_ * 2, size_ + count});
        if (limit_ != 0) {
            next = std::max(std::min(next, limit_ + max_claim), size_ + count);
        }
        if (next > columns_.i->capacity()) {
            limits_->check_growth(capacity_);
        }
        resize(next);
    }

    void flush() {
        if (size_ == 0) {
            return;
        }
        if (frame_ != nullptr) {
            frame_->to_caller(ps_, size_);
        }
        on_block_(context_, PairBlock{size_, pi_, pj_, ps_, pv_, pd_});
        size_ = 0;
    }

    void resize(std::size_t capacity) {
        capacity_ = capacity;
        columns_.i->resize(capacity);
        columns_.j->resize(capacity);
        pi_ = columns_.i->data();
        pj_ = columns_.j->data();
        if (columns_.shifts != nullptr) {
            columns_.shifts->resize(3 * capacity);
            ps_ = columns_.shifts->data();
        }
        if (columns_.distances != nullptr) {
            columns_.distances->resize(capacity);
            pd_ = columns_.distances->data();
        }
        if (columns_.vectors != nullptr) {
            columns_.vectors->resize(3 * capacity);
            pv_ = columns_.vectors->data();
        }
    }

    SinkColumns columns_;
    std::size_t size_ = 0;
    std::uint32_t* pi_ = nullptr;
    std::uint32_t* pj_ = nullptr;
    std::int32_t* ps_ = nullptr;
    double* pd_ = nullptr;
    double* pv_ = nullptr;
    std::size_t capacity_ = 0, limit_ = 0;
    const ListLimits* limits_ = nullptr;

    // Block mode.
    void (*on_block_)(void*, const PairBlock&) = nullptr;
    void* context_ = nullptr;
    const SearchFrame* frame_ = nullptr;
    bool store_squares_ = false;
    std::uint32_t block_i_[block_size];
    std::uint32_t block_j_[block_size];
    std::int32_t block_shifts_[3 * block_size];
    double block_d_sq_[block_size];
    double block_vectors_[3 * block_size];
};

} // namespace tricell::detail
