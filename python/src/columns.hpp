// The output arrays of NeighborList, VerletList and compute_batch, and the quantity letters
// that name them.
//
// A quantities argument is read once, by parse_quantities(), into a QuantitySpec: the columns
// in the caller's order and what the search must store for them. One table of letters holds the
// whole rule: i and j (uint32), S (shifts, N x 3 int32), d (distances, float64), D (vectors,
// N x 3 float64), P (pairs (i, j), N x 2 uint32) and o (per-atom offsets of a list grouped by i,
// int64). An unknown letter is a ValueError naming it and the quantities argument.
//
// The arrays are the columns of a computed list, either copied into fresh numpy arrays or
// handed out as views whose base object keeps the list's buffers alive; P and o are always
// fresh arrays (i and j are stored apart, the offsets in another integer type).
#pragma once

#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include <pybind11/pybind11.h>

#include <tricell/batch.hpp>
#include <tricell/neighbor_list.hpp>

namespace tricell::python {

namespace py = pybind11;

/// What one quantity letter names.
enum class Column { i, j, shifts, distances, vectors, pairs, offsets };

/// A quantities argument, read once.
struct QuantitySpec {
    std::vector<Column> columns; ///< one per letter, in the caller's order
    Quantities stored;           ///< the columns the search stores for them (S, d, D)
    bool offsets = false;        ///< whether o is asked (a list grouped by i has them)
};

/// `letters` (the quantities argument) as a QuantitySpec; ValueError for an unknown letter,
/// naming it, or for no letter at all.
QuantitySpec parse_quantities(const std::string& letters);

/// The columns of a computed list as numpy arrays in the order of `spec`: one array for a
/// single letter, a tuple otherwise. With `owner` non-null the arrays (except P and o) are views
/// whose base holds `owner`; otherwise they are copies.
py::object pair_columns(const NeighborList& list, const QuantitySpec& spec,
                        const std::shared_ptr<const NeighborList>& owner);

/// Column buffers that the arrays of batch_columns() give back when the caller drops them, lent
/// to the next batch of the same NeighborList, so that its columns reuse memory already faulted
/// in instead of fresh pages; at most one spare buffer per column (the largest).
class ColumnRecycler {
  public:
    /// Swaps the spares into the columns of `list` that hold less room.
    void lend(BatchList& list);
    /// Keeps `column` (a buffer of the column `which`) as that column's spare if it holds more
    /// room than the spare.
    template <class T> void give_back(PairArray<T> PairColumns::*which, PairArray<T>& column);

  private:
    std::mutex mutex_;
    PairColumns spare_;
};

/// The lists of a batch: a tuple of the per-structure pair offsets (int64, structures + 1)
/// followed by the columns of `spec` over all structures (P and o fresh arrays). With `owner`
/// set, views whose base holds `owner`; otherwise the columns are taken out of `list` without a
/// copy, each array owning its own buffer and giving it back to `recycler` when dropped (a
/// letter asked twice is copied the second time).
py::tuple batch_columns(BatchList& list, const QuantitySpec& spec,
                        const std::shared_ptr<const BatchList>& owner,
                        const std::shared_ptr<ColumnRecycler>& recycler);

} // namespace tricell::python
