// Where found pairs go: a PairSink appends them to struct-of-arrays columns through raw
// pointers. In storing mode the columns belong to a NeighborList and grow geometrically (a
// push_back per field would re-check capacity five times per pair), refusing to grow past
// max_pairs. In block mode they are a fixed block of a few hundred pairs that is handed to a
// visitor each time it fills (for_each_pair), with shifts already in the caller's frame. Either
// way add() is the same few stores; only the rare "full" path differs.
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>

#include <Eigen/Core>

#include "tricell/error.hpp"
#include "tricell/neighbor_list.hpp"

namespace tricell::detail {

/// The refusal of a stored list that outgrew NeighborOptions::max_pairs (the sink here and the
/// threads' ordered output both throw it).
[[noreturn]] inline void fail_list_over_limit(std::size_t limit) {
    fail<InvalidArgument>("the neighbour list has more than max_pairs = ", limit,
                          " pairs; raise NeighborOptions::max_pairs to allow it");
}

/// The columns a storing sink fills (null: not stored).
struct PairColumns {
    PairArray<std::uint32_t>* i = nullptr;
    PairArray<std::uint32_t>* j = nullptr;
    PairArray<std::int32_t>* shifts = nullptr;
    PairArray<double>* distances = nullptr;
    PairArray<double>* vectors = nullptr;
};

class PairSink {
  public:
    static constexpr std::size_t block_size = 256;

    /// Storing mode: appends to `columns` after their first `start` pairs (kept), starting with
    /// room for `initial` more, never more than `limit` pairs in all (0: no limit).
    PairSink(const PairColumns& columns, std::size_t limit, std::size_t initial,
             std::size_t start = 0)
        : columns_(columns), size_(start), limit_(limit) {
        resize(limit_ != 0 ? std::min(start + initial, std::max(start, limit_)) : start + initial);
    }

    /// Block mode: every block_size pairs (and at finish()) calls on_block(context, block),
    /// with shifts mapped by `to_caller` when `map_shifts`.
    PairSink(void (*on_block)(void*, const PairBlock&), void* context,
             const Eigen::Matrix3i& to_caller, bool map_shifts)
        : on_block_(on_block), context_(context), to_caller_(to_caller), map_shifts_(map_shifts),
          store_squares_(true) {
        pi_ = block_i_;
        pj_ = block_j_;
        ps_ = block_shifts_;
        pd_ = block_d_sq_;
        pv_ = block_vectors_;
        capacity_ = block_size;
    }

    void add(std::uint32_t i, std::uint32_t j, int sa, int sb, int sc, double dx, double dy,
             double dz, double d_sq) {
        if (size_ == capacity_) {
            full();
        }
        pi_[size_] = i;
        pj_[size_] = j;
        if (ps_ != nullptr) {
            ps_[3 * size_] = sa;
            ps_[3 * size_ + 1] = sb;
            ps_[3 * size_ + 2] = sc;
        }
        if (pd_ != nullptr) {
            pd_[size_] = store_squares_ ? d_sq : std::sqrt(d_sq);
        }
        if (pv_ != nullptr) {
            pv_[3 * size_] = dx;
            pv_[3 * size_ + 1] = dy;
            pv_[3 * size_ + 2] = dz;
        }
        ++size_;
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
    void full() {
        if (on_block_ != nullptr) {
            flush();
            return;
        }
        if (limit_ != 0 && capacity_ >= limit_) {
            fail_list_over_limit(limit_);
        }
        std::size_t next = std::max<std::size_t>(1024, capacity_ * 2);
        if (limit_ != 0) {
            next = std::min(next, limit_);
        }
        resize(next);
    }

    void flush() {
        if (size_ == 0) {
            return;
        }
        if (map_shifts_) {
            for (std::size_t k = 0; k < size_; ++k) {
                Eigen::Map<Eigen::Vector3i> s(ps_ + 3 * k);
                s = (to_caller_ * s).eval();
            }
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

    PairColumns columns_;
    std::size_t size_ = 0;
    std::uint32_t* pi_ = nullptr;
    std::uint32_t* pj_ = nullptr;
    std::int32_t* ps_ = nullptr;
    double* pd_ = nullptr;
    double* pv_ = nullptr;
    std::size_t capacity_ = 0, limit_ = 0;

    // Block mode.
    void (*on_block_)(void*, const PairBlock&) = nullptr;
    void* context_ = nullptr;
    Eigen::Matrix3i to_caller_ = Eigen::Matrix3i::Identity();
    bool map_shifts_ = false;
    bool store_squares_ = false;
    std::uint32_t block_i_[block_size];
    std::uint32_t block_j_[block_size];
    std::int32_t block_shifts_[3 * block_size];
    double block_d_sq_[block_size];
    double block_vectors_[3 * block_size];
};

} // namespace tricell::detail
