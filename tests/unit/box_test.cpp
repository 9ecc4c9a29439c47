#include <array>
#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "support/expect_throw_msg.hpp"
#include "support/random_boxes.hpp"
#include "tricell/box.hpp"
#include "tricell/error.hpp"

using tricell::Box;
using tricell::Cartesian;
using tricell::Fractional;
using tricell::Periodicity;
using tricell::Shift;

namespace {

constexpr double pi = 3.14159265358979323846;
double rad(double deg) {
    return deg * pi / 180.0;
}

Eigen::Matrix3d triclinic_columns() {
    Eigen::Matrix3d h;
    h << 5.0, 1.2, -0.7, //
        0.3, 6.0, 0.9,   //
        -0.4, 0.2, 7.0;
    return h;
}

// Exhaustive minimum image: every translate n with |n_k| <= 2|d| / w_k (a shorter translate
// than d itself satisfies |H n| <= 2|d|), the a-coefficient chosen exactly by 1-D rounding.
double brute_force_minimum_distance(const Box& box, const Eigen::Vector3d& d) {
    const Eigen::Matrix3d& h = box.matrix();
    const Eigen::Vector3d w = box.perpendicular_widths();
    int bound[3];
    for (int k = 0; k < 3; ++k) {
        bound[k] = box.periodic(k) ? static_cast<int>(std::ceil(2 * d.norm() / w[k])) : 0;
    }
    double best_sq = d.squaredNorm();
    for (int nc = -bound[2]; nc <= bound[2]; ++nc) {
        for (int nb = -bound[1]; nb <= bound[1]; ++nb) {
            const Eigen::Vector3d partial = d + nb * h.col(1) + nc * h.col(2);
            double na = 0;
            if (box.periodic(0)) {
                na = std::round(-partial.dot(h.col(0)) / h.col(0).squaredNorm());
            }
            best_sq = std::min(best_sq, (partial + na * h.col(0)).squaredNorm());
        }
    }
    return std::sqrt(best_sq);
}

} // namespace

TEST(Box, FromRowsIsTransposeOfFromColumns) {
    const Eigen::Matrix3d h = triclinic_columns();
    const Box by_columns = Box::from_columns(h);
    const Box by_rows = Box::from_rows(h.transpose());
    EXPECT_EQ(by_columns.matrix(), h);
    EXPECT_EQ(by_rows.matrix(), h);
    EXPECT_EQ(by_columns.vector(1), Cartesian(1.2, 6.0, 0.2));
}

TEST(Box, FromParametersOrientsAAlongXAndBInXyPlane) {
    const Box box = Box::from_parameters(4.0, 5.0, 6.0, 80.0, 95.0, 110.0);
    const Eigen::Matrix3d& h = box.matrix();
    EXPECT_DOUBLE_EQ(h(0, 0), 4.0);
    EXPECT_EQ(h(1, 0), 0.0);
    EXPECT_EQ(h(2, 0), 0.0);
    EXPECT_EQ(h(2, 1), 0.0);
    EXPECT_GT(h(1, 1), 0.0);
    EXPECT_GT(h(2, 2), 0.0);
    EXPECT_GT(box.determinant(), 0.0) << "right-handed";
    const tricell::LatticeParameters p = box.parameters();
    EXPECT_NEAR(p.a, 4.0, 1e-12);
    EXPECT_NEAR(p.b, 5.0, 1e-12);
    EXPECT_NEAR(p.c, 6.0, 1e-12);
    EXPECT_NEAR(p.alpha, 80.0, 1e-10);
    EXPECT_NEAR(p.beta, 95.0, 1e-10);
    EXPECT_NEAR(p.gamma, 110.0, 1e-10);
}

TEST(Box, FromParametersHexagonalMatchesTextbookMatrix) {
    const Box box = Box::from_parameters(3.0, 3.0, 5.0, 90, 90, 120);
    Eigen::Matrix3d expected;
    expected << 3.0, -1.5, 0,       //
        0, 1.5 * std::sqrt(3.0), 0, //
        0, 0, 5.0;
    EXPECT_TRUE(box.matrix().isApprox(expected, 1e-14)) << box.matrix();
}

TEST(Box, FromLammpsPutsTiltsAboveDiagonal) {
    const Box box = Box::from_lammps(10, 11, 12, 1.5, -2.0, 0.5);
    Eigen::Matrix3d expected;
    expected << 10, 1.5, -2.0, //
        0, 11, 0.5,            //
        0, 0, 12;
    EXPECT_EQ(box.matrix(), expected);
    EXPECT_DOUBLE_EQ(box.volume(), 10.0 * 11 * 12);
}

TEST(Box, ParametersRoundTripOverRandomCells) {
    std::mt19937_64 rng(20261123);
    std::uniform_real_distribution<double> len(1, 20), ang(40, 140);
    int checked = 0;
    for (int trial = 0; trial < 500; ++trial) {
        SCOPED_TRACE(trial);
        tricell::LatticeParameters p{len(rng), len(rng), len(rng), ang(rng), ang(rng), ang(rng)};
        try {
            const Box box = Box::from_parameters(p);
            const tricell::LatticeParameters q = box.parameters();
            EXPECT_NEAR(q.a, p.a, 1e-11 * p.a);
            EXPECT_NEAR(q.b, p.b, 1e-11 * p.b);
            EXPECT_NEAR(q.c, p.c, 1e-11 * p.c);
            EXPECT_NEAR(q.alpha, p.alpha, 1e-9);
            EXPECT_NEAR(q.beta, p.beta, 1e-9);
            EXPECT_NEAR(q.gamma, p.gamma, 1e-9);
            ++checked;
        } catch (const tricell::GeometryError&) {
            // angles that cannot close a cell: checked separately
        }
    }
    EXPECT_GT(checked, 250);
}

TEST(Box, CartesianFractionalRoundTrip) {
    std::mt19937_64 rng(7);
    std::uniform_real_distribution<double> u(-50, 50);
    for (int trial = 0; trial < 200; ++trial) {
        SCOPED_TRACE(trial);
        const Box box = Box::from_columns(tricell::testing::random_box_matrix(rng, 1, 10, 2));
        const Cartesian r(u(rng), u(rng), u(rng));
        const Cartesian back = box.to_cartesian(box.to_fractional(r));
        EXPECT_LT((back - r).norm(), 1e-11 * (1 + r.norm()));
        EXPECT_TRUE((box.matrix() * box.inverse()).isIdentity(1e-12));
    }
}

TEST(Box, BulkConversionMatchesSinglePointAndAllowsAliasing) {
    const Box box = Box::from_columns(triclinic_columns());
    std::vector<Cartesian> points{{0.1, 0.2, 0.3}, {-4, 5, 100}, {7, -8, 9}};
    std::vector<Fractional> fractional(points.size());
    box.to_fractional(points, fractional);
    for (std::size_t i = 0; i < points.size(); ++i) {
        EXPECT_TRUE(fractional[i].isApprox(box.to_fractional(points[i]), 1e-15));
    }
    std::vector<double> raw{0.1, 0.2, 0.3, -4, 5, 100, 7, -8, 9};
    box.to_fractional(tricell::PointsView(raw.data(), 3),
                      tricell::MutablePointsView(raw.data(), 3));
    box.to_cartesian(tricell::PointsView(raw.data(), 3), tricell::MutablePointsView(raw.data(), 3));
    for (std::size_t i = 0; i < points.size(); ++i) {
        EXPECT_NEAR(raw[3 * i + 2], points[i].z(), 1e-12);
    }
}

TEST(Box, BulkConversionRejectsSizeMismatch) {
    const Box box = Box::from_columns(triclinic_columns());
    std::vector<Cartesian> points(3);
    std::vector<Fractional> out(2);
    EXPECT_THROW_MSG(box.to_fractional(points, out), tricell::InvalidArgument,
                     "output holds 2 points but the input 3");
    EXPECT_THROW_MSG(box.to_cartesian(out, points), tricell::InvalidArgument,
                     "output holds 3 points but the input 2");
}

// Perpendicular widths against the analytic w_a = V / |b x c| written with lattice parameters.
TEST(Box, PerpendicularWidthsMatchAnalyticFormulas) {
    struct Case {
        const char* name;
        double a, b, c, alpha, beta, gamma;
    };
    const Case cases[] = {
        {"cubic", 4, 4, 4, 90, 90, 90},
        {"orthorhombic", 3, 5, 7, 90, 90, 90},
        {"monoclinic", 5, 6, 7, 90, 104.5, 90},
        {"hexagonal", 3.2, 3.2, 5.2, 90, 90, 120},
        {"triclinic", 5.1, 6.2, 7.3, 81, 103, 112},
        {"rhombohedral", 5, 5, 5, 60, 60, 60},
    };
    for (const Case& c : cases) {
        SCOPED_TRACE(c.name);
        const Box box = Box::from_parameters(c.a, c.b, c.c, c.alpha, c.beta, c.gamma);
        const double ca = std::cos(rad(c.alpha)), cb = std::cos(rad(c.beta)),
                     cg = std::cos(rad(c.gamma));
        const double volume =
            c.a * c.b * c.c * std::sqrt(1 - ca * ca - cb * cb - cg * cg + 2 * ca * cb * cg);
        EXPECT_NEAR(box.volume(), volume, 1e-11 * volume);
        const Eigen::Vector3d w = box.perpendicular_widths();
        EXPECT_NEAR(w[0], volume / (c.b * c.c * std::sin(rad(c.alpha))), 1e-12 * c.a);
        EXPECT_NEAR(w[1], volume / (c.a * c.c * std::sin(rad(c.beta))), 1e-12 * c.b);
        EXPECT_NEAR(w[2], volume / (c.a * c.b * std::sin(rad(c.gamma))), 1e-12 * c.c);
    }
    // Closed forms for the simple systems.
    EXPECT_NEAR(Box::from_parameters(3, 5, 7, 90, 90, 90).perpendicular_widths()[1], 5, 1e-14);
    const Box mono = Box::from_parameters(5, 6, 7, 90, 104.5, 90);
    EXPECT_NEAR(mono.perpendicular_widths()[0], 5 * std::sin(rad(104.5)), 1e-12);
    EXPECT_NEAR(mono.perpendicular_widths()[1], 6, 1e-12);
    EXPECT_NEAR(mono.perpendicular_widths()[2], 7 * std::sin(rad(104.5)), 1e-12);
    const Box hex = Box::from_parameters(3.2, 3.2, 5.2, 90, 90, 120);
    EXPECT_NEAR(hex.perpendicular_widths()[0], 3.2 * std::sqrt(3.0) / 2, 1e-12);
    EXPECT_NEAR(hex.perpendicular_widths()[2], 5.2, 1e-12);
}

TEST(Box, WrapFloatingPointEdges) {
    const Box box = Box::from_columns(triclinic_columns());
    struct Case {
        double s;
        double wrapped;
        int image;
    };
    const Case cases[] = {
        {-1e-17, 0.0, 0},
        {-0.0, 0.0, 0},
        {0.0, 0.0, 0},
        {1.0, 0.0, 1},
        {-1.0, 0.0, -1},
        {std::nextafter(1.0, 0.0), std::nextafter(1.0, 0.0), 0},
        {-std::numeric_limits<double>::denorm_min(), 0.0, 0},
        {2.5, 0.5, 2},
        {-2.25, 0.75, -3},
        {1e6 + 0.25, 0.25, 1000000},
        {-1e6 - 0.25, 0.75, -1000001},
        {-1e6, 0.0, -1000000},
    };
    for (const Case& c : cases) {
        SCOPED_TRACE(c.s);
        const tricell::WrappedFractional w = box.wrap(Fractional(c.s, 0.5, 0.5));
        EXPECT_EQ(w.wrapped.x(), c.wrapped);
        EXPECT_FALSE(std::signbit(w.wrapped.x()));
        EXPECT_EQ(w.image.x(), c.image);
        EXPECT_EQ(w.image.y(), 0);
    }
}

TEST(Box, WrapAlwaysLandsInHalfOpenUnitInterval) {
    const Box box = Box::from_columns(triclinic_columns());
    std::mt19937_64 rng(99);
    std::uniform_real_distribution<double> exponent(-18, 6);
    std::uniform_int_distribution<int> sign(0, 1);
    for (int trial = 0; trial < 100000; ++trial) {
        const double magnitude = std::pow(10.0, exponent(rng));
        const double s = sign(rng) ? magnitude : -magnitude;
        const tricell::WrappedFractional w = box.wrap(Fractional(s, -s, s * 0.5));
        for (int k = 0; k < 3; ++k) {
            ASSERT_GE(w.wrapped[k], 0.0) << s;
            ASSERT_LT(w.wrapped[k], 1.0) << s;
        }
        const double original = w.wrapped.x() + w.image.x();
        ASSERT_NEAR(original, s, 4e-16 * std::max(1.0, std::abs(s))) << s;
    }
}

TEST(Box, WrapLeavesOpenAxesAlone) {
    const Box box = Box::from_columns(triclinic_columns(), Periodicity{{true, false, true}});
    const tricell::WrappedFractional w = box.wrap(Fractional(1.25, -7.5, 3.0));
    EXPECT_DOUBLE_EQ(w.wrapped.x(), 0.25);
    EXPECT_EQ(w.wrapped.y(), -7.5);
    EXPECT_EQ(w.wrapped.z(), 0.0);
    EXPECT_EQ(w.image, Shift(1, 0, 3));
}

TEST(Box, WrapCartesianReportsShift) {
    const Box box = Box::from_columns(triclinic_columns());
    const Cartesian r(-13.0, 22.0, 40.0);
    Shift image;
    const Cartesian wrapped = box.wrap(r, &image);
    const Fractional s = box.to_fractional(wrapped);
    for (int k = 0; k < 3; ++k) {
        EXPECT_GE(s[k], -1e-12);
        EXPECT_LT(s[k], 1.0 + 1e-12);
    }
    EXPECT_LT((wrapped + box.matrix() * image.cast<double>() - r).norm(), 1e-12);
}

TEST(Box, WrapRejectsNonFiniteAndAbsurdCoordinates) {
    const Box box = Box::from_columns(triclinic_columns());
    EXPECT_THROW_MSG(box.wrap(Fractional(0.1, std::nan(""), 0.2)), tricell::InvalidArgument,
                     "fractional coordinate b is not finite (got nan)");
    EXPECT_THROW_MSG(box.wrap(Fractional(0.1, 0.2, 1e12)), tricell::InvalidArgument,
                     "fractional coordinate c = 1e+12 is more than");
}

TEST(Box, MinimumImageMatchesBruteForceInSkewedCells) {
    std::mt19937_64 rng(12345);
    std::uniform_real_distribution<double> frac(-2.0, 2.0);
    std::uniform_int_distribution<int> pattern(0, 7);
    int cases = 0;
    for (int trial = 0; trial < 1500; ++trial) {
        SCOPED_TRACE(trial);
        const double skew = trial % 3 == 0 ? 4.0 : 1.0; // every third cell strongly skewed
        const Eigen::Matrix3d h = tricell::testing::random_box_matrix(rng, 1, 4, skew);
        const int bits = trial < 1000 ? 7 : pattern(rng);
        const Periodicity pbc{{bool(bits & 1), bool(bits & 2), bool(bits & 4)}};
        const Box box = Box::from_columns(h, pbc);
        const Eigen::Vector3d d = h * Eigen::Vector3d(frac(rng), frac(rng), frac(rng));
        const tricell::MinimumImage mi = box.minimum_image(Cartesian(d));
        const double expected = brute_force_minimum_distance(box, d);
        ASSERT_NEAR(mi.distance, expected, 1e-10 * (1 + expected));
        EXPECT_LT((mi.vector - (d + h * mi.shift.cast<double>())).norm(), 1e-10);
        for (int k = 0; k < 3; ++k) {
            if (!pbc[k]) {
                EXPECT_EQ(mi.shift[k], 0);
            }
        }
        ++cases;
    }
    EXPECT_EQ(cases, 1500);
}

TEST(Box, MinimumImageBeatsFractionalRoundingInSkewedCell) {
    // Strongly sheared 2-D lattice: rounding the fractional components gives a longer vector.
    const Box box = Box::from_lammps(1.0, 0.3, 10.0, 0.9, 0.0, 0.0);
    const Cartesian d(0.04, -0.47, 0.0);
    const Eigen::Vector3d s = box.to_fractional(d);
    const Eigen::Vector3d rounded = s.array().round();
    const double naive = (d - box.matrix() * rounded).norm();
    const tricell::MinimumImage mi = box.minimum_image(d);
    EXPECT_NEAR(naive, 0.85, 1e-12);
    EXPECT_NEAR(mi.distance, std::sqrt(0.1 * 0.1 + 0.15 * 0.15), 1e-12);
    EXPECT_NEAR(mi.distance, brute_force_minimum_distance(box, d), 1e-12);
    EXPECT_NEAR(box.minimum_image_distance(Cartesian(0, 0, 0), d), mi.distance, 1e-15);
}

TEST(Box, MinimumImageInOpenBoxIsIdentity) {
    const Box box = Box::from_columns(triclinic_columns(), Periodicity::none());
    const Cartesian d(100, -200, 300);
    const tricell::MinimumImage mi = box.minimum_image(d);
    EXPECT_EQ(mi.vector, d);
    EXPECT_EQ(mi.shift, Shift::Zero());
}

TEST(Box, LeftHandedBoxIsValid) {
    Eigen::Matrix3d h = Eigen::Matrix3d::Identity() * 3;
    h(2, 2) = -3;
    const Box box = Box::from_columns(h);
    EXPECT_LT(box.determinant(), 0);
    EXPECT_DOUBLE_EQ(box.volume(), 27);
    EXPECT_TRUE(box.perpendicular_widths().isApprox(Eigen::Vector3d(3, 3, 3)));
    EXPECT_NEAR(box.minimum_image(Cartesian(0, 0, 2.5)).distance, 0.5, 1e-15);
}

TEST(Box, RejectsNonFiniteEntries) {
    Eigen::Matrix3d h = triclinic_columns();
    h(1, 2) = std::numeric_limits<double>::infinity();
    EXPECT_THROW_MSG(Box::from_columns(h), tricell::InvalidArgument,
                     "lattice vector c component 1 is not finite (got inf)");
}

TEST(Box, RejectsBoxesTooLargeForDoubles) {
    EXPECT_THROW_MSG(Box::from_columns(1e103 * Eigen::Matrix3d::Identity()), tricell::GeometryError,
                     "box is too large: |a|, |b|, |c| = 1e+103, 1e+103, 1e+103 and |det H| = inf");
    Eigen::Matrix3d h = Eigen::Matrix3d::Identity();
    h(0, 0) = 2e154; // |a|^2 overflows, the volume does not
    EXPECT_THROW_MSG(Box::from_columns(h), tricell::GeometryError,
                     "box is too large: |a|, |b|, |c| = 2e+154, 1, 1 and |det H| = 2e+154");
    EXPECT_NO_THROW(Box::from_columns(1e100 * Eigen::Matrix3d::Identity()));
}

TEST(Box, RejectsSingularAndNearlyFlatBoxes) {
    Eigen::Matrix3d h = triclinic_columns();
    h.col(2) = h.col(0) + h.col(1);
    EXPECT_THROW_MSG(Box::from_columns(h), tricell::GeometryError, "singular or nearly flat");
    h.col(2) += Eigen::Vector3d(0, 0, 1e-13);
    EXPECT_THROW_MSG(Box::from_columns(h), tricell::GeometryError, "|det H| = ");
}

TEST(Box, RejectsZeroPeriodicVector) {
    Eigen::Matrix3d h = triclinic_columns();
    h.col(1).setZero();
    EXPECT_THROW_MSG(Box::from_columns(h), tricell::GeometryError,
                     "lattice vector b is zero but axis b is periodic");
}

TEST(Box, RejectsDependentPeriodicVectorsNamingThem) {
    Eigen::Matrix3d h = triclinic_columns();
    h.col(2) = 2.5 * h.col(0);
    EXPECT_THROW_MSG(Box::from_columns(h, Periodicity{{true, false, true}}), tricell::GeometryError,
                     "box is singular or nearly flat: the periodic lattice vectors a and c are "
                     "parallel or nearly so, |a x c| / (|a||c|) = ");
    // Open along c, the parallel vector only sets the frame: replaced.
    EXPECT_NO_THROW(Box::from_columns(h, Periodicity{{true, true, false}}));
    h = triclinic_columns();
    h.col(2) = h.col(0) - 3 * h.col(1);
    EXPECT_THROW_MSG(Box::from_columns(h), tricell::GeometryError,
                     "the periodic lattice vectors a, b and c are coplanar or nearly so");
}

// Along open axes a zero vector (a molecule's all-zero cell, a slab's zero c) is completed by
// unit vectors orthogonal to the others, right-handed; given open vectors that span are kept,
// and open vectors that do not span with the others are all replaced. Periodic vectors never
// change.
TEST(Box, CompletesTheVectorsOfOpenAxes) {
    const Eigen::Matrix3d given = triclinic_columns();
    const auto expect_completed = [&](const Eigen::Matrix3d& h, const Periodicity& pbc,
                                      const std::array<bool, 3>& kept) {
        const Box box = Box::from_columns(h, pbc);
        const Eigen::Matrix3d& out = box.matrix();
        EXPECT_GT(box.determinant(), 0.0);
        for (int k = 0; k < 3; ++k) {
            if (kept[std::size_t(k)]) {
                EXPECT_EQ(out.col(k), h.col(k)) << "axis " << k;
                continue;
            }
            EXPECT_NEAR(out.col(k).norm(), 1.0, 1e-15) << "axis " << k;
            for (int l = 0; l < 3; ++l) {
                if (l != k && (pbc[l] || !kept[std::size_t(l)])) {
                    EXPECT_NEAR(out.col(k).dot(out.col(l)), 0.0, 1e-12) << k << " and " << l;
                }
            }
        }
    };
    // A molecule: the identity.
    EXPECT_EQ(Box::from_columns(Eigen::Matrix3d::Zero(), Periodicity::none()).matrix(),
              Eigen::Matrix3d::Identity());
    for (int open = 0; open < 3; ++open) {
        // A slab: the zero vector of its open axis completed.
        Eigen::Matrix3d slab = given;
        slab.col(open).setZero();
        Periodicity pbc = Periodicity::all();
        pbc.axes[std::size_t(open)] = false;
        std::array<bool, 3> kept{{true, true, true}};
        kept[std::size_t(open)] = false;
        expect_completed(slab, pbc, kept);
        // A wire along `open`'s axis: two zero vectors, and one vector only along the wire.
        Eigen::Matrix3d wire = Eigen::Matrix3d::Zero();
        wire.col(open) = given.col(open);
        Periodicity line = Periodicity::none();
        line.axes[std::size_t(open)] = true;
        std::array<bool, 3> along{{false, false, false}};
        along[std::size_t(open)] = true;
        expect_completed(wire, line, along);
        wire.col(open) = Eigen::Vector3d(0, 4, 0); // the helper direction switches
        expect_completed(wire, line, along);
        // An open vector parallel to a periodic one: every open vector replaced.
        Eigen::Matrix3d parallel = given;
        parallel.col(open) = 3 * given.col((open + 1) % 3);
        expect_completed(parallel, pbc, kept);
        // An open vector that spans is the caller's frame, kept.
        expect_completed(given, pbc, {{true, true, true}});
    }
    // Open axes that span with one zero among them: the zero one completed, the others kept.
    Eigen::Matrix3d two = given;
    two.col(1).setZero();
    expect_completed(two, Periodicity::none(), {{true, false, true}});
}

TEST(Box, RejectsBadLatticeParameters) {
    EXPECT_THROW_MSG(Box::from_parameters(-1, 2, 3, 90, 90, 90), tricell::InvalidArgument,
                     "lattice parameter a must be > 0 (got -1)");
    EXPECT_THROW_MSG(Box::from_parameters(1, 2, 3, 90, 180, 90), tricell::InvalidArgument,
                     "lattice angle beta must be in (0, 180) degrees (got 180)");
    EXPECT_THROW_MSG(Box::from_parameters(1, 2, 3, 90, 90, std::nan("")), tricell::InvalidArgument,
                     "lattice angle gamma");
    EXPECT_THROW_MSG(Box::from_parameters(1, 1, 1, 10, 10, 100), tricell::GeometryError,
                     "lattice angles alpha = 10, beta = 10, gamma = 100 do not form a cell");
    EXPECT_THROW_MSG(Box::from_lammps(1, 0, 1, 0, 0, 0), tricell::InvalidArgument,
                     "ly must be > 0 (got 0)");
}

TEST(Box, ExtremelySkewedBoxNeitherOverflowsNorHangs) {
    // Found by fuzzing the command line's inputs: reduction coefficients beyond int range.
    Eigen::Matrix3d rows;
    rows << 0, 2.7155, 2.155e9, //
        2.7155, 0, 2.7155,      //
        5.5e7, 2.7155, 0;
    const Box box = Box::from_rows(rows);
    const tricell::MinimumImage mi = box.minimum_image(Cartesian(1.0, 1.0, 1.0));
    EXPECT_LE(mi.distance, std::sqrt(3.0) + 1e-9);
    EXPECT_LT(
        (mi.vector - (Eigen::Vector3d(1, 1, 1) + box.matrix() * mi.shift.cast<double>())).norm(),
        1e-6);
}

TEST(Box, AnyScaleIsValid) {
    for (const double scale : {1e-90, 1e-30, 1.0, 1e30, 1e90}) { // det H must stay a normal double
        SCOPED_TRACE(scale);
        const Box box = Box::from_parameters(scale, scale, scale, 90, 90, 90);
        EXPECT_NEAR(box.perpendicular_widths()[0] / scale, 1.0, 1e-12);
    }
}
