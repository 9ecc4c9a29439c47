// Neighbour lists in a periodic triclinic box (CONTRACT.md section 2).
//
// The search works in fractional space. Each position is wrapped into the box along periodic
// axes (remembering the integer image it came from), binned into a CellGrid, and the cells are
// listed by a SortedCellList (default) or a LinkedCellList. Every cell is then paired with the
// cells of the Stencil, each stencil entry carrying its image shift as a precomputed Cartesian
// vector, and every candidate pair is tested against the cutoff. The image shift reported for a
// pair is relative to the caller's own positions: S = (cell shift) + (image of i) - (image of j),
// so D = x_j - x_i + H S holds for the positions as given, even far outside the box.
//
// Full lists report every ordered (i, j, S) with |D| < cutoff except (i, i, 0). Half lists walk
// the half stencil (no filtering of a full enumeration) and report each pair once, oriented
// canonically: i < j, or for i == j (an atom and its own image) S lexicographically positive.
// That orientation does not depend on the grid, so neither does any result.
//
// Two ways to consume pairs: compute() stores them struct-of-arrays in a reusable NeighborList
// (optionally sorted by i, j, S with per-atom offsets), and for_each_pair() calls a function
// for each pair without storing anything.
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "tricell/box.hpp"
#include "tricell/cell_list.hpp"
#include "tricell/export.hpp"
#include "tricell/grid.hpp"
#include "tricell/stencil.hpp"
#include "tricell/types.hpp"

namespace tricell {

enum class CellListKind { sorted, linked };

/// Which per-pair quantities compute() stores besides i and j.
struct Quantities {
    bool shifts = true;    ///< S, three ints per pair
    bool distances = true; ///< d = |D|
    bool vectors = false;  ///< D, three doubles per pair
};

struct TRICELL_API NeighborOptions {
    /// Pairs with |D| < cutoff (strict) are reported. Must be finite and > 0.
    double cutoff = 0;
    /// Report each pair once (canonical orientation) instead of both orientations.
    bool half = false;
    /// Sort by i, then j, then S lexicographically, and fill NeighborList::offsets().
    bool sorted = false;
    Quantities quantities;
    /// Target cells per cutoff along each axis (>= 1). Never changes the result, only the speed.
    double cells_per_cutoff = 1;
    CellListKind cell_list = CellListKind::sorted;
    /// Refuse (InvalidArgument) when the estimated or actual number of stored pairs exceeds this;
    /// 0 means no limit. The default, 5e8 pairs, is about 14 GB of i, j, S, d
    /// (26 GB with D).
    std::size_t max_pairs = 500'000'000;
    /// Cap on grid cells; 0 means 4 N + 64. Memory follows atoms, not volume.
    std::size_t max_cells = 0;
    /// Search a strongly skewed periodic cell in its reduced twin (same lattice, rounder cell),
    /// so a sheared box costs what the reduced one costs. Never changes the result.
    bool reduce_cell = true;
    /// Threads for NeighborSearch::compute(); 0 means all hardware threads. The stored list is
    /// identical, pair for pair and in the same order, whatever the number of threads.
    /// (for_each_pair() always runs on the calling thread.)
    int threads = 1;

    /// Throws InvalidArgument naming the offending field and value.
    void validate() const;
};

/// What the visitor of for_each_pair() receives. `vector` is D = x_j - x_i + H shift.
struct Pair {
    std::uint32_t i;
    std::uint32_t j;
    Shift shift;
    Eigen::Vector3d vector;
    double distance_sq;
    double distance() const { return std::sqrt(distance_sq); }
};

namespace detail {
/// An allocator that leaves new elements of trivial types uninitialised, so that growing a pair
/// array does not first write zeros over memory that is about to be overwritten.
template <class T> struct UninitializedAllocator : std::allocator<T> {
    template <class U> struct rebind { using other = UninitializedAllocator<U>; };
    UninitializedAllocator() = default;
    template <class U>
    UninitializedAllocator(const UninitializedAllocator<U>&) noexcept {} // NOLINT
    template <class U> void construct(U* p) noexcept { ::new (static_cast<void*>(p)) U; }
    template <class U, class... Args> void construct(U* p, Args&&... args) {
        ::new (static_cast<void*>(p)) U(std::forward<Args>(args)...);
    }
};
} // namespace detail

/// The array type of a NeighborList's columns: a std::vector whose growth skips zero-filling.
template <class T> using PairArray = std::vector<T, detail::UninitializedAllocator<T>>;

/// Stored pairs, struct-of-arrays. Reuse one object across calls to keep its buffers.
class TRICELL_API NeighborList {
  public:
    std::size_t size() const { return i_.size(); }
    bool empty() const { return i_.empty(); }
    const PairArray<std::uint32_t>& i() const { return i_; }
    const PairArray<std::uint32_t>& j() const { return j_; }
    /// 3 ints per pair (Sa, Sb, Sc), empty unless Quantities::shifts.
    const PairArray<std::int32_t>& shifts() const { return shifts_; }
    /// Empty unless Quantities::distances.
    const PairArray<double>& distances() const { return distances_; }
    /// 3 doubles per pair (Dx, Dy, Dz), empty unless Quantities::vectors.
    const PairArray<double>& vectors() const { return vectors_; }
    /// With sorted output: pairs of atom i are [offsets[i], offsets[i + 1]). Empty otherwise.
    const std::vector<std::size_t>& offsets() const { return offsets_; }

    Shift shift(std::size_t k) const {
        return Shift(shifts_[3 * k], shifts_[3 * k + 1], shifts_[3 * k + 2]);
    }
    Eigen::Vector3d vector(std::size_t k) const {
        return Eigen::Vector3d(vectors_[3 * k], vectors_[3 * k + 1], vectors_[3 * k + 2]);
    }
    /// Empties the list, keeping the capacity.
    void clear();

  private:
    friend class NeighborSearch;
    friend class VerletList;
    PairArray<std::uint32_t> i_, j_;
    PairArray<std::int32_t> shifts_;
    PairArray<double> distances_, vectors_;
    std::vector<std::size_t> offsets_;
    // Per-thread lists of a threaded compute(), kept so that their memory is reused by the next
    // call instead of being faulted in again.
    std::vector<NeighborList> partial_;
};

/// The search structure for one configuration: grid, cell list, stencil and wrapped positions.
/// build() once, then compute() and/or for_each_pair(); rebuild when positions or the box
/// change. An object can be reused to keep its buffers.
class TRICELL_API NeighborSearch {
  public:
    /// Validates everything (cutoff, positions, limits) before any work.
    void build(const Box& box, PointsView positions, const NeighborOptions& options);

    /// Stores the pairs into `out`. On error `out` is left empty, never half written.
    void compute(NeighborList& out) const;

    /// Calls visit(const Pair&) once per pair of the full or half list (as built), in
    /// unspecified order. Stores nothing.
    template <class Visit> void for_each_pair(Visit&& visit) const;

    const CellGrid& grid() const { return grid_; }
    const Stencil& stencil() const { return stencil_; }
    const SortedCellList& sorted_cells() const { return sorted_; }
    const LinkedCellList& linked_cells() const { return linked_; }
    /// Expected number of pairs from the density (what max_pairs is checked against first).
    double estimated_pairs() const { return estimated_pairs_; }
    std::size_t atom_count() const { return atom_count_; }

  private:
    // A row of the stencil: offsets (da, db, dc) for dc in [dc_lo, dc_hi]. In the sorted layout
    // the cells of one row are consecutive in memory (c varies fastest), so a row is scanned as
    // at most a few contiguous atom ranges instead of one range per offset.
    struct StencilRow {
        int da, db, dc_lo, dc_hi;
    };

    template <class Emit>
    void traverse(Emit&& emit, std::size_t cell_begin, std::size_t cell_end) const;
    template <bool Half, class Emit>
    void traverse_sorted(Emit&& emit, std::size_t cell_begin, std::size_t cell_end) const;
    template <bool Half, class Emit>
    void traverse_linked(Emit&& emit, std::size_t cell_begin, std::size_t cell_end) const;
    // Calls piece(begin, end, own, sa, sb, sc) for each contiguous sorted atom range that the
    // stencil rows reach from cell c1, with its image shift.
    template <class Piece> void for_each_row_piece(std::size_t c1, Piece&& piece) const;
    // Estimated work per cell (candidate pairs), for splitting cells between threads.
    std::vector<double> cell_costs() const;
    // Maps shifts found in the reduced frame to the caller's lattice vectors.
    void to_caller_frame(PairArray<std::int32_t>& shifts) const;
    // Appends the chunks' lists to `out` (which holds chunk 0) in chunk order.
    static void append_in_order(NeighborList& out, std::vector<NeighborList>& partial,
                                const std::vector<std::size_t>& sizes, bool shifts, bool distances,
                                bool vectors);
    template <class CellPair>
    void for_each_cell_pair(CellPair&& cell_pair, std::size_t cell_begin,
                            std::size_t cell_end) const;

    NeighborOptions options_;
    Eigen::Matrix3d h_ = Eigen::Matrix3d::Identity(); // of the search frame
    // Shifts in the search frame map to the caller's as S = to_caller_ * S' (identity unless
    // the cell was reduced).
    Eigen::Matrix3i to_caller_ = Eigen::Matrix3i::Identity();
    bool reduced_frame_ = false;
    bool built_ = false;
    double cutoff_sq_ = 0;
    std::size_t atom_count_ = 0;
    double estimated_pairs_ = 0;
    CellGrid grid_;
    Stencil stencil_;
    std::vector<StencilRow> rows_;
    SortedCellList sorted_;
    LinkedCellList linked_;
    // Per axis, for t = c + delta in [-reach, n + reach): the neighbour cell coordinate
    // (-1 outside an open axis) and its image shift, at index t + reach.
    std::vector<int> neighbor_cell_[3];
    std::vector<int> neighbor_shift_[3];
    // Sorted layout: wrapped Cartesian positions struct-of-arrays in cell order and the image
    // each came from (3 ints per atom, x = wrapped + H image).
    std::vector<double> x_, y_, z_;
    std::vector<std::int32_t> sorted_image_;
    // Linked layout: wrapped positions and images in the caller's order.
    std::vector<double> wrapped_;
    std::vector<std::int32_t> image_;
};

/// Convenience: build a search and store its pairs.
TRICELL_API NeighborList compute_neighbors(const Box& box, PointsView positions,
                                           const NeighborOptions& options);
TRICELL_API void compute_neighbors(const Box& box, PointsView positions,
                                   const NeighborOptions& options, NeighborList& out);

/// Convenience: visit every pair without storing (see NeighborSearch::for_each_pair).
template <class Visit>
void for_each_pair(const Box& box, PointsView positions, const NeighborOptions& options,
                   Visit&& visit) {
    NeighborSearch search;
    search.build(box, positions, options);
    search.for_each_pair(std::forward<Visit>(visit));
}

} // namespace tricell

#include "tricell/detail/pair_traversal.hpp"
