// The tensors the ops return. Pair columns run to hundreds of megabytes, and every call
// allocates them afresh: PyTorch's CPU allocator maps such blocks in pages of 4 KiB, whose first
// touch costs more than the search that fills them. An output of 4 MiB or more is therefore
// allocated here, aligned to 2 MiB and advised to use transparent huge pages (as numpy does for
// its large arrays), one of 128 KiB or more in whole pages, and handed to torch with its
// deleter; a small one is an ordinary at::empty.
//
// Fresh memory is zeroed by the kernel on first touch, which costs about as much as filling
// it. So the deleter does not return a block to the system at once: it
// keeps the last few freed blocks (at most block_cache_blocks of them, block_cache_bytes in
// all), and the next output that fits one (at most a fifth smaller, so that a tensor never holds
// much more memory than its size) takes it. A loop that
// drops each call's tensors before the next call (a training step) thus writes into memory
// already faulted in, and at most block_cache_bytes stay held between calls.
#pragma once

#include <algorithm>
#include <cstdint>
#include <cstdlib>
#include <mutex>
#include <utility>
#include <vector>

#include <sys/mman.h>

#include <torch/types.h>

namespace tricell::torch_ops {

constexpr std::size_t block_cache_blocks = 8;
constexpr std::size_t block_cache_bytes = std::size_t(256) << 20;

/// The freed large output blocks kept for reuse (see above).
class BlockCache {
  public:
    /// A kept block of at least `bytes` and at most a fifth more (the smallest such), or null.
    void* take(std::size_t bytes, std::size_t& size) {
        std::lock_guard<std::mutex> lock(mutex_);
        auto best = blocks_.end();
        for (auto b = blocks_.begin(); b != blocks_.end(); ++b) {
            if (b->second >= bytes && b->second <= bytes + bytes / 5 &&
                (best == blocks_.end() || b->second < best->second)) {
                best = b;
            }
        }
        if (best == blocks_.end()) {
            return nullptr;
        }
        void* data = best->first;
        size = best->second;
        held_ -= size;
        blocks_.erase(best);
        return data;
    }
    /// Keeps the block (evicting the oldest ones past the limits) or frees it.
    void give(void* data, std::size_t size) {
        std::vector<void*> evicted;
        {
            std::lock_guard<std::mutex> lock(mutex_);
            if (size > block_cache_bytes) {
                evicted.push_back(data);
            } else {
                blocks_.emplace_back(data, size);
                held_ += size;
                while (blocks_.size() > block_cache_blocks || held_ > block_cache_bytes) {
                    evicted.push_back(blocks_.front().first);
                    held_ -= blocks_.front().second;
                    blocks_.erase(blocks_.begin());
                }
            }
        }
        for (void* p : evicted) {
            std::free(p);
        }
    }

  private:
    std::mutex mutex_;
    std::vector<std::pair<void*, std::size_t>> blocks_; // oldest first
    std::size_t held_ = 0;
};

inline BlockCache& block_cache() {
    static BlockCache* cache = new BlockCache; // never destroyed: deleters may run at exit
    return *cache;
}

inline at::Tensor output_tensor(at::IntArrayRef shape, at::ScalarType dtype) {
    constexpr std::size_t huge_page = std::size_t(2) << 20, page = 4096;
    std::size_t bytes = c10::elementSize(dtype);
    for (const auto extent : shape) {
        bytes *= std::size_t(extent);
    }
    if (bytes < 32 * page) { // the C library's own heap, never freshly mapped
        return at::empty(shape, at::TensorOptions().dtype(dtype));
    }
    const std::size_t align = bytes < 2 * huge_page ? page : huge_page;
    std::size_t rounded = (bytes + align - 1) / align * align;
    void* data = block_cache().take(rounded, rounded);
    if (data == nullptr) {
        data = std::aligned_alloc(align, rounded);
        TORCH_CHECK(data != nullptr, "cannot allocate ", bytes, " bytes for an output tensor");
#ifdef MADV_HUGEPAGE
        if (align == huge_page) {
            madvise(data, rounded, MADV_HUGEPAGE); // advice only: without it the pages are small
        }
#endif
    }
    return at::from_blob(
        data, shape, [rounded](void* p) { block_cache().give(p, rounded); },
        at::TensorOptions().dtype(dtype));
}

} // namespace tricell::torch_ops
