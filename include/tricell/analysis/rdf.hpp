// Radial distribution functions g(r) over every periodic image, accumulated frame by frame.
//
// For each frame the pairs with d < rmax come from one NeighborSearch (a half list visited with
// for_each_pair, nothing stored), over every periodic image, so rmax may exceed the cell: an
// atom's own images count as neighbours like any other atom. Each pair (i, j, S) of the half list
// stands for the two ordered pairs (i, j) and (j, i). Bin k holds r_k <= d < r_{k+1} with
// r_k = k rmax / bins; the shell volume is the exact V_k = 4/3 pi (r_{k+1}^3 - r_k^3).
//
// Normalisation per frame (V the cell volume, N atoms, N_A atoms of species A):
//   total    g(r_k)    = C_k / (N * (N / V) * V_k),          C_k    = ordered pairs in bin k;
//   partial  g_AB(r_k) = C_AB_k / (N_A * (N_B / V) * V_k),  C_AB_k = ordered pairs (i in A, j in
//                        B) in bin k, so g_AB = g_BA and the total is sum_AB x_A x_B g_AB with
//                        x_A = N_A / N.
// This is ASE's get_rdf and freud's exact mode for the total (density N / V, not (N - 1) / V).
// ASE's partial (elements=(A, B)) differs: it normalises C_AB by N_A * (N / V), the density of
// all atoms, instead of N_A * (N_B / V); its value is ours times N_B / N, and tends to N_B / N,
// not 1, at large r. The running coordination number n(r) at a bin's upper edge r_{k+1} is the
// mean number of neighbours (of species B, for a partial) within r_{k+1} of an atom (of species
// A): sum over bins <= k of C_k / N (C_AB_k / N_A).
//
// Frames may differ in cell and in atom count; g and n are the plain averages of the per-frame
// values. A partial averages over the frames in which both its species occur (a frame without
// atoms of A says nothing about g_AB). Every axis must be periodic: g(r) is normalised by the
// cell volume, which an open axis does not define, so a frame with an open axis is refused.
// Memory is O(bins * species pairs), whatever the number of frames.
#pragma once

#include <cstddef>
#include <cstdint>
#include <map>
#include <utility>
#include <vector>

#include "tricell/box.hpp"
#include "tricell/export.hpp"
#include "tricell/neighbor_list.hpp"
#include "tricell/types.hpp"

namespace tricell {

struct TRICELL_API RdfOptions {
    /// Largest distance (exclusive). Finite and > 0; may exceed the cell (every image counts).
    double rmax = 0;
    /// Number of bins of width rmax / bins over [0, rmax). At least 1, at most max_bins.
    std::size_t bins = 0;
    /// Threads for the search of each frame (NeighborOptions::threads; 0 means all). On one
    /// thread pairs are streamed and nothing is stored; with more, each frame's half list is
    /// stored first (i, j, S, d: 24 bytes per pair). The result is the same either way.
    int threads = 1;
    /// Search backend (never changes the result).
    SearchBackend backend = SearchBackend::automatic;

    /// The largest accepted `bins` (10^8 bins: 2.4 GB of curves per species pair).
    static constexpr std::size_t max_bins = 100'000'000;

    /// Throws InvalidArgument naming the field and its value.
    void validate() const;
};

/// One curve, one value per bin.
struct RdfCurve {
    std::vector<double> r; ///< bin centres, (r_k + r_{k+1}) / 2
    std::vector<double> g; ///< g(r) per bin, averaged over frames
    std::vector<double> n; ///< running coordination number at each bin's upper edge r_{k+1}
};

/// Accumulates g(r) frame by frame (see the top of this header for the definitions).
class TRICELL_API Rdf {
  public:
    /// Validates the options (InvalidArgument).
    explicit Rdf(const RdfOptions& options);

    /// Adds one frame. `species`: one non-negative integer per atom (say, the atomic number),
    /// or empty for a single species. Throws InvalidArgument (a species vector of the wrong
    /// size, a negative species, no atoms, an open axis, a non-finite position) or
    /// GeometryError before anything is accumulated: a refused frame leaves the Rdf unchanged.
    void add_frame(const Box& box, PointsView positions,
                   const std::vector<std::int32_t>& species = {});

    /// Frames added so far.
    std::size_t frames() const { return frames_; }
    /// The bins + 1 bin edges 0, rmax / bins, ..., rmax.
    const std::vector<double>& edges() const { return edges_; }
    const RdfOptions& options() const { return options_; }
    /// Species seen so far, ascending (empty species vectors count as species 0).
    std::vector<std::int32_t> species() const;

    /// The total g(r) and n(r) averaged over the frames. InvalidArgument before any frame.
    RdfCurve total() const;
    /// g_AB(r) (= g_BA) and the mean number of B neighbours of an A atom within r, averaged
    /// over the frames holding both A and B. InvalidArgument naming the species when A or B
    /// never occurred.
    RdfCurve partial(std::int32_t a, std::int32_t b) const;

  private:
    // Sums over frames of per-frame g and n, and how many frames contributed.
    struct Sums {
        std::vector<double> g;
        std::vector<double> n;
        std::size_t frames = 0;
    };
    RdfCurve curve(const Sums& sums) const;

    RdfOptions options_;
    std::vector<double> edges_;
    std::size_t frames_ = 0;
    Sums total_;
    std::map<std::pair<std::int32_t, std::int32_t>, Sums> partials_; // (A, B), both orders
};

} // namespace tricell
