// The tensors the ops return. Pair columns run to hundreds of megabytes, and every call
// allocates them afresh: PyTorch's CPU allocator maps such blocks in pages of 4 KiB, whose first
// touch costs more than the search that fills them. A large output is therefore allocated here,
// aligned to 2 MiB and advised to use transparent huge pages (as numpy does for its large
// arrays), and handed to torch with its deleter; a small one is an ordinary at::empty.
#pragma once

#include <cstdint>
#include <cstdlib>

#include <sys/mman.h>

#include <torch/types.h>

namespace tricell::torch_ops {

inline at::Tensor output_tensor(at::IntArrayRef shape, at::ScalarType dtype) {
    constexpr std::size_t huge_page = std::size_t(2) << 20;
    std::size_t bytes = c10::elementSize(dtype);
    for (const auto extent : shape) {
        bytes *= std::size_t(extent);
    }
    if (bytes < 2 * huge_page) {
        return at::empty(shape, at::TensorOptions().dtype(dtype));
    }
    const std::size_t rounded = (bytes + huge_page - 1) / huge_page * huge_page;
    void* data = std::aligned_alloc(huge_page, rounded);
    TORCH_CHECK(data != nullptr, "cannot allocate ", bytes, " bytes for an output tensor");
#ifdef MADV_HUGEPAGE
    madvise(data, rounded, MADV_HUGEPAGE); // advice only: without huge pages it still works
#endif
    return at::from_blob(
        data, shape, [](void* p) { std::free(p); }, at::TensorOptions().dtype(dtype));
}

} // namespace tricell::torch_ops
