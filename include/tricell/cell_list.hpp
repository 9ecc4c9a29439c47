// Two cell-list structures over a CellGrid, both built in O(N + C) from the cell of each atom.
//
// LinkedCellList is the classic head/next structure: head[c] is the first atom of cell c and
// next[i] the atom after i in the same cell (-1 ends a chain). It needs no reordering and two
// small arrays, but walking a chain jumps around memory.
//
// SortedCellList is the data-locality structure: a counting sort by cell. cell_start[c] ..
// cell_end(c) is the range of cell c in the sorted order, order[k] the original index of the
// k-th sorted atom. Atoms of one cell are contiguous, so the neighbour search streams through
// positions stored struct-of-arrays in that order. This is the structure the neighbour search
// uses by default (benchmarks/ compares both).
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "tricell/export.hpp"

namespace tricell {

class TRICELL_API LinkedCellList {
  public:
    static constexpr std::int32_t end = -1;

    /// cell_of[i] in [0, cell_count) is the cell of atom i.
    void build(const std::vector<std::uint32_t>& cell_of, std::size_t cell_count);

    /// First atom of cell c, or `end`.
    std::int32_t head(std::size_t c) const { return head_[c]; }
    /// Atom after i in its cell, or `end`.
    std::int32_t next(std::size_t i) const { return next_[i]; }
    std::size_t cell_count() const { return head_.size(); }
    std::size_t atom_count() const { return next_.size(); }

  private:
    std::vector<std::int32_t> head_;
    std::vector<std::int32_t> next_;
};

class TRICELL_API SortedCellList {
  public:
    /// cell_of[i] in [0, cell_count) is the cell of atom i. Stable: atoms of one cell keep their
    /// original relative order. With `threads` > 1 the sort runs on up to that many threads (the
    /// same result; fewer when there are many more cells than atoms, to bound its memory).
    void build(const std::vector<std::uint32_t>& cell_of, std::size_t cell_count,
               std::size_t threads = 1);

    /// Sorted range of cell c: [cell_start(c), cell_end(c)).
    std::uint32_t cell_start(std::size_t c) const { return start_[c]; }
    std::uint32_t cell_end(std::size_t c) const { return start_[c + 1]; }
    /// Original index of the k-th atom in sorted order.
    std::uint32_t original(std::size_t k) const { return order_[k]; }
    const std::vector<std::uint32_t>& order() const { return order_; }
    std::size_t cell_count() const { return start_.empty() ? 0 : start_.size() - 1; }
    std::size_t atom_count() const { return order_.size(); }

  private:
    void build_threaded(const std::vector<std::uint32_t>& cell_of, std::size_t cell_count,
                        std::size_t threads);
    std::vector<std::uint32_t> start_; // cell_count + 1 offsets
    std::vector<std::uint32_t> order_;
    std::vector<std::uint32_t> cursor_; // the threaded sort's (cell, thread) table, kept for reuse
};

} // namespace tricell
