// The memory of a stored list and the limits on it (docs/memory.md is this model in words).
//
// A list's columns cost a fixed number of bytes per pair (i and j 8, S 12, d 8, D 24). Besides
// the list, a column that grows (a list past its estimate) holds its old and its new copy for
// the time of the copy; grouping scatters one column at a time (the widest one extra); sorting
// holds an 8-byte permutation and one column extra; both write 8-byte offsets and cursors per atom.
// Keeping the nearest within the cutoff (max_neighbors) holds each pair's (d, index) grouped by
// centre (then, in the same room, one column being gathered) and the output order, and per atom
// each centre's offsets, count and cut.
// The peak of a list is its columns plus the working space of its order. NeighborOptions::max_bytes
// bounds that peak, NeighborOptions::max_pairs the pairs: ListLimits turns both into pair
// counts for the stores, and refuses an estimate or a list past either with a PairLimitError
// that names the pairs, their bytes and the limit.
#pragma once

#include <cstddef>
#include <string>

#include "tricell/neighbor_list.hpp"

namespace tricell::detail {

/// Bytes of a list of given pairs and atoms, for one set of stored columns and order.
struct ListMemory {
    double per_pair = 0;       ///< the stored columns
    double widest = 0;         ///< the widest stored column (held twice while it grows)
    double order_per_pair = 0; ///< grouping's or sorting's working space
    double per_atom = 0;       ///< offsets and cursors (grouped or sorted)
    bool shifts = false, distances = false, vectors = false; ///< stored besides i and j
    const char* order = ""; ///< "sort", "group", "select" or "" (unordered)

    /// The list at its peak: columns and the order's working space.
    double peak(double pairs, std::size_t atoms) const;
    /// The columns while one of them grows.
    double growing(double pairs) const;
    /// "i, j, S, d": the stored columns (for messages only: built when asked).
    std::string columns() const;
    /// "52 bytes a pair of i, j, S, d, D + 32 a pair to sort them + 16 an atom".
    std::string rates() const;
};

/// The memory model of the list `options` asks for (its quantities and order; a sorted list
/// stores S while it sorts).
ListMemory list_memory(const NeighborOptions& options);

/// options.max_pairs and options.max_bytes for a list of `atoms` atoms, as pair counts.
class ListLimits {
  public:
    ListLimits() = default; ///< no limit
    /// `subject` names the list in a refusal of its size (fail_size()).
    ListLimits(const NeighborOptions& options, std::size_t atoms,
               const char* subject = "the neighbour list has too many pairs");

    /// Refuses `pairs` pairs estimated from the density at `cutoff` past either limit before
    /// anything is allocated ("cutoff 5 would give about 1e9 pairs for 1000 atoms (estimated from
    /// the density), ...").
    void check_estimate(double pairs, double cutoff) const;
    /// The most pairs a list may hold (0: no limit).
    std::size_t pairs() const { return pairs_; }
    /// The refusal of a list that reached `size` > pairs() pairs while it was written.
    [[noreturn]] void fail_size(std::size_t size) const;
    /// Refuses to grow columns of `size` pairs when the copy would pass max_bytes.
    void check_growth(std::size_t size) const {
        if (growing_ != 0 && size > growing_) {
            fail_growth(size);
        }
    }

  private:
    [[noreturn]] void fail_growth(std::size_t size) const;

    ListMemory memory_;
    const char* subject_ = "the neighbour list has too many pairs";
    std::size_t atoms_ = 0;
    std::size_t max_pairs_ = 0;
    std::size_t max_bytes_ = 0;
    std::size_t pairs_ = 0;   // min(max_pairs, the pairs whose peak fits max_bytes)
    std::size_t growing_ = 0; // the most pairs whose columns may grow within max_bytes
};

} // namespace tricell::detail
