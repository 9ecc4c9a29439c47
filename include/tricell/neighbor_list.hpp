// Neighbour lists in a periodic triclinic box (docs/contract.md): the front door.
//
// NeighborSearch::build() does, once for every backend, everything a search shares: it
// validates the options and positions, picks the search frame (the caller's box, or its reduced
// twin when the cell is strongly skewed), wraps every position into the box along periodic axes
// remembering the integer image it came from, checks the expected pair count against max_pairs
// before anything large is allocated, and hands the wrapped fractional positions to a backend.
// A backend (lib/backends/: dense sorted grid, linked head/next grid, compact hash, octree,
// direct image enumeration) only bins the atoms and enumerates candidate (atom range, atom
// range, image shift) triples; the shared distance test, pair storage, half-list orientation,
// variable cutoffs, threads and their ordered output, sorting and the map of shifts back to the
// caller's lattice vectors live once, in lib/search/. The image shift reported for a pair is
// relative to the caller's own positions, S = (cell shift) + (image of i) - (image of j), so D =
// x_j - x_i + H S holds for the positions as given, even far outside the box.
//
// Full lists report every ordered (i, j, S) with |D| < cutoff except (i, i, 0). Half lists report
// each pair once, oriented canonically: i < j, or for i == j (an atom and its own image) S
// lexicographically positive. That orientation does not depend on the backend or the grid, so
// neither does any result.
//
// Two ways to consume pairs: compute() stores them struct-of-arrays in a reusable NeighborList
// (optionally grouped by i, or sorted by i, j, S, with per-atom offsets), and for_each_pair() calls
// a function for each pair without storing anything (pairs reach it in blocks of up to about a
// thousand).
#pragma once

#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <new>
#include <optional>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "tricell/box.hpp"
#include "tricell/export.hpp"
#include "tricell/pair_columns.hpp"
#include "tricell/types.hpp"

namespace tricell {

/// How atoms are binned and candidate pairs enumerated. Never changes the result, only the
/// speed and memory (docs/contract.md).
enum class SearchBackend {
    automatic, ///< chosen per call by the search policy from the cost model
    dense,     ///< a dense cell grid (at most max_cells cells), atoms sorted by cell
    linked,    ///< the same grid as head/next chains (no reordering of the atoms)
    hash,      ///< compact hashing: only non-empty cells stored, full resolution, O(N) memory
    octree,    ///< an adaptive octree in fractional space, leaves of at most leaf_size atoms
    direct,    ///< no grid: every atom pair through every image that can hold a pair (tiny cells)
};

/// Every backend, `automatic` first, in the order of the library's one table of backends.
TRICELL_API const std::vector<SearchBackend>& search_backends();
/// "auto", "dense", "linked", "hash", "octree" or "direct".
TRICELL_API const char* backend_name(SearchBackend backend);
/// The backend of a name backend_name() returns; InvalidArgument naming the text otherwise.
TRICELL_API SearchBackend parse_backend(const std::string& name);
/// The names of search_backends() for messages and help texts: "auto, dense, ... or direct".
TRICELL_API std::string backend_choices();

/// One entry of a per-species-pair cutoff table (symmetric: (a, b) also covers (b, a)).
struct SpeciesCutoff {
    std::int32_t a = 0;
    std::int32_t b = 0;
    double cutoff = 0; ///< pairs of these species count when d < cutoff; finite and > 0
};

/// Three quarters of the memory this process may use, in bytes: the physical memory or, when
/// smaller, its control group's memory limit (a container's or a batch job's). The default of
/// NeighborOptions::max_bytes; 0 (no limit) where the system says neither.
TRICELL_API std::size_t default_max_bytes();

struct TRICELL_API NeighborOptions {
    /// Pairs with |D| < cutoff (strict) are reported. Finite and > 0, unless radii or
    /// species_cutoffs decide instead (then it must stay 0).
    double cutoff = 0;
    /// Per-atom radii (one per position, finite, >= 0): a pair (i, j) counts when
    /// d < radii[i] + radii[j]. Empty: unused.
    std::vector<double> radii;
    /// Per-atom species (one per position), with species_cutoffs: a pair counts when d is below
    /// the table's cutoff for its two species; a species pair missing from the table never
    /// counts. Both empty: unused.
    std::vector<std::int32_t> species;
    std::vector<SpeciesCutoff> species_cutoffs;
    /// Report each pair once (canonical orientation) instead of both orientations.
    bool half = false;
    /// Pairs of a subset: when set, only the pairs of these points (indices into the positions,
    /// each < N and listed once) are reported, with every point as a neighbour. A full list
    /// holds every (i, j, S) of the full list with i in the query; a half list each pair with
    /// both ends in the query once (canonically oriented) and each pair with one end in it once,
    /// oriented from that end (i in the query). The search costs what the query's pairs cost,
    /// not what all points' pairs do. Unset: every point (a query of every point gives the
    /// same list).
    std::optional<std::vector<std::uint32_t>> query;
    /// Sort by i, then j, then S lexicographically, and fill NeighborList::offsets().
    bool sorted = false;
    /// Group the pairs by i (CSR) and fill NeighborList::offsets(): atom i's pairs are
    /// consecutive, in the order the search found them (the same for every thread count, not
    /// across backends). One counting pass, cheaper than `sorted`, which implies it.
    bool grouped = false;
    /// At most this many pairs per centre among those the cutoff allows, nearest first: the
    /// k nearest within r, as machine-learning potentials build their graphs; 0 means no limit.
    /// Each centre's pairs are ranked by (d, j, S), which makes the k kept the same on every
    /// backend and thread count, and are stored grouped by i in that order, with offsets (d and
    /// S are computed for the ranking whether stored or not). Full lists only (half and sorted
    /// are refused); max_pairs and max_bytes bound the full list it selects from.
    std::size_t max_neighbors = 0;
    /// With max_neighbors: every other pair with d <= d_k + tie_tolerance is kept too, d_k being
    /// the k-th distance of its centre (FAIRChem's degeneracy rule, whose k is max_neighbors - 1:
    /// its mask compares with the (k+1)-th distance). Finite and >= 0; 0 keeps exactly k.
    double tie_tolerance = 0;
    /// With max_neighbors: keep (j, i, -S) wherever (i, j, S) is kept, so that no edge is kept
    /// at one end and dropped at the other (a centre may then hold more than max_neighbors).
    bool symmetric = false;
    Quantities quantities;
    SearchBackend backend = SearchBackend::automatic;
    /// Target cells per cutoff along each axis (>= 1), grid backends; 0 lets the search choose
    /// (one cell per cutoff, or two where an atom has many neighbours). Never changes the result.
    double cells_per_cutoff = 0;
    /// Refuse (InvalidArgument) when the estimated or actual number of stored pairs exceeds this;
    /// 0 means no limit. The default, 5e8 pairs, is about 14 GB of i, j, S, d
    /// (26 GB with D).
    std::size_t max_pairs = 500'000'000;
    /// Refuse (InvalidArgument) when the stored list would need more than this many bytes at its
    /// peak: the pairs times the bytes per pair of the stored columns, plus the working space of
    /// grouping or sorting (docs/memory.md), checked against the estimated pairs before anything
    /// proportional to them is allocated, and again while the list is written (a list that
    /// outgrows its estimate is refused before a growing column would pass the limit). 0 means
    /// no limit. The default, default_max_bytes(), is three quarters of the memory this
    /// process may use.
    std::size_t max_bytes = default_max_bytes();
    /// Cap on the dense and linked grids' cells; 0 means 4 N + 64. Memory follows atoms, not
    /// volume. (The hash and octree backends need no cap: their memory is O(N) anyway.)
    std::size_t max_cells = 0;
    /// Hash backend: slots of the hash table; 0 means about 2 N. Any size >= 1 gives the same
    /// result (tests use tiny tables to force collisions).
    std::size_t hash_table_size = 0;
    /// Octree backend: most atoms in a leaf; 0 chooses from the cost model.
    std::size_t leaf_size = 0;
    /// Search a strongly skewed periodic cell in its reduced twin (same lattice, rounder cell),
    /// so a sheared box costs what the reduced one costs. Never changes the result.
    bool reduce_cell = true;
    /// Threads for NeighborSearch::build() and compute(); 0 means all hardware threads. The stored
    /// list is identical, pair for pair and in the same order, whatever the number of threads.
    /// (for_each_pair() always runs on the calling thread.) Threads asked for explicitly are
    /// always used; each build() and compute() (one for both in compute_neighbors()) starts its
    /// helper threads once, which a search of a few thousand atoms or more outweighs and a
    /// smaller one does not (benchmarks/README.md has the figures). Automatic threads (0) stay
    /// at one for small searches.
    int threads = 1;

    /// Throws InvalidArgument naming the offending field and value. Checks that do not need
    /// the positions (the sizes of radii and species are checked by NeighborSearch::build()).
    void validate() const;
    /// True when radii or species_cutoffs decide which pairs count.
    bool variable_cutoff() const { return !radii.empty() || !species_cutoffs.empty(); }
    /// True when the list comes grouped by i with per-atom offsets (grouped, sorted, or the
    /// nearest within the cutoff).
    bool with_offsets() const { return grouped || sorted || max_neighbors != 0; }
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
class ListAccess; // lib/search/list_access.hpp: how the library fills a list
} // namespace detail

/// Stored pairs, struct-of-arrays. Reuse one object across calls to keep its buffers.
class TRICELL_API NeighborList {
  public:
    std::size_t size() const { return columns_.size(); }
    bool empty() const { return columns_.empty(); }
    const PairArray<std::uint32_t>& i() const { return columns_.i; }
    const PairArray<std::uint32_t>& j() const { return columns_.j; }
    /// 3 ints per pair (Sa, Sb, Sc), empty unless Quantities::shifts.
    const PairArray<std::int32_t>& shifts() const { return columns_.shifts; }
    /// Empty unless Quantities::distances.
    const PairArray<double>& distances() const { return columns_.distances; }
    /// 3 doubles per pair (Dx, Dy, Dz), empty unless Quantities::vectors.
    const PairArray<double>& vectors() const { return columns_.vectors; }
    /// With grouped or sorted output: pairs of atom i are [offsets[i], offsets[i + 1]). Empty
    /// otherwise.
    const std::vector<std::size_t>& offsets() const { return columns_.offsets; }

    Shift shift(std::size_t k) const { return columns_.shift(k); }
    Eigen::Vector3d vector(std::size_t k) const { return columns_.vector(k); }
    /// Empties the list, keeping the capacity.
    void clear() { columns_.clear(); }

    /// The columns themselves.
    const PairColumns& columns() const { return columns_; }

  private:
    friend class detail::ListAccess;
    PairColumns columns_;
    // Kept here between calls so that their memory is reused instead of being faulted in again;
    // not part of the list: the per-thread batch columns of a threaded compute(), and the raw
    // scratch column a grouped compute() regroups each column through (empty between calls, its
    // capacity kept).
    std::vector<PairColumns> thread_columns_;
    PairArray<unsigned char> order_scratch_;
};

/// A block of pairs handed to for_each_pair()'s visitor: `count` pairs, struct-of-arrays.
struct PairBlock {
    std::size_t count = 0;
    const std::uint32_t* i = nullptr;
    const std::uint32_t* j = nullptr;
    const std::int32_t* shifts = nullptr; ///< 3 per pair, in the caller's frame
    const double* vectors = nullptr;      ///< 3 per pair
    const double* distances_sq = nullptr;
};

/// What a built search looks like (for tests, the command line's `bench` and benchmarks).
struct SearchInfo {
    SearchBackend backend = SearchBackend::dense; ///< the backend in use (never automatic)
    bool reduced_frame = false;                   ///< searched in the reduced twin of a skewed cell
    std::array<int, 3> cells{{1, 1, 1}}; ///< grid backends: cells per axis (full resolution)
    std::size_t stored_cells = 0;        ///< cells (or octree leaves) actually stored
    std::size_t work_units = 0;          ///< what threads split: cells, buckets or leaves
    double estimated_pairs = 0;          ///< from the density (what max_pairs is checked against)
    double search_radius = 0;            ///< the largest cutoff, plus a rounding margin
};

/// Work of each unit threads split (cells, buckets or leaves, in visiting order): its atoms, the
/// occupancy-moment estimate compute() balances (the cost model) and the distance tests its
/// candidates really cost. For load-balance benchmarks and tests.
struct UnitWork {
    std::vector<double> atoms;
    std::vector<double> estimated;
    std::vector<double> measured;
};

namespace detail {
struct SearchState; // lib/search/search_state.hpp
} // namespace detail

/// The search structure for one configuration. build() once, then compute() and/or
/// for_each_pair(); rebuild when positions or the box change. An object can be reused to keep
/// its buffers. Movable, not copyable.
class TRICELL_API NeighborSearch {
  public:
    NeighborSearch();
    ~NeighborSearch();
    NeighborSearch(NeighborSearch&&) noexcept;
    NeighborSearch& operator=(NeighborSearch&&) noexcept;
    NeighborSearch(const NeighborSearch&) = delete;
    NeighborSearch& operator=(const NeighborSearch&) = delete;

    /// Validates everything (options, positions, limits) before any work.
    void build(const Box& box, PointsView positions, const NeighborOptions& options);

    /// Stores the pairs into `out`. On error `out` is left empty, never half written.
    void compute(NeighborList& out) const;

    /// Calls visit(const Pair&) once per pair of the full or half list (as built), in
    /// unspecified order. Stores nothing.
    template <class Visit> void for_each_pair(Visit&& visit) const {
        using V = std::remove_reference_t<Visit>;
        auto on_block = [](void* context, const PairBlock& block) {
            V& v = *static_cast<V*>(context);
            for (std::size_t k = 0; k < block.count; ++k) {
                const std::int32_t* s = block.shifts + 3 * k;
                const double* d = block.vectors + 3 * k;
                v(Pair{block.i[k], block.j[k], Shift(s[0], s[1], s[2]),
                       Eigen::Vector3d(d[0], d[1], d[2]), block.distances_sq[k]});
            }
        };
        for_each_block(on_block, const_cast<void*>(static_cast<const void*>(&visit)));
    }

    /// The non-template core of for_each_pair(): calls on_block(context, block) for blocks of
    /// pairs (all quantities filled) until every pair has been seen.
    void for_each_block(void (*on_block)(void*, const PairBlock&), void* context) const;

    SearchInfo info() const;
    /// Per-unit work (see UnitWork); scans every candidate once without storing.
    UnitWork unit_work() const;
    /// Expected number of pairs from the density (what max_pairs is checked against first).
    double estimated_pairs() const;
    std::size_t atom_count() const;

  private:
    std::unique_ptr<detail::SearchState> state_;
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
