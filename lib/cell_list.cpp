#include "tricell/cell_list.hpp"

#include <algorithm>

#include "detail/parallel.hpp"

namespace tricell {

void LinkedCellList::build(const std::vector<std::uint32_t>& cell_of, std::size_t cell_count) {
    head_.assign(cell_count, end);
    next_.resize(cell_of.size());
    // Insert in reverse so each chain lists its atoms in increasing original index.
    for (std::size_t i = cell_of.size(); i-- > 0;) {
        next_[i] = head_[cell_of[i]];
        head_[cell_of[i]] = static_cast<std::int32_t>(i);
    }
}

// The threaded counting sort: thread t counts the cells of its contiguous range of atoms, the
// offsets are laid out cell by cell and, within a cell, range by range (so the sort stays stable),
// and each thread scatters its range from its own cursors. Three passes over the atoms or cells,
// each split between the threads; the (cell, thread) table costs 4 bytes per cell per thread.
void SortedCellList::build_threaded(const std::vector<std::uint32_t>& cell_of,
                                    std::size_t cell_count, std::size_t threads) {
    const std::size_t n = cell_of.size();
    std::vector<std::uint32_t>& cursor = cursor_; // [t * cell_count + c]
    cursor.assign(threads * cell_count, 0);
    detail::parallel_ranges(n, threads, [&](std::size_t begin, std::size_t end, std::size_t t) {
        std::uint32_t* count = cursor.data() + t * cell_count;
        for (std::size_t i = begin; i < end; ++i) {
            ++count[cell_of[i]];
        }
    });
    // Atoms in each range of cells, then the offsets within each range.
    std::vector<std::uint32_t> before(threads + 1, 0);
    detail::parallel_ranges(cell_count, threads,
                            [&](std::size_t begin, std::size_t end, std::size_t t) {
                                std::uint32_t sum = 0;
                                for (std::size_t c = begin; c < end; ++c) {
                                    for (std::size_t u = 0; u < threads; ++u) {
                                        sum += cursor[u * cell_count + c];
                                    }
                                }
                                before[t + 1] = sum;
                            });
    for (std::size_t t = 0; t < threads; ++t) {
        before[t + 1] += before[t];
    }
    start_.resize(cell_count + 1);
    detail::parallel_ranges(cell_count, threads,
                            [&](std::size_t begin, std::size_t end, std::size_t t) {
                                std::uint32_t running = before[t];
                                for (std::size_t c = begin; c < end; ++c) {
                                    start_[c] = running;
                                    for (std::size_t u = 0; u < threads; ++u) {
                                        const std::uint32_t count = cursor[u * cell_count + c];
                                        cursor[u * cell_count + c] = running;
                                        running += count;
                                    }
                                }
                            });
    start_[cell_count] = static_cast<std::uint32_t>(n);
    order_.resize(n);
    detail::parallel_ranges(n, threads, [&](std::size_t begin, std::size_t end, std::size_t t) {
        std::uint32_t* next = cursor.data() + t * cell_count;
        for (std::size_t i = begin; i < end; ++i) {
            order_[next[cell_of[i]]++] = static_cast<std::uint32_t>(i);
        }
    });
}

void SortedCellList::build(const std::vector<std::uint32_t>& cell_of, std::size_t cell_count,
                           std::size_t threads) {
    // The (cell, thread) table stays within twice the serial sort's memory (atoms plus cells).
    threads =
        std::min(threads, 2 * (cell_of.size() + cell_count) / std::max<std::size_t>(cell_count, 1));
    if (threads > 1) {
        build_threaded(cell_of, cell_count, threads);
        return;
    }
    start_.assign(cell_count + 1, 0);
    for (const std::uint32_t c : cell_of) {
        ++start_[c + 1];
    }
    for (std::size_t c = 0; c < cell_count; ++c) {
        start_[c + 1] += start_[c];
    }
    order_.resize(cell_of.size());
    // Scatter using start_ as running cursors, then shift them back.
    for (std::size_t i = 0; i < cell_of.size(); ++i) {
        order_[start_[cell_of[i]]++] = static_cast<std::uint32_t>(i);
    }
    for (std::size_t c = cell_count; c > 0; --c) {
        start_[c] = start_[c - 1];
    }
    start_[0] = 0;
}

} // namespace tricell
