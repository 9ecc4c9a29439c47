#include "tricell/box.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include <Eigen/LU>

#include "detail/lattice_reduction.hpp"
#include "detail/open_axes.hpp"
#include "detail/pi.hpp"
#include "tricell/error.hpp"

namespace tricell {

namespace {

constexpr const char* axis_name[3] = {"a", "b", "c"};
// A box whose |det H| is below this fraction of |a||b||c| is treated as flat.
using detail::flatness_tolerance;

double degrees(double radians) {
    return radians * 180.0 / detail::pi;
}
double radians(double degrees) {
    return degrees * detail::pi / 180.0;
}

double angle_between(const Eigen::Vector3d& u, const Eigen::Vector3d& v) {
    const double c = u.dot(v) / (u.norm() * v.norm());
    return degrees(std::acos(std::clamp(c, -1.0, 1.0)));
}

// Refuses periodic vectors that are linearly dependent (nearly), naming them.
void check_periodic_vectors(const Eigen::Matrix3d& h, const Periodicity& pbc) {
    if (pbc.count() < 2) {
        return;
    }
    const double flatness = detail::unit_flatness(h, pbc.axes);
    if (flatness > flatness_tolerance) {
        return;
    }
    if (pbc.count() == 3) {
        detail::fail<GeometryError>(
            "box is singular or nearly flat: the periodic lattice vectors a, b and c are "
            "coplanar or nearly so, |det H| / (|a||b||c|) = ",
            flatness, " (|det H| = ", std::abs(h.determinant()), "; at most ", flatness_tolerance,
            " is flat)");
    }
    const int first = pbc[0] ? 0 : 1, second = pbc[2] ? 2 : 1;
    detail::fail<GeometryError>(
        "box is singular or nearly flat: the periodic lattice vectors ", axis_name[first], " and ",
        axis_name[second], " are parallel or nearly so, |", axis_name[first], " x ",
        axis_name[second], "| / (|", axis_name[first], "||", axis_name[second], "|) = ", flatness,
        " (at most ", flatness_tolerance, " is flat)");
}

} // namespace

Box::Box(const Eigen::Matrix3d& h, Periodicity pbc) : h_(h), pbc_(pbc) {
    for (int col = 0; col < 3; ++col) {
        for (int row = 0; row < 3; ++row) {
            if (!std::isfinite(h(row, col))) {
                detail::fail<InvalidArgument>("lattice vector ", axis_name[col], " component ", row,
                                              " is not finite (got ", h(row, col), ")");
            }
        }
    }
    for (int axis = 0; axis < 3; ++axis) {
        if (pbc_[axis] && h_.col(axis).squaredNorm() == 0.0) {
            detail::fail<GeometryError>("lattice vector ", axis_name[axis], " is zero but axis ",
                                        axis_name[axis], " is periodic");
        }
    }
    check_periodic_vectors(h_, pbc_);
    h_ = detail::complete_open_axes(h_, pbc_);
    det_ = h_.determinant();
    // The squared lengths and the volume must be doubles: past them the inverse is zero or NaN.
    const Eigen::Vector3d squared_lengths = h_.colwise().squaredNorm();
    if (!std::isfinite(det_) || !squared_lengths.allFinite()) {
        detail::fail<GeometryError>("box is too large: |a|, |b|, |c| = ", h_.col(0).stableNorm(),
                                    ", ", h_.col(1).stableNorm(), ", ", h_.col(2).stableNorm(),
                                    " and |det H| = ", std::abs(det_),
                                    " (the squared lengths and |det H| must be finite doubles)");
    }
    // Flatness is judged on unit vectors, det(H) / (|a||b||c|), which neither overflows nor
    // underflows for boxes of any scale.
    Eigen::Matrix3d unit = h_;
    for (int axis = 0; axis < 3; ++axis) {
        const double length = h_.col(axis).norm();
        unit.col(axis) =
            length > 0 ? Eigen::Vector3d(h_.col(axis) / length) : Eigen::Vector3d::Zero();
    }
    const double flatness = std::abs(unit.determinant());
    if (!(flatness > flatness_tolerance) || !(std::abs(det_) > 0)) {
        detail::fail<GeometryError>(
            "box is singular or nearly flat: |det H| / (|a||b||c|) = ", flatness,
            " (|det H| = ", std::abs(det_), "; at most ", flatness_tolerance, " is flat)");
    }
    h_inv_ = h_.inverse();
    for (int axis = 0; axis < 3; ++axis) {
        widths_[axis] = 1.0 / h_inv_.row(axis).norm();
    }

    // Reduced basis of the periodic vectors, for the minimum image.
    Eigen::Matrix3d periodic_vectors = Eigen::Matrix3d::Zero();
    int periodic_axis[3] = {0, 0, 0};
    for (int axis = 0; axis < 3; ++axis) {
        if (pbc_[axis]) {
            periodic_axis[n_periodic_] = axis;
            periodic_vectors.col(n_periodic_++) = h_.col(axis);
        }
    }
    const detail::ReducedBasis reduced = detail::reduce_basis(periodic_vectors, n_periodic_);
    for (int k = 0; k < n_periodic_; ++k) {
        reduced_.col(k) = reduced.vectors.col(k);
        for (int l = 0; l < n_periodic_; ++l) {
            reduced_to_h_(periodic_axis[l], k) = reduced.transform(l, k);
        }
    }
    if (n_periodic_ > 0) {
        // Sizes bounded by 3: no heap allocation (a Box is built on every search call).
        using Bounded = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, 3, 3>;
        const Bounded b = reduced_.leftCols(n_periodic_);
        const Bounded gram_inv = (b.transpose() * b).inverse();
        reduced_gram_inv_.topLeftCorner(n_periodic_, n_periodic_) = gram_inv;
    }
}

Box Box::from_columns(const Eigen::Matrix3d& h, Periodicity pbc) {
    return Box(h, pbc);
}

Box Box::from_rows(const Eigen::Matrix3d& m, Periodicity pbc) {
    return Box(m.transpose(), pbc);
}

Box Box::from_parameters(const LatticeParameters& p, Periodicity pbc) {
    const double lengths[3] = {p.a, p.b, p.c};
    for (int axis = 0; axis < 3; ++axis) {
        if (!(std::isfinite(lengths[axis]) && lengths[axis] > 0)) {
            detail::fail<InvalidArgument>("lattice parameter ", axis_name[axis],
                                          " must be > 0 (got ", lengths[axis], ")");
        }
    }
    const char* angle_name[3] = {"alpha", "beta", "gamma"};
    const double angles[3] = {p.alpha, p.beta, p.gamma};
    for (int k = 0; k < 3; ++k) {
        if (!(std::isfinite(angles[k]) && angles[k] > 0 && angles[k] < 180)) {
            detail::fail<InvalidArgument>("lattice angle ", angle_name[k],
                                          " must be in (0, 180) degrees (got ", angles[k], ")");
        }
    }
    const double cos_alpha = std::cos(radians(p.alpha));
    const double cos_beta = std::cos(radians(p.beta));
    const double cos_gamma = std::cos(radians(p.gamma));
    const double sin_gamma = std::sin(radians(p.gamma));
    const double cx = p.c * cos_beta;
    const double cy = p.c * (cos_alpha - cos_beta * cos_gamma) / sin_gamma;
    const double cz_sq = p.c * p.c - cx * cx - cy * cy;
    if (!(cz_sq > 0)) {
        detail::fail<GeometryError>("lattice angles alpha = ", p.alpha, ", beta = ", p.beta,
                                    ", gamma = ", p.gamma, " do not form a cell");
    }
    Eigen::Matrix3d h;
    h << p.a, p.b * cos_gamma, cx, //
        0, p.b * sin_gamma, cy,    //
        0, 0, std::sqrt(cz_sq);
    return Box(h, pbc);
}

Box Box::from_parameters(double a, double b, double c, double alpha, double beta, double gamma,
                         Periodicity pbc) {
    return from_parameters(LatticeParameters{a, b, c, alpha, beta, gamma}, pbc);
}

Box Box::from_lammps(double lx, double ly, double lz, double xy, double xz, double yz,
                     Periodicity pbc) {
    const char* name[3] = {"lx", "ly", "lz"};
    const double length[3] = {lx, ly, lz};
    for (int k = 0; k < 3; ++k) {
        if (!(std::isfinite(length[k]) && length[k] > 0)) {
            detail::fail<InvalidArgument>(name[k], " must be > 0 (got ", length[k], ")");
        }
    }
    Eigen::Matrix3d h;
    h << lx, xy, xz, //
        0, ly, yz,   //
        0, 0, lz;
    return Box(h, pbc);
}

double Box::volume() const {
    return std::abs(det_);
}

LatticeParameters Box::parameters() const {
    LatticeParameters p;
    p.a = h_.col(0).norm();
    p.b = h_.col(1).norm();
    p.c = h_.col(2).norm();
    p.alpha = angle_between(h_.col(1), h_.col(2));
    p.beta = angle_between(h_.col(0), h_.col(2));
    p.gamma = angle_between(h_.col(0), h_.col(1));
    return p;
}

void Box::to_fractional(PointsView cartesian, MutablePointsView fractional) const {
    if (cartesian.size() != fractional.size()) {
        detail::fail<InvalidArgument>("to_fractional: output holds ", fractional.size(),
                                      " points but the input ", cartesian.size());
    }
    for (std::size_t i = 0; i < cartesian.size(); ++i) {
        const Eigen::Vector3d r = cartesian[i];
        fractional[i] = h_inv_ * r;
    }
}

void Box::to_cartesian(PointsView fractional, MutablePointsView cartesian) const {
    if (cartesian.size() != fractional.size()) {
        detail::fail<InvalidArgument>("to_cartesian: output holds ", cartesian.size(),
                                      " points but the input ", fractional.size());
    }
    for (std::size_t i = 0; i < fractional.size(); ++i) {
        const Eigen::Vector3d s = fractional[i];
        cartesian[i] = h_ * s;
    }
}

void Box::wrap_failure(const Fractional& s, int axis) {
    if (!std::isfinite(s[axis])) {
        detail::fail<InvalidArgument>("fractional coordinate ", axis_name[axis],
                                      " is not finite (got ", s[axis], ")");
    }
    detail::fail<InvalidArgument>("fractional coordinate ", axis_name[axis], " = ", s[axis],
                                  " is more than ", max_fractional,
                                  " box lengths away and cannot be wrapped");
}

Cartesian Box::wrap(const Cartesian& r, Shift* image) const {
    const WrappedFractional w = wrap(to_fractional(r));
    if (image != nullptr) {
        *image = w.image;
    }
    return Cartesian(r - h_ * w.image.cast<double>());
}

MinimumImage Box::minimum_image(const Cartesian& d) const {
    MinimumImage best;
    best.vector = d;
    best.distance = d.norm();
    const int k = n_periodic_;
    if (k == 0) {
        return best;
    }
    // Babai rounding in the reduced basis B: coefficients of the projection of d onto span(B).
    const auto b = reduced_.leftCols(k);
    const Eigen::Matrix<double, Eigen::Dynamic, 1, 0, 3, 1> t =
        reduced_gram_inv_.topLeftCorner(k, k) *
        (b.transpose() * static_cast<const Eigen::Vector3d&>(d));
    Eigen::Vector3i rounded = Eigen::Vector3i::Zero();
    for (int l = 0; l < k; ++l) {
        if (!std::isfinite(t[l]) || std::abs(t[l]) > max_fractional) {
            detail::fail<InvalidArgument>("displacement (", d.x(), ", ", d.y(), ", ", d.z(),
                                          ") is not finite or too far for a minimum image");
        }
        rounded[l] = -static_cast<int>(std::lround(t[l]));
    }
    Eigen::Vector3d start = d;
    for (int l = 0; l < k; ++l) {
        start += rounded[l] * reduced_.col(l);
    }
    // Any translate m with |start + B m| <= |start| has |B m| <= 2 |start|, hence
    // |m_l| <= 2 |start| sqrt((G^-1)_ll) with G = B^T B.
    const double radius = start.norm();
    int bound[3] = {0, 0, 0};
    double candidates = 1;
    for (int l = 0; l < k; ++l) {
        const double reach =
            std::floor(2.0 * radius * std::sqrt(reduced_gram_inv_(l, l)) * (1 + 1e-12));
        candidates *= 2 * reach + 1;
        if (!(candidates <= 1e7)) {
            detail::fail<GeometryError>(
                "box is too skewed for an exact minimum image (more than 1e7 lattice "
                "translates to search; lattice vectors a = (",
                h_(0, 0), ", ", h_(1, 0), ", ", h_(2, 0), "), b = (", h_(0, 1), ", ", h_(1, 1),
                ", ", h_(2, 1), "), c = (", h_(0, 2), ", ", h_(1, 2), ", ", h_(2, 2), "))");
        }
        bound[l] = static_cast<int>(reach);
    }
    Eigen::Vector3d best_vector = start;
    double best_sq = start.squaredNorm();
    Eigen::Vector3i best_m = Eigen::Vector3i::Zero();
    for (int m0 = -bound[0]; m0 <= bound[0]; ++m0) {
        for (int m1 = -bound[1]; m1 <= bound[1]; ++m1) {
            for (int m2 = -bound[2]; m2 <= bound[2]; ++m2) {
                const Eigen::Vector3d v =
                    start + m0 * reduced_.col(0) + m1 * reduced_.col(1) + m2 * reduced_.col(2);
                const double v_sq = v.squaredNorm();
                if (v_sq < best_sq) {
                    best_sq = v_sq;
                    best_vector = v;
                    best_m = Eigen::Vector3i(m0, m1, m2);
                }
            }
        }
    }
    const Eigen::Matrix<long long, 3, 1> shift =
        reduced_to_h_.cast<long long>() * (rounded + best_m).cast<long long>();
    if (shift.cwiseAbs().maxCoeff() > std::numeric_limits<int>::max()) {
        detail::fail<InvalidArgument>("displacement (", d.x(), ", ", d.y(), ", ", d.z(),
                                      ") is too many box lengths away for a minimum image");
    }
    best.shift = shift.cast<int>();
    // Recompute from the integer shift so vector == d + H * shift up to one rounding.
    best.vector =
        Cartesian(static_cast<const Eigen::Vector3d&>(d) + h_ * best.shift.cast<double>());
    best.distance = best.vector.norm();
    return best;
}

double Box::minimum_image_distance(const Cartesian& r_i, const Cartesian& r_j) const {
    return minimum_image(Cartesian(r_j - r_i)).distance;
}

} // namespace tricell
