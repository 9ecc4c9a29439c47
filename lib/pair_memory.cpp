// Memory for the columns of a neighbour list and for the search's large per-atom and per-cell
// arrays (PairArray, pair_columns.hpp). A large list is written once per call through hundreds
// of megabytes, and with 4 KB pages every few pairs cross into a page whose translation is not
// cached; in 2 MB pages the translations of a whole list fit the TLB. Each fresh page also costs
// a fault, which zeroes it, and on a virtual machine a small page's fault can take ~10 us: an
// array of 10^7 positions costs 6 * 10^4 faults each time it is allocated anew in small pages,
// about a hundred in huge ones. So an array of at least huge_page bytes is aligned to and
// rounded up to whole huge pages and advised to the kernel as huge-page memory (Linux
// transparent huge pages in "madvise" mode, Debian's default, gives huge pages only to memory
// advised so). Smaller arrays come from operator new.
#include <cstdlib>
#include <new>

#include "tricell/neighbor_list.hpp"

#if defined(__linux__)
#include <sys/mman.h>
#endif

namespace tricell::detail {

namespace {
constexpr std::size_t huge_page = std::size_t(2) << 20;

bool in_huge_pages(std::size_t bytes) {
    return bytes >= huge_page;
}
} // namespace

void* allocate_pair_memory(std::size_t bytes) {
    if (!in_huge_pages(bytes)) {
        return ::operator new(bytes);
    }
    const std::size_t rounded = (bytes + huge_page - 1) / huge_page * huge_page;
    if (rounded < bytes) {
        throw std::bad_alloc();
    }
    void* memory = std::aligned_alloc(huge_page, rounded);
    if (memory == nullptr) {
        throw std::bad_alloc();
    }
#if defined(__linux__) && defined(MADV_HUGEPAGE)
    madvise(memory, rounded, MADV_HUGEPAGE); // advice only: without it the pages are small
#endif
    return memory;
}

void free_pair_memory(void* memory, std::size_t bytes) noexcept {
    if (!in_huge_pages(bytes)) {
        ::operator delete(memory);
    } else {
        std::free(memory);
    }
}

} // namespace tricell::detail
