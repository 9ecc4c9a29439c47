// A test-only preload library for test_out_of_memory.py: it replaces the global operator new and
// delete of the process it is preloaded into (LD_PRELOAD), so that the C++ allocations of the
// tricell module and library go through it, and counts them. Once armed, the k-th allocation
// from then on throws std::bad_alloc, as the C API's alloc_test does in its own program (the
// nothrow forms are counted but never failed). The
// test drives it through ctypes; nothing of it is part of the module or the library.
#include <atomic>
#include <cstddef>
#include <cstdlib>
#include <new>

namespace {
std::atomic<long> allocations_left{-1}; // -1: never fail
std::atomic<long> live{0};              // allocations not yet freed
std::atomic<long> failed{0};            // allocations refused so far

// `may_fail`: false for the nothrow forms, whose callers expect a null pointer and do without
// (std::stable_sort's buffer): they are not failed, so every failure injected throws.
void* allocate(std::size_t size, std::size_t alignment, bool may_fail = true) {
    if (may_fail && allocations_left.load() >= 0 && allocations_left.fetch_sub(1) == 0) {
        failed.fetch_add(1);
        throw std::bad_alloc();
    }
    size = size == 0 ? 1 : size;
    void* p = alignment <= alignof(std::max_align_t)
                  ? std::malloc(size)
                  : std::aligned_alloc(alignment, (size + alignment - 1) / alignment * alignment);
    if (p == nullptr) {
        throw std::bad_alloc();
    }
    live.fetch_add(1);
    return p;
}

void release(void* p) noexcept {
    if (p != nullptr) {
        live.fetch_sub(1);
        std::free(p);
    }
}
} // namespace

extern "C" {
/// Makes the allocation `k` from now (0: the next one) fail; -1 disarms.
void tricell_alloc_hook_fail_at(long k) {
    allocations_left.store(k);
}
/// Allocations made through operator new and not yet deleted.
long tricell_alloc_hook_live() {
    return live.load();
}
/// Allocations refused so far.
long tricell_alloc_hook_failed() {
    return failed.load();
}
}

void* operator new(std::size_t size) {
    return allocate(size, 0);
}
void* operator new[](std::size_t size) {
    return allocate(size, 0);
}
void* operator new(std::size_t size, std::align_val_t alignment) {
    return allocate(size, std::size_t(alignment));
}
void* operator new[](std::size_t size, std::align_val_t alignment) {
    return allocate(size, std::size_t(alignment));
}
void* operator new(std::size_t size, const std::nothrow_t&) noexcept {
    try {
        return allocate(size, 0, false);
    } catch (...) {
        return nullptr;
    }
}
void* operator new[](std::size_t size, const std::nothrow_t&) noexcept {
    try {
        return allocate(size, 0, false);
    } catch (...) {
        return nullptr;
    }
}
void operator delete(void* p) noexcept {
    release(p);
}
void operator delete[](void* p) noexcept {
    release(p);
}
void operator delete(void* p, std::size_t) noexcept {
    release(p);
}
void operator delete[](void* p, std::size_t) noexcept {
    release(p);
}
void operator delete(void* p, std::align_val_t) noexcept {
    release(p);
}
void operator delete[](void* p, std::align_val_t) noexcept {
    release(p);
}
void operator delete(void* p, std::size_t, std::align_val_t) noexcept {
    release(p);
}
void operator delete[](void* p, std::size_t, std::align_val_t) noexcept {
    release(p);
}
void operator delete(void* p, const std::nothrow_t&) noexcept {
    release(p);
}
void operator delete[](void* p, const std::nothrow_t&) noexcept {
    release(p);
}
