// The displacement tracker: how far every atom has moved since a reference configuration (a
// "build"), in the build's frame, and the rule that says when a list built at a radius of
// cutoff + skin may miss a pair within the cutoff. VerletList uses it for its rebuilds; the
// Python ASE drop-ins (python/tricell/_ase_classes.py) use it, through the binding, for lists
// with per-atom cutoffs.
//
// Why the rule is safe. Let s0 be the fractional build positions in the build box H0, and s the
// current ones in the current box H. For each atom the tracker picks an integer jump m_i and
// measures its displacement in the build frame, delta_i = H0 (s_i + m_i - s0_i). A current pair
// (i, j, S') maps to the pair (i, j, S' - m_j + m_i) of the build, whose vector then was
//     D0 = H0 H^-1 D - delta_j + delta_i,   so   |D0| <= ||H0 H^-1|| |D| + |delta_i| + |delta_j|,
// with ||.|| the spectral norm. If every |delta| <= (skin - eps r_c) / 2, where
// eps = max(0, ||H0 H^-1|| - 1) <= ||(H0 - H) H^-1|| (the box's strain since the build), then
// |D| < r_c implies |D0| < r_c + skin: a list built at r_c + skin holds the pair. With a cutoff
// per pair (r_c of the pair, the same skin for every pair) the same holds when r_c in eps r_c is
// the largest pair cutoff. That is the rebuild rule: needs_rebuild() is true when some atom has
// moved more than (skin - eps r_c) / 2 since the build (skin / 2 while the box is unchanged),
// or the atom count or periodicity changed. The bound holds for ANY choice of the integers m_i,
// so wrapping never matters for correctness; the tracker takes the m_i that make delta_i the
// minimum image in the build box (fractional rounding, then Box::minimum_image when rounding is
// not short enough), so a caller who wraps positions into the box between calls, or moves an
// atom by a whole lattice vector, does not trigger a rebuild, and a real move is never hidden:
// delta_i is the shortest way the atom could have got there. A build pair (i, j, S) of the
// positions as recorded is the current pair (i, j, S + k_j - k_i), k the jumps since the record
// (jumps_since_record()).
//
// Why displacements are taken in fractional coordinates. When the box deforms (NPT, shear) and
// the caller moves the atoms with it (s fixed, the usual affine remap), delta is zero: the
// whole box change enters through eps alone, a bound on how much any pair vector, through any
// image, can shrink (|D0| <= (1 + eps) |D|, whatever the pair's shift or how far the atoms are
// from the origin). Cartesian displacements would instead grow with the distance from the
// origin (|dH s| <= ||dH|| |s|) and trigger rebuilds for a mere change of box. A caller who
// changes the box but keeps Cartesian positions still gets exact lists; the non-affine part
// then counts as displacement.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <vector>

#include "tricell/box.hpp"
#include "tricell/export.hpp"
#include "tricell/types.hpp"

namespace tricell {

/// Displacements since a recorded configuration and the rebuild rule of a list built then at
/// cutoff + skin (see the file comment). `skin` is the margin of the list beyond the cutoff and
/// `cutoff` the largest cutoff of a pair (r_c in eps r_c); both finite and >= 0.
class TRICELL_API DisplacementTracker {
  public:
    /// Makes (box, positions) the build. With non-null `jumps` (3 per atom) and `unwrapped`
    /// (3 per atom) it writes this configuration's jumps m = -image and x + H m (the positions
    /// wrapped into the box). Throws InvalidArgument for a non-finite position.
    void record(const Box& box, PointsView positions, std::int32_t* jumps = nullptr,
                double* unwrapped = nullptr);
    /// Forgets the build.
    void reset();

    bool recorded() const { return build_box_.has_value(); }
    /// Atoms of the build (0 when nothing is recorded).
    std::size_t atom_count() const { return atom_count_; }
    /// A build exists with the same atom count and periodicity.
    bool compatible(const Box& box, PointsView positions) const;

    /// (skin - eps cutoff) / 2 with eps = max(0, ||H0 H^-1|| - 1): how far each atom may have
    /// moved since the build for the list to stay complete in this box. Negative (a rebuild is
    /// needed whatever the positions) when nothing is recorded or the periodicity changed.
    double budget(const Box& box, double skin, double cutoff) const;
    /// True when a list built at cutoff + skin may miss a pair: nothing recorded, a different
    /// atom count or periodicity, or some atom displaced (minimum image, build frame) by more
    /// than budget(box, skin, cutoff). Throws InvalidArgument for a non-finite position.
    bool needs_rebuild(const Box& box, PointsView positions, double skin, double cutoff) const;
    /// Largest displacement of an atom since the build (minimum image in the build box of the
    /// fractional displacement). Infinity when nothing is recorded or the atom count or
    /// periodicity differs.
    double max_displacement(const Box& box, PointsView positions) const;
    /// When !needs_rebuild(box, positions, skin, cutoff), writes the jumps k (3 per atom) since
    /// the record, relative to the positions as recorded, and returns true: a recorded pair
    /// (i, j, S) is now (i, j, S + k_j - k_i). Otherwise returns false.
    bool jumps_since_record(const Box& box, PointsView positions, double skin, double cutoff,
                            std::int32_t* out) const;

    /// Tracks every atom against the build (which must be compatible): checks finiteness,
    /// picks its jump m_i and measures delta_i. Returns the largest |delta_i|, stopping early
    /// above `stop_above`. The jump is the rounded fractional displacement unless that leaves
    /// |delta_i| above `stop_above` (or always, when `exact`): then the exact minimum image.
    /// With non-null `jumps` (3 per atom) and `unwrapped` (x + H m, 3 per atom) it records them.
    double track(const Box& box, PointsView positions, double stop_above, bool exact,
                 std::int32_t* jumps, double* unwrapped) const;

  private:
    std::optional<Box> build_box_;
    std::size_t atom_count_ = 0;
    std::vector<double> reference_;         // wrapped fractional build positions, 3 per atom
    std::vector<std::int32_t> build_jumps_; // m = -image of the recorded positions, 3 per atom
};

} // namespace tricell
