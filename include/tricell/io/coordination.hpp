// Coordination numbers: how many neighbours each atom has within a cutoff that may depend on the
// pair of elements.
//
// A pair (i, j, S) of the full neighbour list counts as a bond when the elements of i and j have
// a cutoff and |D| < that cutoff (strict, as in the neighbour list). Per-pair cutoffs
// (CoordinationOptions::bonds, unordered: Si-O is O-Si) take precedence over the default cutoff;
// without a default cutoff, only the listed pairs count. Bonds to periodic images count, also to
// an atom's own image. Partial occupancies are ignored: every listed site is an atom. The
// search runs once, with the largest cutoff.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "tricell/io/export.hpp"
#include "tricell/io/structure.hpp"
#include "tricell/neighbor_list.hpp"

namespace tricell::io {

/// A cutoff for one unordered pair of elements.
struct BondCutoff {
    std::string a;
    std::string b;
    double cutoff = 0;
};

struct TRICELL_IO_API CoordinationOptions {
    /// Cutoff for every pair not listed in `bonds`; 0 means such pairs never count.
    double cutoff = 0;
    /// Per-element-pair cutoffs. Element symbols in any case ("si" is "Si").
    std::vector<BondCutoff> bonds;
    /// Refuse (InvalidArgument, before the search allocates) when the neighbour list of the
    /// largest cutoff would hold more pairs than this; 0 means no limit (NeighborOptions).
    std::size_t max_pairs = NeighborOptions().max_pairs;
    /// Refuse the same way a list whose memory would pass this many bytes (NeighborOptions).
    std::size_t max_bytes = NeighborOptions().max_bytes;

    /// Throws InvalidArgument: a cutoff not finite or < 0 (0 only for the default), an unknown
    /// element, a pair listed twice, or no cutoff at all.
    void validate() const;
};

struct Coordination {
    /// Number of counted bonds.
    std::size_t count = 0;
    /// Shortest counted bond, NaN when there is none.
    double nearest = 0;
    /// Mean length of the counted bonds, NaN when there is none.
    double mean = 0;
};

/// One entry per atom, in the structure's order.
TRICELL_IO_API std::vector<Coordination> coordination(const Structure& structure,
                                                      const CoordinationOptions& options);

} // namespace tricell::io
