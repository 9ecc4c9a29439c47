// Small value types shared by the public headers: coordinate kinds, image shifts, periodicity,
// and non-owning views over the caller's N x 3 arrays.
//
// Cartesian and Fractional are distinct types (as gemmi's Position and Fractional are) so that
// a Cartesian point cannot be passed where a fractional one is expected. Both are Eigen
// 3-vectors underneath and support Eigen arithmetic; converting one kind into the other goes
// through tricell::Box.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include <Eigen/Core>

namespace tricell {

/// A Cartesian position or displacement (length units of the box).
struct Cartesian : Eigen::Vector3d {
    Cartesian() : Eigen::Vector3d(Eigen::Vector3d::Zero()) {}
    Cartesian(double x, double y, double z) : Eigen::Vector3d(x, y, z) {}
    template <class Derived>
    explicit Cartesian(const Eigen::MatrixBase<Derived>& v) : Eigen::Vector3d(v) {}
};

/// Fractional coordinates s with r = H s.
struct Fractional : Eigen::Vector3d {
    Fractional() : Eigen::Vector3d(Eigen::Vector3d::Zero()) {}
    Fractional(double a, double b, double c) : Eigen::Vector3d(a, b, c) {}
    template <class Derived>
    explicit Fractional(const Eigen::MatrixBase<Derived>& v) : Eigen::Vector3d(v) {}
};

/// An integer lattice translation (image shift) S in units of the lattice vectors a, b, c.
using Shift = Eigen::Vector3i;

/// Which of the axes a, b, c are periodic.
struct Periodicity {
    std::array<bool, 3> axes{{true, true, true}};

    static Periodicity all() { return {{{true, true, true}}}; }
    static Periodicity none() { return {{{false, false, false}}}; }
    bool operator[](int axis) const { return axes[static_cast<std::size_t>(axis)]; }
    bool any() const { return axes[0] || axes[1] || axes[2]; }
    int count() const { return int(axes[0]) + int(axes[1]) + int(axes[2]); }
    friend bool operator==(const Periodicity& l, const Periodicity& r) { return l.axes == r.axes; }
    friend bool operator!=(const Periodicity& l, const Periodicity& r) { return !(l == r); }
};

/// Read-only view over N points stored row-major as N x 3 doubles (x0 y0 z0 x1 y1 z1 ...).
/// Nothing is copied; the caller keeps the memory alive while the view is used.
struct PointsView {
    const double* data = nullptr;
    std::size_t count = 0;

    PointsView() = default;
    PointsView(const double* xyz, std::size_t n) : data(xyz), count(n) {}
    /// Views a vector of Eigen 3-vectors (or Cartesian/Fractional), which are contiguous.
    template <class Vec3>
    PointsView(const std::vector<Vec3>& points) // NOLINT(google-explicit-constructor)
        : data(points.empty() ? nullptr : points.front().data()), count(points.size()) {
        static_assert(sizeof(Vec3) == 3 * sizeof(double), "expects packed 3-vectors");
    }
    std::size_t size() const { return count; }
    Eigen::Map<const Eigen::Vector3d> operator[](std::size_t i) const {
        return Eigen::Map<const Eigen::Vector3d>(data + 3 * i);
    }
};

/// Writable view over N points stored row-major as N x 3 doubles.
struct MutablePointsView {
    double* data = nullptr;
    std::size_t count = 0;

    MutablePointsView() = default;
    MutablePointsView(double* xyz, std::size_t n) : data(xyz), count(n) {}
    template <class Vec3>
    MutablePointsView(std::vector<Vec3>& points) // NOLINT(google-explicit-constructor)
        : data(points.empty() ? nullptr : points.front().data()), count(points.size()) {
        static_assert(sizeof(Vec3) == 3 * sizeof(double), "expects packed 3-vectors");
    }
    std::size_t size() const { return count; }
    Eigen::Map<Eigen::Vector3d> operator[](std::size_t i) const {
        return Eigen::Map<Eigen::Vector3d>(data + 3 * i);
    }
};

} // namespace tricell
