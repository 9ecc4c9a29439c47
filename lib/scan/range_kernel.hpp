// The fused kernel of the common search: the atoms of a home cell against a list of candidate
// ranges, each hit written straight into the pair columns. A grid backend hands the scan, per
// home cell, the contiguous atom ranges of all its stencil rows (each through one image shift);
// the kernel tests each range against every atom of the cell in vector blocks and stores the
// hits of a block at once, compressed in registers where the processor has AVX-512 (i, j, S, d
// and D as asked, a half list's pairs turned into their canonical orientation by lane masks). No
// per-range call, no hit buffer and no second pass over the hits: that is what makes cells of half
// the cutoff pay, whose rows hold a few atoms each but leave fewer candidates
// (grid_cells_per_cutoff in policy/cost_model.hpp).
//
// The arithmetic is distance_kernel.hpp's, term for term: D = (x_b - x_a) + T, d^2 = dx dx +
// dy dy + dz dz without fused multiply-adds, d = sqrt(d^2), a zero component of D stored as +0,
// so every version (AVX-512, AVX2, portable) and the general scan give the same bits.
//
// It serves a uniform cutoff without a query; the scanner takes variable cutoffs and subset
// searches through its general path.
#pragma once

#include <cstdint>
#include <vector>

namespace tricell::detail {

/// One contiguous range [b0, b1) of candidate atoms through one image shift s (a piece of a
/// stencil row).
struct CandidateRange {
    std::uint32_t b0, b1;
    std::int32_t s[3]; ///< the shift in the search frame
    double v[3];       ///< its vector H s
    /// The range holds the home atoms through a zero shift: a full list skips b == a, a half
    /// list takes b > a only.
    bool own;
    /// Half lists: whether the pair of an atom with its own image through s is turned around
    /// (its canonical orientation has -S; set by the scanner from the caller's frame).
    bool self_turn;
};

/// What the kernel reads: the atom table's columns and the list's rules.
struct RangeScanInput {
    const double* x;
    const double* y;
    const double* z;
    const std::uint32_t* index; ///< the caller's index of each atom
    const std::int32_t* image;  ///< 3 per atom
    bool zero_images;           ///< every image is 0
    double cutoff_sq;           ///< d^2 < cutoff_sq counts
    bool half;                  ///< canonical orientation
};

/// Where the pairs go: the next free place of each stored column (null: not stored), with room
/// for the ranges' candidates plus kernel_slack (the vector versions store whole registers).
/// `squares`: distances holds d^2, not d.
struct PairSlots {
    std::uint32_t* i;
    std::uint32_t* j;
    std::int32_t* shifts; ///< 3 per pair
    double* distances;
    double* vectors; ///< 3 per pair
    bool squares;
};

/// Tests atoms [a0, a1) against every range of ranges[0, count) and writes their pairs atom by
/// atom, each atom's range by range in the ranges' order (so an atom's pairs of one call are one
/// run, which grouping by i moves whole); returns how many. The slots have room for (a1 - a0)
/// times the ranges' candidates, plus kernel_slack.
using RangeKernel = std::uint32_t (*)(const RangeScanInput& in, std::uint32_t a0, std::uint32_t a1,
                                      const CandidateRange* ranges, std::uint32_t count,
                                      const PairSlots& out);

/// One instruction set's range kernel.
struct RangeKernelVersion {
    const char* name; ///< "avx512", "avx2" or "generic"
    RangeKernel scan;
};

/// Every version this processor can run, fastest first (the first is the one the search uses,
/// the last the portable one).
std::vector<RangeKernelVersion> range_kernels();

/// The fastest version on this processor.
RangeKernel range_kernel();

} // namespace tricell::detail
