// Neighbour lists of many independent structures in one call (machine-learning potentials
// evaluate batches of small cells, each with its own box, periodicity and positions).
//
// compute_neighbors_batch() gives every structure exactly the list compute_neighbors() gives
// it alone (same pairs, same order, same bits), and stores all of them one after the other in
// shared struct-of-arrays columns: the pairs of structure s are [pair_offsets[s],
// pair_offsets[s + 1]), with i and j numbering the atoms of s from 0 or, asked for global
// indices, all atoms of the batch in structure order. A front whose structures are concatenated
// in one array (N_total x 3, with a pointer array batch_ptr as machine-learning codes pass
// them) makes each BatchStructure a view into that array, without a copy, and asks for global
// indices: i and j are then indices into the concatenated positions. No pair ever joins two
// structures, also when they overlap in space. One NeighborOptions applies to every structure.
//
// Threads work across structures, not inside one: the structures are cut into contiguous runs
// of about equal estimated cost (a fixed cost per call, one per atom, and the pairs expected
// from the density), one run per thread. Each thread searches its structures in order with a
// search object of its own, so nothing is allocated per structure once the buffers have grown,
// and writes each structure's pairs straight after the last one's: the first run into the
// output's columns, the others into their own, which are then copied after it in structure
// order (a grouped or sorted list goes through a scratch list first). The output is the same,
// array for array, whatever the thread count.
//
// Errors name the structure: "structure 17: position 3 is not finite (got ...)". When several
// structures are bad the one with the lowest index is reported, whatever the thread count, and
// the output is left empty.
#pragma once

#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

#include "tricell/box.hpp"
#include "tricell/export.hpp"
#include "tricell/neighbor_list.hpp"
#include "tricell/types.hpp"

namespace tricell {

/// One structure of a batch: its box (with periodicity) and a view of its positions (N x 3,
/// the caller keeps the memory alive during the call).
struct BatchStructure {
    Box box;
    PointsView positions;
};

namespace detail {
struct BatchWorker; // one thread's search object and scratch list (lib/batch.cpp)
/// Rethrows the tricell::Error in flight with "structure s: " before its message, keeping its
/// type (for the batch's front doors, which check their own per-structure arguments).
[[noreturn]] TRICELL_API void rethrow_for_structure(std::size_t s);
} // namespace detail

class BatchList;

/// How i and j number the atoms of a batch.
enum class BatchIndices {
    /// From 0 within each structure.
    local,
    /// Among all atoms of the batch in structure order: atom_offsets()[s] + the local index, the
    /// index into the concatenated positions when the structures' views lie one after another in
    /// one array. At most 2^32 - 1 atoms in all.
    global,
};

/// Computes the neighbour list of each of `count` structures with `options` (validated once;
/// options.threads threads across structures, 0 = all hardware threads) into `out`, numbering
/// the atoms as `indices` says. On error `out` is left empty and the message names the
/// structure.
TRICELL_API void compute_neighbors_batch(const BatchStructure* structures, std::size_t count,
                                         const NeighborOptions& options, BatchList& out,
                                         BatchIndices indices = BatchIndices::local);

/// The lists of a batch, struct-of-arrays. Reuse one object across calls to keep its buffers.
class TRICELL_API BatchList {
  public:
    BatchList();
    ~BatchList();
    BatchList(BatchList&&) noexcept;
    BatchList& operator=(BatchList&&) noexcept;
    BatchList(const BatchList&) = delete;
    BatchList& operator=(const BatchList&) = delete;

    /// Structures of the last call.
    std::size_t structure_count() const {
        return pair_offsets_.empty() ? 0 : pair_offsets_.size() - 1;
    }
    /// Pairs over all structures.
    std::size_t size() const { return columns_.size(); }
    /// The shared columns (see the accessors below).
    const PairColumns& columns() const { return columns_; }
    /// Pairs of structure s are [pair_offsets()[s], pair_offsets()[s + 1]); size count + 1.
    const std::vector<std::size_t>& pair_offsets() const { return pair_offsets_; }
    /// Atoms of structure s are [atom_offsets()[s], atom_offsets()[s + 1]) in a numbering of
    /// all atoms of the batch (the index space of offsets()); size count + 1.
    const std::vector<std::size_t>& atom_offsets() const { return atom_offsets_; }

    /// How i and j number the atoms (as the last call asked).
    BatchIndices indices() const { return indices_; }
    /// Atom indices within their own structure (0-based per structure), or among all atoms of
    /// the batch with BatchIndices::global (see indices()).
    const PairArray<std::uint32_t>& i() const { return columns_.i; }
    const PairArray<std::uint32_t>& j() const { return columns_.j; }
    /// 3 ints per pair, empty unless Quantities::shifts.
    const PairArray<std::int32_t>& shifts() const { return columns_.shifts; }
    /// Empty unless Quantities::distances.
    const PairArray<double>& distances() const { return columns_.distances; }
    /// 3 doubles per pair, empty unless Quantities::vectors.
    const PairArray<double>& vectors() const { return columns_.vectors; }
    /// With grouped or sorted output: the pairs of atom a of structure s are [offsets[k], offsets[k
    /// + 1]) with k = atom_offsets()[s] + a (indices into the shared columns). Empty otherwise.
    const std::vector<std::size_t>& offsets() const { return columns_.offsets; }

    /// Empties the list, keeping the capacity.
    void clear();

    /// Exchanges the pair columns with `other` (the offsets stay): a front takes the pairs
    /// without a copy, or hands buffers in for the next call to fill (it reuses their capacity).
    void swap_columns(PairColumns& other) noexcept { std::swap(columns_, other); }

  private:
    friend void compute_neighbors_batch(const BatchStructure*, std::size_t, const NeighborOptions&,
                                        BatchList&, BatchIndices);
    PairColumns columns_;
    std::vector<std::size_t> pair_offsets_, atom_offsets_;
    BatchIndices indices_ = BatchIndices::local;
    // One per thread of the last call, kept so that their buffers are reused.
    std::vector<detail::BatchWorker> workers_;
};

/// The same for a vector of structures.
TRICELL_API void compute_neighbors_batch(const std::vector<BatchStructure>& structures,
                                         const NeighborOptions& options, BatchList& out,
                                         BatchIndices indices = BatchIndices::local);

} // namespace tricell
