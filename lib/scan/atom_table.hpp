// The atoms as the scan reads them: the wrapped Cartesian positions struct-of-arrays in a
// backend's order (contiguous ranges stream through the vectorised kernel), the integer image
// each came from (x = wrapped + H image), the caller's index of each and, for a subset search,
// which are query atoms. A pair (a, b) found through the cell shift s has, for the caller,
// S = s + image_a - image_b.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "frame/wrap.hpp"
#include "tricell/pair_columns.hpp"
#include "tricell/types.hpp"

namespace tricell::detail {

struct AtomTable {
    // Left uninitialised when grown (every entry is written by the build, on its threads).
    PairArray<double> x, y, z;
    PairArray<std::int32_t> image;    ///< 3 per atom
    std::vector<std::uint32_t> index; ///< the caller's index of each atom
    /// A subset search (NeighborOptions::query): 1 per query atom; empty for the ordinary search.
    std::vector<std::uint8_t> query;
    /// Every image is 0 (every atom was given inside the search frame's cell, the usual case):
    /// then S = s for every pair a scan through s finds.
    bool zero_images = false;
    std::size_t size() const { return index.size(); }
    bool subset() const { return !query.empty(); }
};

/// Fills `atoms` in the backend's `order` (order[k]: the caller's index of the k-th atom) with
/// the positions wrapped into the frame of box matrix `h`, x - H image (exactly x for atoms
/// already in the box), their images and, when `query` (per caller index) is not empty, the
/// query flags, on `threads` threads. The table takes `order` as its index, and `order` gets
/// the table's old index buffer (its content unspecified), so that no buffer is allocated again.
void fill_atom_table(const Eigen::Matrix3d& h, PointsView positions,
                     const WrappedPositions& wrapped, std::vector<std::uint32_t>& order,
                     const std::vector<std::uint8_t>& query, std::size_t threads, AtomTable& atoms);

} // namespace tricell::detail
