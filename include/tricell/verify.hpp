// Verification of a neighbour list, from tricell or from any other code, against an independent
// search (docs/contract.md, "Verify").
//
// verify() recomputes every listed pair from the caller's own positions (D = x_j - x_i + H S)
// and compares the list, as a multiset of (i, j, S), with what a reference search finds for the
// same box, positions and options. The reference is a brute-force loop over every atom pair and
// every image the perpendicular widths allow while N^2 times the images per pair stays within
// brute_force_budget distance tests; beyond that it is tricell's search with a different backend
// than the automatic choice would take (the dense grid, or the compact hash when the automatic
// choice is the dense grid), so one backend's mistake cannot hide itself. The list's own rules
// are checked entry by entry: indices in range, no (i, i, 0), S = 0 along open axes, and the
// listed d and D (when given) equal to the recomputed ones. A full list must hold both
// orientations of every pair; a half list may hold either orientation of each pair, (i, j, S)
// or (j, i, -S), but exactly once. With options.query the list expected is the query's: the
// pairs with i in the query (full), or with either end in it (half). A pair whose distance is
// within rounding_allowance() of its cutoff may be present or absent: different but correct
// arithmetic decides it either way.
//
// The report counts every kind of difference and describes the first one in words (entries in
// list order first, then pairs in (i, j, S) order), e.g. "pair (3, 17, [0 1 0]) at distance 2.31
// < cutoff 2.5 is missing". Bad arguments (a null array, a non-finite position, invalid options,
// a list without shifts in a periodic box) throw InvalidArgument instead.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

#include <Eigen/Core>

#include "tricell/box.hpp"
#include "tricell/export.hpp"
#include "tricell/neighbor_list.hpp"
#include "tricell/types.hpp"

namespace tricell {

/// A list as plain arrays from any code (NumPy arrays of ASE, another library's buffers): `size`
/// entries of i and j (any integers; out-of-range ones are reported, not refused), 3 shifts per
/// entry (may be null when no axis is periodic: all zero), and optionally d (one per entry) and
/// D (3 per entry), checked against the positions when given.
struct PairArrays {
    std::size_t size = 0;
    const std::int64_t* i = nullptr;
    const std::int64_t* j = nullptr;
    const std::int64_t* shifts = nullptr;
    const double* distances = nullptr;
    const double* vectors = nullptr;
};

/// The verdict of verify(): counts of every kind of difference and the first one in words.
struct VerifyReport {
    bool ok = false;
    std::size_t entries = 0;      ///< entries of the list examined
    std::size_t expected = 0;     ///< pairs the reference found
    std::size_t matched = 0;      ///< entries that matched a reference pair
    std::size_t near_cutoff = 0;  ///< pairs within rounding of their cutoff, accepted either way
    std::size_t missing = 0;      ///< reference pairs the list lacks
    std::size_t extra = 0;        ///< listed pairs that are not pairs
    std::size_t duplicates = 0;   ///< entries repeating a pair (in a half list: either way)
    std::size_t rule_breaks = 0;  ///< out-of-range index, (i, i, 0), shift along an open axis
    std::size_t wrong_values = 0; ///< a listed d or D that differs from the recomputed one
    std::string reference;        ///< "brute force" or "the dense backend" / "the hash backend"
    std::string message;          ///< "ok: ..." or the first difference
};

/// Distance tests (N^2 times images per pair) up to which the reference is brute force.
constexpr double brute_force_budget = 1 << 26;

/// The rounding allowance of the pair (x_i, x_j, S) at `cutoff`: distances computed in two
/// correct ways (from wrapped positions, from the caller's) differ by less. It grows with the
/// condition number of the box and with the size of the coordinates, of the shift and of the
/// translations that wrap the two atoms into the box.
TRICELL_API double rounding_allowance(const Box& box, const Eigen::Vector3d& xi,
                                      const Eigen::Vector3d& xj, const Eigen::Vector3i& shift,
                                      double cutoff);

/// Checks plain arrays against the reference for (box, positions, options); options.cutoff, or
/// radii or species with species_cutoffs, options.half and options.query say which list is expected
/// (options.threads, max_pairs and max_bytes bound the reference search; the other fields do not
/// matter).
TRICELL_API VerifyReport verify(const Box& box, PointsView positions,
                                const NeighborOptions& options, const PairArrays& list);

/// Checks a stored list (it must hold shifts when an axis is periodic; d and D are checked when
/// stored).
TRICELL_API VerifyReport verify(const Box& box, PointsView positions,
                                const NeighborOptions& options, const NeighborList& list);

} // namespace tricell
