#include "tricell/cell_list.hpp"

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

void SortedCellList::build(const std::vector<std::uint32_t>& cell_of, std::size_t cell_count) {
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
