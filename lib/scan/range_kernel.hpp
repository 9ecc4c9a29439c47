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
// Cluster pruning, as in the cluster-pair search of Pall & Hess (2013): where the backend cuts
// its atoms into clusters (contiguous runs of the sorted order, each with the bounding box of its
// atoms; the dense grid sorts each cell's atoms along the stencil rows and cuts them into slabs
// of at most 8), each atom of the home cell is first tested against the boxes of the clusters of
// every range (the atoms in the lanes, one box at a time), and tests only the clusters from the
// first to the last whose box, moved by the range's shift, comes within the cutoff (plus a margin
// far wider than any rounding). The clusters left out hold no pair of that atom, so the exact
// test still decides every pair, the pairs come in the same order and only the candidates
// change: on diamond Si (rc 5, cells of one cutoff, about 7 atoms each: a cluster per cell) 6.5
// per stored pair of a half list become 3.4, whose lattice leaves the boxes well inside their
// cells; on random atoms (rc 6, about 24 atoms per cell) 7.3 become 3.1, where the boxes of whole
// cells left 6.5. A span runs along a row, so the slabs cut it at both ends to about the chord of
// the cutoff sphere.
//
// The arithmetic is distance_kernel.hpp's, term for term: D = (x_b - x_a) + T, d^2 = dx dx +
// dy dy + dz dz without fused multiply-adds, d = sqrt(d^2), a zero component of D stored as +0,
// so every version (AVX-512, AVX2, portable) and the general scan give the same bits.
//
// It serves a uniform cutoff without a query; the scanner takes variable cutoffs and subset
// searches through its general path.
#pragma once

#include <cmath>
#include <cstdint>
#include <vector>

namespace tricell::detail {

/// One contiguous range [b0, b1) of candidate atoms through one image shift s (a piece of a
/// stencil row).
struct CandidateRange {
    std::uint32_t b0, b1;
    std::int32_t s[3]; ///< the shift in the search frame
    double v[3];       ///< its vector H s
    /// The range holds the home atoms through a zero shift: a full list skips b == a, the half
    /// stencil takes b > a only.
    bool own;
    /// Half lists: whether the pair of an atom with its own image through s is turned around
    /// (its canonical orientation has -S; set by the scanner from the caller's frame).
    bool self_turn;
    /// With cluster boxes (RangeScanInput::boxes): the range is clusters [c0, c1].
    std::uint32_t c0 = 0, c1 = 0;
    /// With cluster boxes: a cluster whose box, moved by v, lies at least this far (squared)
    /// from an atom holds no pair of it (set by the scanner).
    double reach_sq = 0;
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
    bool half_stencil;          ///< the own range takes b > a only (a half or mirrored list)
    bool orient;                ///< each pair in its canonical orientation (a half list)
    /// Bounding boxes of the atoms of each cluster, 6 per cluster (lower x, y, z, upper x, y,
    /// z), or null (no pruning); cluster c holds atoms [cluster_start[c], cluster_start[c + 1]).
    const double* boxes = nullptr;
    const std::uint32_t* cluster_start = nullptr;
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
/// `tested` grows by the candidates tested: those the half stencil and the cluster boxes leave.
using RangeKernel = std::uint32_t (*)(const RangeScanInput& in, std::uint32_t a0, std::uint32_t a1,
                                      const CandidateRange* ranges, std::uint32_t count,
                                      const PairSlots& out, std::uint64_t& tested);

/// CandidateRange::reach_sq for a range through translation v, cutoff `cutoff`, coordinates of
/// magnitude at most `bound`: the cutoff plus a margin far wider than the rounding of the
/// kernel's D and of the distance to a box (a few ulps of the largest coordinate or translation),
/// squared.
inline double cell_reach_sq(double cutoff, double bound, const double v[3]) {
    const double reach =
        cutoff + 1e-12 * (cutoff + bound + std::abs(v[0]) + std::abs(v[1]) + std::abs(v[2]));
    return reach * reach;
}

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
