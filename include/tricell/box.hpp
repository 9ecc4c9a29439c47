// The periodic box: lattice vectors, coordinate conversion, wrapping and minimum image.
//
// The box matrix H holds the lattice vectors a, b, c as its COLUMNS, so a point with fractional
// coordinates s sits at r = H s. Files and Python tools list the vectors as rows; the named
// constructors from_rows() and from_columns() make the orientation explicit, and no function
// takes an unnamed 3x3 matrix. Each axis is periodic or open; along an open axis positions are
// never wrapped and the lattice vector only defines the frame, so none is needed there: a zero
// vector of an open axis (a molecule's all-zero box, a slab's zero c), or open vectors that do
// not span space with the periodic ones, are completed by unit vectors orthogonal to the others
// (docs/contract.md), and matrix() returns the completed vectors.
//
// Perpendicular widths w_a = 1 / |row a of H^-1| (distances between opposite faces), not edge
// lengths, decide how many cells of a given size fit along an axis. The minimum image is the
// true shortest lattice translate of a displacement: the box keeps a reduced basis of its
// periodic vectors, starts from Babai rounding in that basis and then searches all translates
// that could still be shorter (a bound from the Gram matrix), so skewed cells are exact.
#pragma once

#include <cmath>
#include <cstdint>
#include <limits>

#include <Eigen/Core>

#include "tricell/export.hpp"
#include "tricell/types.hpp"

namespace tricell {

/// Lattice parameters: edge lengths and the angles alpha = (b, c), beta = (a, c),
/// gamma = (a, b) in degrees.
struct LatticeParameters {
    double a = 0, b = 0, c = 0;
    double alpha = 90, beta = 90, gamma = 90;
};

/// A fractional position wrapped into [0, 1) on periodic axes, with the integer shift that was
/// removed: original = wrapped + image (exactly, up to the rounding of one subtraction).
struct WrappedFractional {
    Fractional wrapped;
    Shift image = Shift::Zero();
};

/// A minimum-image displacement: vector = d + H * shift is the shortest lattice translate of d.
struct MinimumImage {
    Cartesian vector;
    Shift shift = Shift::Zero();
    double distance = 0;
};

class TRICELL_API Box {
  public:
    /// Lattice vectors as the columns of h (r = H s). Along open axes a zero vector is completed
    /// (see above); periodic vectors must be nonzero and independent (GeometryError naming them).
    static Box from_columns(const Eigen::Matrix3d& h, Periodicity pbc = Periodicity::all());
    /// Lattice vectors as the rows of m (as POSCAR, extended XYZ, ASE and pymatgen list them).
    static Box from_rows(const Eigen::Matrix3d& m, Periodicity pbc = Periodicity::all());
    /// From lattice parameters: a along x, b in the xy plane, c completing a right-handed frame
    /// (the orientation of pymatgen, ASE and LAMMPS). Angles in degrees.
    static Box from_parameters(const LatticeParameters& p, Periodicity pbc = Periodicity::all());
    static Box from_parameters(double a, double b, double c, double alpha, double beta,
                               double gamma, Periodicity pbc = Periodicity::all());
    /// LAMMPS restricted triclinic box: a = (lx, 0, 0), b = (xy, ly, 0), c = (xz, yz, lz).
    static Box from_lammps(double lx, double ly, double lz, double xy, double xz, double yz,
                           Periodicity pbc = Periodicity::all());

    /// H, with the lattice vectors as columns.
    const Eigen::Matrix3d& matrix() const { return h_; }
    /// H^-1; its rows are the reciprocal vectors (without 2 pi).
    const Eigen::Matrix3d& inverse() const { return h_inv_; }
    /// Lattice vector of an axis (0 = a, 1 = b, 2 = c).
    Cartesian vector(int axis) const { return Cartesian(h_.col(axis)); }
    const Periodicity& periodicity() const { return pbc_; }
    bool periodic(int axis) const { return pbc_[axis]; }

    /// det H (negative for a left-handed box, which is valid).
    double determinant() const { return det_; }
    /// |det H|.
    double volume() const;
    LatticeParameters parameters() const;
    /// Distances between opposite faces, 1 / |row of H^-1| per axis.
    const Eigen::Vector3d& perpendicular_widths() const { return widths_; }

    Fractional to_fractional(const Cartesian& r) const { return Fractional(h_inv_ * r); }
    Cartesian to_cartesian(const Fractional& s) const { return Cartesian(h_ * s); }
    /// Bulk conversions over N x 3 row-major arrays; out must have the same count as in (it may
    /// alias in).
    void to_fractional(PointsView cartesian, MutablePointsView fractional) const;
    void to_cartesian(PointsView fractional, MutablePointsView cartesian) const;

    /// Fractional coordinates beyond this many box lengths cannot be wrapped into an int shift.
    static constexpr double max_fractional = 1e9;

    /// Wraps periodic components into [0, 1) and reports the removed integer shift. Open axes
    /// are returned unchanged with shift 0. Throws InvalidArgument for a non-finite coordinate
    /// or one more than max_fractional box lengths away (its shift would not fit an int).
    /// (Inline: the search wraps every atom of every call.)
    WrappedFractional wrap(const Fractional& s) const;
    /// Cartesian convenience: the wrapped Cartesian point and the shift with
    /// r = wrapped + H * image.
    Cartesian wrap(const Cartesian& r, Shift* image = nullptr) const;

    /// Shortest periodic translate of the displacement d (translations along periodic axes
    /// only). Ties are broken deterministically.
    MinimumImage minimum_image(const Cartesian& d) const;
    /// Length of the minimum-image displacement from r_i to r_j.
    double minimum_image_distance(const Cartesian& r_i, const Cartesian& r_j) const;

  private:
    Box(const Eigen::Matrix3d& h, Periodicity pbc);
    /// The InvalidArgument of wrap() for component `axis` of s.
    [[noreturn]] static void wrap_failure(const Fractional& s, int axis);

    Eigen::Matrix3d h_;
    Eigen::Matrix3d h_inv_;
    Periodicity pbc_;
    double det_ = 0;
    Eigen::Vector3d widths_;
    // Reduced basis of the periodic vectors: reduced_.col(k) = h_ * reduced_to_h_.col(k) for
    // k < n_periodic_. Used by minimum_image().
    int n_periodic_ = 0;
    Eigen::Matrix3d reduced_ = Eigen::Matrix3d::Zero();
    Eigen::Matrix3i reduced_to_h_ = Eigen::Matrix3i::Zero();
    Eigen::Matrix3d reduced_gram_inv_ = Eigen::Matrix3d::Zero();
};

inline WrappedFractional Box::wrap(const Fractional& s) const {
    // Built in locals and stored once: stored component by component, the result would be read
    // back as a vector before the stores retire (a store-forwarding stall per atom).
    double wrapped[3] = {s[0], s[1], s[2]};
    int images[3] = {0, 0, 0};
    for (int axis = 0; axis < 3; ++axis) {
        // Finite, and within max_fractional on a periodic axis (a NaN fails the comparison).
        const double limit = pbc_[axis] ? max_fractional : std::numeric_limits<double>::max();
        if (!(std::abs(s[axis]) <= limit)) {
            wrap_failure(s, axis);
        }
        if (!pbc_[axis]) {
            continue;
        }
        // floor(s) without a library call: |s| <= 1e9 converts to an integer exactly.
        double image = double(std::int64_t(s[axis]));
        image -= image > s[axis] ? 1.0 : 0.0;
        double w = s[axis] - image;
        // s - floor(s) rounds to 1.0 for tiny negative s (e.g. -1e-17): that point belongs to
        // the next image at 0.0, never at 1.0.
        if (w >= 1.0) {
            w = 0.0;
            image += 1.0;
        }
        wrapped[axis] = w + 0.0; // + 0.0 turns -0.0 into +0.0
        images[axis] = static_cast<int>(image);
    }
    WrappedFractional out;
    out.wrapped = Fractional(wrapped[0], wrapped[1], wrapped[2]);
    out.image = Shift(images[0], images[1], images[2]);
    return out;
}

} // namespace tricell
