// Tests of tricell::VerletList: at every step of random trajectories the refreshed
// list equals the brute-force list, whether the caller wraps positions or not, while the box
// deforms, and when atoms jump; the rebuild rule and box budget at their thresholds; the cost
// model; and the md_lj example's forces against brute-force forces.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <sstream>
#include <vector>

#include <gtest/gtest.h>

#include "lj_system.hpp"
#include "support/brute_force.hpp"
#include "support/expect_throw_msg.hpp"
#include "support/random_boxes.hpp"
#include "tricell/error.hpp"
#include "tricell/tuning.hpp"
#include "tricell/verlet.hpp"

using tricell::Box;
using tricell::CellSize;
using tricell::InvalidArgument;
using tricell::Periodicity;
using tricell::Shift;
using tricell::SkinCostModel;
using tricell::VerletList;
using tricell::VerletOptions;
using tricell::testing::PairKey;
using tricell::testing::PairMap;
using tricell::testing::PairValue;

namespace {

constexpr double tol = 1e-9;

// Unoptimised or AddressSanitizer builds run shorter trajectories (the same seeds and checks).
#if defined(__has_feature)
#if __has_feature(address_sanitizer)
#define TRICELL_VERLET_INSTRUMENTED 1
#endif
#endif
#if defined(__SANITIZE_ADDRESS__) || !defined(NDEBUG)
#define TRICELL_VERLET_INSTRUMENTED 1
#endif
#ifdef TRICELL_VERLET_INSTRUMENTED
constexpr int trajectory_steps = 40;
#else
constexpr int trajectory_steps = 100;
#endif

VerletOptions verlet_options(double cutoff, double skin, bool half = false) {
    VerletOptions o;
    o.neighbors.cutoff = cutoff;
    o.skin = skin;
    o.neighbors.half = half;
    o.neighbors.quantities.vectors = true;
    return o;
}

PairMap to_map(const VerletList& list) {
    PairMap out;
    for (std::size_t k = 0; k < list.size(); ++k) {
        const Shift s = list.pairs().shift(k);
        out[PairKey{list.pairs().i()[k], list.pairs().j()[k], s[0], s[1], s[2]}] =
            PairValue{list.pairs().distances()[k], list.pairs().vector(k)};
    }
    return out;
}

// Equal as sets of (i, j, S) with d and D within tol; an entry may be missing from one side
// only when its distance is within tol of the cutoff.
::testing::AssertionResult same_pairs(const PairMap& expected, const PairMap& actual,
                                      double cutoff) {
    std::ostringstream why;
    auto key_text = [](const PairKey& key) {
        const auto& [i, j, a, b, c] = key;
        std::ostringstream out;
        out << "i=" << i << " j=" << j << " S=(" << a << "," << b << "," << c << ")";
        return out.str();
    };
    for (const auto& [key, value] : expected) {
        const auto found = actual.find(key);
        if (found == actual.end()) {
            if (std::abs(value.distance - cutoff) > tol) {
                why << "missing " << key_text(key) << " d=" << value.distance << "; ";
            }
        } else if (std::abs(found->second.distance - value.distance) > tol ||
                   (found->second.vector - value.vector).norm() > tol) {
            why << "differs " << key_text(key) << " d=" << found->second.distance << " vs "
                << value.distance << "; ";
        }
    }
    for (const auto& [key, value] : actual) {
        if (expected.count(key) == 0 && std::abs(value.distance - cutoff) > tol) {
            why << "extra " << key_text(key) << " d=" << value.distance << "; ";
        }
    }
    if (why.str().empty()) {
        return ::testing::AssertionSuccess();
    }
    return ::testing::AssertionFailure() << why.str().substr(0, 600);
}

::testing::AssertionResult matches_brute_force(const VerletList& list, const Box& box,
                                               const std::vector<Eigen::Vector3d>& x) {
    const double cutoff = list.options().neighbors.cutoff;
    PairMap expected = tricell::testing::brute_force_pairs(box, x, cutoff);
    if (list.options().neighbors.half) {
        expected = tricell::testing::canonical_half(expected);
    }
    return same_pairs(expected, to_map(list), cutoff);
}

std::vector<Eigen::Vector3d> random_positions(std::mt19937_64& rng, const Box& box, std::size_t n) {
    std::uniform_real_distribution<double> unit(0, 1);
    std::vector<Eigen::Vector3d> x;
    for (std::size_t i = 0; i < n; ++i) {
        x.push_back(box.matrix() * Eigen::Vector3d(unit(rng), unit(rng), unit(rng)));
    }
    return x;
}

Eigen::Vector3d random_direction(std::mt19937_64& rng) {
    std::normal_distribution<double> normal;
    return Eigen::Vector3d(normal(rng), normal(rng), normal(rng)).normalized();
}

// ---- random trajectories ---------------------------------------------------------------------

enum class Wrapping { none, every_step, random_lattice_jumps };
enum class Deformation { none, affine, box_only };

struct TrajectoryStats {
    std::vector<bool> rebuilt; // per step
    int crossings = 0;         // face crossings of the true trajectory
    int teleports = 0;
};

// One trajectory from `seed`; the same seed gives the same true motion whatever `wrapping`.
TrajectoryStats run_trajectory(std::uint64_t seed, Wrapping wrapping, int steps) {
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> unit(0, 1);
    auto uniform = [&](double lo, double hi) { return lo + (hi - lo) * unit(rng); };
    const bool half = seed % 2 == 1;
    const auto deformation = static_cast<Deformation>((seed / 2) % 3);
    Periodicity pbc = Periodicity::all();
    if (seed % 5 == 4) {
        pbc = Periodicity{{true, seed % 3 != 0, false}};
    }
    Eigen::Matrix3d h = tricell::testing::random_box_matrix(rng, 4, 8, seed % 4 == 3 ? 1.5 : 0.4);
    Box box = Box::from_columns(h, pbc);
    const double width = box.perpendicular_widths().minCoeff();
    // Mostly cutoffs below half the box, sometimes beyond the box (images of the atom itself).
    const double cutoff = width * (seed % 7 == 6 ? uniform(1.0, 1.6) : uniform(0.25, 0.6));
    const double skin = cutoff * uniform(0.05, 0.35);
    // Fewer atoms when the cutoff spans the box (every pair has many images).
    const std::size_t n =
        cutoff > width ? 6 + std::size_t(unit(rng) * 8) : 20 + std::size_t(unit(rng) * 24);
    VerletOptions options = verlet_options(cutoff, skin, half);
    options.neighbors.cells_per_cutoff = 1 + double(seed % 3);
    // The Verlet list works over any backend: seeds 1 to 30 take each of the registry's in turn.
    const std::vector<tricell::SearchBackend>& backends = tricell::search_backends();
    options.neighbors.backend = backends[(seed / 3) % backends.size()];
    VerletList list(options);

    std::vector<Eigen::Vector3d> truth = random_positions(rng, box, n);
    // Every fourth atom sits on the a face and crosses it at every step (fractional a
    // coordinate alternating between +1e-4 and -1e-4); the others drift and cross faces too.
    auto on_face = [](std::size_t i) { return i % 4 == 0; };
    std::vector<Eigen::Vector3d> velocity(n);
    // Up to skin / 5 per step; much slower in a deforming box, so that the box change decides.
    const double speed = deformation == Deformation::none ? 0.2 : 0.005;
    const double jitter = deformation == Deformation::none ? 0.02 : 0.002;
    for (auto& v : velocity) {
        v = random_direction(rng) * uniform(0, speed) * skin;
    }
    Eigen::Matrix3d rate;
    for (int k = 0; k < 9; ++k) {
        rate(k / 3, k % 3) = 2e-3 * uniform(-1, 1);
    }
    rate.diagonal() = -2e-3 * Eigen::Vector3d::Ones(); // compression brings pairs closer
    std::uniform_int_distribution<int> lattice(-2, 2);
    std::mt19937_64 lattice_rng(seed + 1000); // its own stream: the true motion stays the same
    std::uniform_int_distribution<std::size_t> atom(0, n - 1);
    // Sudden jumps, of at least 1.5 skins to the nearest lattice translate: with the other
    // motion (at most skin / 2 + skin / 5 + jitter) the atom is then beyond skin / 2.
    const bool teleports = 1.5 * skin < 0.4 * width;
    TrajectoryStats stats;
    std::vector<Eigen::Vector3i> image(n, Eigen::Vector3i::Zero());
    for (int step = 0; step < steps; ++step) {
        SCOPED_TRACE(::testing::Message() << "step " << step);
        bool teleport = false;
        if (step > 0) {
            for (std::size_t i = 0; i < n; ++i) {
                truth[i] += velocity[i] + random_direction(rng) * (jitter * skin);
            }
            if (deformation != Deformation::none) {
                // A steady strain rate (shear and compression, 0.2 % per step) plus noise.
                Eigen::Matrix3d strain = rate;
                for (int k = 0; k < 9; ++k) {
                    strain(k / 3, k % 3) += 5e-4 * uniform(-1, 1);
                }
                const Eigen::Matrix3d f = Eigen::Matrix3d::Identity() + strain;
                h = f * h;
                box = Box::from_columns(h, pbc);
                if (deformation == Deformation::affine) {
                    for (auto& r : truth) {
                        r = f * r; // fractional coordinates unchanged
                    }
                }
            }
            if (teleports && unit(rng) < 0.04) { // a sudden jump: must rebuild
                Eigen::Vector3d jump;
                do {
                    jump = random_direction(rng) * uniform(1.5 * skin, 2 * width);
                } while (box.minimum_image(tricell::Cartesian(jump)).distance < 1.5 * skin);
                truth[atom(rng)] += jump;
                teleport = true;
                ++stats.teleports;
            }
        }
        for (std::size_t i = 0; i < n; ++i) {
            if (on_face(i) && !teleport) {
                Eigen::Vector3d s = box.inverse() * truth[i];
                s[0] = step % 2 == 0 ? 1e-4 : -1e-4;
                truth[i] = h * s;
            }
            const Eigen::Vector3i now =
                box.wrap(box.to_fractional(tricell::Cartesian(truth[i]))).image.cast<int>();
            stats.crossings += (now - image[i]).cwiseAbs().sum();
            image[i] = now;
        }
        std::vector<Eigen::Vector3d> x = truth;
        for (std::size_t i = 0; i < n; ++i) {
            if (wrapping == Wrapping::every_step) {
                x[i] = box.wrap(tricell::Cartesian(truth[i]));
            } else if (wrapping == Wrapping::random_lattice_jumps) {
                Eigen::Vector3d k(lattice(lattice_rng), lattice(lattice_rng), lattice(lattice_rng));
                for (int a = 0; a < 3; ++a) {
                    k[a] = pbc[a] ? k[a] : 0;
                }
                x[i] += h * k;
            }
        }
        const bool expected = list.needs_rebuild(box, x);
        const bool rebuilt = list.update(box, x);
        EXPECT_EQ(rebuilt, expected);
        if (teleport) {
            EXPECT_TRUE(rebuilt);
        }
        stats.rebuilt.push_back(rebuilt);
        EXPECT_TRUE(matches_brute_force(list, box, x));
        if (::testing::Test::HasFailure()) {
            break;
        }
    }
    return stats;
}

class VerletTrajectory : public ::testing::TestWithParam<std::uint64_t> {};

TEST_P(VerletTrajectory, EveryStepEqualsBruteForce_WrappedOrNot) {
    const std::uint64_t seed = GetParam();
    SCOPED_TRACE(::testing::Message() << "seed " << seed);
    constexpr int steps = trajectory_steps;
    const TrajectoryStats plain = run_trajectory(seed, Wrapping::none, steps);
    const TrajectoryStats wrapped = run_trajectory(seed, Wrapping::every_step, steps);
    const TrajectoryStats jumped = run_trajectory(seed, Wrapping::random_lattice_jumps, steps);
    // Wrapping or shifting by lattice vectors neither adds nor hides a rebuild.
    EXPECT_EQ(wrapped.rebuilt, plain.rebuilt);
    EXPECT_EQ(jumped.rebuilt, plain.rebuilt);
    // The trajectory exercised what it is meant to: atoms crossing faces many times, and a
    // list that is reused between rebuilds.
    EXPECT_GE(plain.crossings, steps);
    const auto rebuilds = std::count(plain.rebuilt.begin(), plain.rebuilt.end(), true);
    EXPECT_GE(rebuilds, steps >= 100 ? 2 : 1);
    if (static_cast<Deformation>((seed / 2) % 3) != Deformation::box_only) {
        // (With Cartesian positions kept while the box strains, atoms far from the origin
        // move relative to the box at every step: rebuilds are frequent there, and correct.)
        EXPECT_LE(rebuilds, steps - 10);
    }
}

INSTANTIATE_TEST_SUITE_P(Seeds, VerletTrajectory, ::testing::Range<std::uint64_t>(1, 31));

// ---- the rebuild rule at its thresholds --------------------------------------------------------

const Box cube10 = Box::from_parameters(10, 10, 10, 90, 90, 90);

TEST(VerletList, NoMotion_NoRebuild) {
    std::mt19937_64 rng(11);
    const auto x = random_positions(rng, cube10, 50);
    VerletList list(verlet_options(3, 0.5));
    EXPECT_TRUE(list.needs_rebuild(cube10, x));
    EXPECT_TRUE(list.update(cube10, x));
    EXPECT_FALSE(list.needs_rebuild(cube10, x));
    EXPECT_FALSE(list.update(cube10, x));
    EXPECT_EQ(list.rebuild_count(), 1u);
    EXPECT_EQ(list.updates_since_build(), 1u);
    EXPECT_TRUE(matches_brute_force(list, cube10, x));
    // A zero skin still reuses the list for an unchanged configuration.
    VerletList zero(verlet_options(3, 0));
    EXPECT_TRUE(zero.update(cube10, x));
    EXPECT_FALSE(zero.update(cube10, x));
}

TEST(VerletList, RebuildsWhenAnAtomMovesMoreThanHalfTheSkin) {
    const double skin = 0.4;
    for (const std::uint64_t seed : {1, 2, 3}) {
        SCOPED_TRACE(seed);
        std::mt19937_64 rng(seed);
        auto x = random_positions(rng, cube10, 40);
        VerletList list(verlet_options(2.5, skin, seed == 2));
        list.update(cube10, x);
        const Eigen::Vector3d dir = random_direction(rng);
        x[7] += 0.499 * skin * dir;
        EXPECT_FALSE(list.needs_rebuild(cube10, x));
        EXPECT_FALSE(list.update(cube10, x));
        EXPECT_NEAR(list.max_displacement(cube10, x), 0.499 * skin, 1e-12);
        EXPECT_TRUE(matches_brute_force(list, cube10, x));
        x[7] += 0.002 * skin * dir;
        EXPECT_TRUE(list.needs_rebuild(cube10, x));
        EXPECT_TRUE(list.update(cube10, x));
        EXPECT_EQ(list.rebuild_count(), 2u);
        EXPECT_TRUE(matches_brute_force(list, cube10, x));
    }
}

TEST(VerletList, LatticeJumpsAndWrappingDoNotRebuild) {
    std::mt19937_64 rng(5);
    const Box box = Box::from_parameters(9, 10, 11, 75, 100, 115);
    auto x = random_positions(rng, box, 60);
    VerletList list(verlet_options(3, 0.6, true));
    list.update(box, x);
    // Every atom far outside the box by a lattice vector, plus a small move: no rebuild, and S
    // is relative to the new positions.
    std::uniform_int_distribution<int> k(-1000, 1000);
    for (auto& r : x) {
        r += box.matrix() * Eigen::Vector3d(k(rng), k(rng), k(rng)) + 0.05 * random_direction(rng);
    }
    EXPECT_FALSE(list.needs_rebuild(box, x));
    EXPECT_FALSE(list.update(box, x));
    EXPECT_TRUE(matches_brute_force(list, box, x));
    // Wrapped back into the box: still no rebuild.
    for (auto& r : x) {
        r = box.wrap(tricell::Cartesian(r));
    }
    EXPECT_FALSE(list.update(box, x));
    EXPECT_TRUE(matches_brute_force(list, box, x));
    EXPECT_EQ(list.rebuild_count(), 1u);
}

TEST(VerletList, SkewedBoxUsesTheTrueMinimumImageOfTheDisplacement) {
    // A strongly skewed small box with a skin comparable to its widths: for some displacements,
    // rounding the fractional displacement is not the shortest translate. The atom must count
    // as having moved by the shortest one (no rebuild) and the list must stay exact.
    Eigen::Matrix3d rows;
    rows << 3, 0, 0, 2.7, 1.2, 0, 2.6, 1.0, 1.1;
    const Box box = Box::from_rows(rows);
    const double cutoff = 1.0, skin = 2.0;
    std::mt19937_64 rng(17);
    int found = 0;
    for (int attempt = 0; attempt < 2000 && found < 5; ++attempt) {
        SCOPED_TRACE(attempt);
        const Eigen::Vector3d d = random_direction(rng) * 0.95 * (skin / 2);
        Eigen::Vector3d s = box.inverse() * d;
        const Eigen::Vector3d rounded = box.matrix() * (s - s.array().round().matrix());
        if (rounded.norm() <= skin / 2) {
            continue; // rounding is good enough here
        }
        ++found;
        auto x = random_positions(rng, box, 6);
        VerletList list(verlet_options(cutoff, skin));
        list.update(box, x);
        x[2] += d;
        EXPECT_NEAR(list.max_displacement(box, x),
                    box.minimum_image(tricell::Cartesian(d)).distance, 1e-9);
        EXPECT_FALSE(list.update(box, x));
        EXPECT_TRUE(matches_brute_force(list, box, x));
    }
    EXPECT_GE(found, 1);
}

TEST(VerletList, BoxCompressionSpendsTheSkin) {
    // Uniform scaling H -> H / (1 + f) with the atoms moving along (fixed fractional
    // coordinates): eps = f, the budget is (skin - f r_c) / 2.
    std::mt19937_64 rng(23);
    const Eigen::Matrix3d h0 = tricell::testing::random_box_matrix(rng, 8, 10, 0.4);
    const Box box0 = Box::from_columns(h0);
    const auto x0 = random_positions(rng, box0, 50);
    const double cutoff = 2.5, skin = 0.3;
    VerletList list(verlet_options(cutoff, skin));
    list.update(box0, x0);
    EXPECT_DOUBLE_EQ(list.displacement_budget(box0), skin / 2);
    for (const double f : {0.01, 0.05, 0.1, 0.2}) {
        SCOPED_TRACE(f);
        const Box box = Box::from_columns(h0 / (1 + f));
        std::vector<Eigen::Vector3d> x;
        for (const auto& r : x0) {
            x.push_back(r / (1 + f));
        }
        EXPECT_NEAR(list.displacement_budget(box), 0.5 * (skin - f * cutoff), 1e-12);
        EXPECT_NEAR(list.max_displacement(box, x), 0, 1e-12);
        EXPECT_EQ(list.needs_rebuild(box, x), f * cutoff > skin);
        VerletList fresh = list;
        EXPECT_EQ(fresh.update(box, x), f * cutoff > skin);
        EXPECT_TRUE(matches_brute_force(fresh, box, x));
    }
    // Expansion never costs budget.
    const Box bigger = Box::from_columns(h0 * 1.3);
    EXPECT_DOUBLE_EQ(list.displacement_budget(bigger), skin / 2);
}

TEST(VerletList, ShearWithFixedCartesianPositionsCountsAsDisplacement) {
    // The box shears, the caller keeps Cartesian positions: atoms move relative to the box.
    std::mt19937_64 rng(29);
    Eigen::Matrix3d h = Eigen::Matrix3d::Identity() * 9;
    const auto x = random_positions(rng, Box::from_columns(h), 60);
    VerletList list(verlet_options(2.5, 0.4, true));
    int rebuilds = 0;
    for (int step = 0; step < 40; ++step) {
        SCOPED_TRACE(step);
        h(0, 2) += 0.05; // tilt c along x
        const Box box = Box::from_columns(h);
        rebuilds += list.update(box, x);
        EXPECT_TRUE(matches_brute_force(list, box, x));
    }
    EXPECT_GT(rebuilds, 1);
    EXPECT_LT(rebuilds, 40);
}

TEST(VerletList, AtomCountOrPeriodicityChangeRebuilds) {
    std::mt19937_64 rng(31);
    auto x = random_positions(rng, cube10, 30);
    VerletList list(verlet_options(3, 0.3));
    list.update(cube10, x);
    x.push_back(Eigen::Vector3d(1, 2, 3));
    EXPECT_TRUE(list.needs_rebuild(cube10, x));
    EXPECT_TRUE(list.update(cube10, x));
    EXPECT_TRUE(matches_brute_force(list, cube10, x));
    const Box slab = Box::from_parameters(10, 10, 10, 90, 90, 90, Periodicity{{true, true, false}});
    EXPECT_TRUE(std::isinf(list.max_displacement(slab, x)));
    EXPECT_LT(list.displacement_budget(slab), 0);
    EXPECT_TRUE(list.update(slab, x));
    EXPECT_TRUE(matches_brute_force(list, slab, x));
    list.reset();
    EXPECT_TRUE(list.update(slab, x));
    EXPECT_EQ(list.rebuild_count(), 4u);
}

TEST(VerletList, OneAtomAndItsImagesInATinyBox) {
    const Box box = Box::from_parameters(1.0, 1.1, 1.2, 80, 95, 105);
    std::vector<Eigen::Vector3d> x{{0.1, 0.2, 0.3}};
    for (const bool half : {false, true}) {
        SCOPED_TRACE(half);
        VerletList list(verlet_options(2.2, 0.5, half));
        list.update(box, x);
        EXPECT_GT(list.size(), 10u);
        x[0] += Eigen::Vector3d(0.1, -0.1, 0.05);
        list.update(box, x);
        EXPECT_TRUE(matches_brute_force(list, box, x));
    }
    VerletList empty(verlet_options(2, 0.5));
    EXPECT_TRUE(empty.update(box, std::vector<Eigen::Vector3d>{}));
    EXPECT_TRUE(empty.pairs().empty());
    EXPECT_EQ(empty.pairs().offsets(), std::vector<std::size_t>{0});
}

TEST(VerletList, QuantitiesAndOffsets) {
    std::mt19937_64 rng(37);
    const auto x = random_positions(rng, cube10, 80);
    VerletOptions o;
    o.neighbors.cutoff = 2.5;
    o.skin = 0.3;
    o.neighbors.quantities = tricell::Quantities{false, false, false};
    VerletList bare(o);
    bare.update(cube10, x);
    EXPECT_TRUE(bare.pairs().shifts().empty());
    EXPECT_TRUE(bare.pairs().distances().empty());
    EXPECT_TRUE(bare.pairs().vectors().empty());
    VerletList all(verlet_options(2.5, 0.3));
    all.update(cube10, x);
    ASSERT_EQ(bare.size(), all.size());
    EXPECT_EQ(bare.pairs().i(), all.pairs().i());
    EXPECT_EQ(bare.pairs().j(), all.pairs().j());
    ASSERT_EQ(all.pairs().offsets().size(), x.size() + 1);
    for (std::size_t i = 0; i < x.size(); ++i) {
        for (std::size_t k = all.pairs().offsets()[i]; k < all.pairs().offsets()[i + 1]; ++k) {
            EXPECT_EQ(all.pairs().i()[k], i);
        }
    }
    EXPECT_EQ(all.pairs().offsets().back(), all.size());
    EXPECT_GE(all.candidate_count(), all.size());
}

TEST(VerletList, ErrorsNameTheValue) {
    auto with = [](double cutoff, double skin) {
        VerletOptions o;
        o.neighbors.cutoff = cutoff;
        o.skin = skin;
        return o;
    };
    EXPECT_THROW_MSG(VerletList(with(-1.5, 0.1)), InvalidArgument, "cutoff must be > 0 (got -1.5)");
    EXPECT_THROW_MSG(VerletList(with(std::nan(""), 0.1)), InvalidArgument, "cutoff must be finite");
    EXPECT_THROW_MSG(VerletList(with(2, -0.1)), InvalidArgument, "skin must be >= 0 (got -0.1)");
    EXPECT_THROW_MSG(VerletList(with(2, std::numeric_limits<double>::infinity())), InvalidArgument,
                     "skin must be finite (got inf)");
    VerletOptions o = with(2, 0.1);
    o.neighbors.cells_per_cutoff = 0.5;
    EXPECT_THROW_MSG(o.validate(), InvalidArgument,
                     "cells_per_cutoff must be 0 (chosen by the search) or >= 1 (got 0.5)");
    o = with(2, 0.1);
    o.neighbors.threads = -2;
    EXPECT_THROW_MSG(o.validate(), InvalidArgument, "threads must be in [0, 1024] (got -2)");
    o = with(2, 0.1);
    o.neighbors.radii = {1.0};
    EXPECT_THROW_MSG(o.validate(), InvalidArgument, "the Verlet list takes one cutoff");
    EXPECT_THROW_MSG(VerletList().update(cube10, std::vector<Eigen::Vector3d>{}), InvalidArgument,
                     "cutoff must be > 0 (got 0)");

    // A non-finite position: at a build, at a refresh and in needs_rebuild. The stored pairs
    // are left empty, never half written, and the next update rebuilds.
    std::mt19937_64 rng(41);
    auto x = random_positions(rng, cube10, 10);
    VerletList list(verlet_options(3, 0.5));
    list.update(cube10, x);
    ASSERT_FALSE(list.pairs().empty());
    x[3].y() = std::nan("");
    EXPECT_THROW_MSG(list.needs_rebuild(cube10, x), InvalidArgument, "position 3 is not finite");
    EXPECT_THROW_MSG(list.update(cube10, x), InvalidArgument, "position 3 is not finite");
    EXPECT_TRUE(list.pairs().empty());
    EXPECT_THROW_MSG(list.update(cube10, x), InvalidArgument, "position 3 is not finite");
    x[3].y() = 1;
    EXPECT_TRUE(list.update(cube10, x));
    EXPECT_TRUE(matches_brute_force(list, cube10, x));
    EXPECT_THROW_MSG(list.update(cube10, tricell::PointsView(nullptr, 10)), InvalidArgument,
                     "positions: null data for 10 points");
    EXPECT_TRUE(list.pairs().empty());
}

// Found by the C API fuzzer: a coordinate of 1e300 along an open axis widens the candidates'
// rounding margin (relative to the coordinates) to ~1e286, which spans ~1e286 images of the one
// periodic axis. Every backend refuses it with a message naming the radius and leaves the list
// empty (the direct and octree backends cast the image count to int: undefined behaviour, and
// the octree's wrapped-around count silently lost every pair).
TEST(VerletList, HugeCoordinateOnAnOpenAxis_RefusedByEveryBackend) {
    const Box box = Box::from_rows((Eigen::Matrix3d() << 3, -1.663229515947517, 2.9175446155024503,
                                    0, 3, -3.7960784313725489, 0, 0, 3)
                                       .finished(),
                                   tricell::Periodicity{{false, true, false}});
    const std::vector<Eigen::Vector3d> x = {{7.4999063294325072, 3.2026348788673333, -6.21},
                                            {10, 1e-300, 1e300},
                                            {-1.9074678308869324, -0.28953989117890067, 5.85}};
    for (const tricell::SearchBackend backend : tricell::search_backends()) {
        SCOPED_TRACE(tricell::backend_name(backend));
        VerletOptions o = verlet_options(6.0225681678921568, 0.7753593772789843);
        o.neighbors.backend = backend;
        o.neighbors.max_pairs = 20000;
        VerletList list(o);
        EXPECT_THROW_MSG(list.update(box, x), InvalidArgument, "search radius");
        EXPECT_TRUE(list.pairs().empty());
    }
}

// ---- cost model ------------------------------------------------------------------------------

SkinCostModel lj_model() {
    SkinCostModel m;
    m.cutoff = 2.5;
    m.density = 0.8;
    m.displacement_per_step = 0.02;
    m.build_per_atom = 2e-7;
    m.build_per_test = 2e-9;
    m.build_per_cell_visit = 5e-9;
    m.refresh_per_atom = 2e-8;
    m.refresh_per_candidate = 1.5e-9;
    return m;
}

TEST(SkinCostModel, StencilCells) {
    EXPECT_EQ(tricell::stencil_cells(1), 27u);
    EXPECT_EQ(tricell::stencil_cells(2), 125u);
    // h = r_c with r_l = 1.12 r_c: the 27 neighbours plus the 54 face neighbours at distance 2
    EXPECT_EQ(tricell::stencil_cells(1.12), 81u);
    EXPECT_DOUBLE_EQ(tricell::cells_per_list_radius(CellSize::cutoff, 2.5, 0.5), 3.0 / 2.5);
    EXPECT_DOUBLE_EQ(tricell::cells_per_list_radius(CellSize::list_radius, 2.5, 0.5), 1.0);
    // Finer cells scan a volume closer to the sphere 4 pi / 3 = 4.19 (in units of r^3).
    double previous = 1e9;
    for (const double k : {1.0, 2.0, 3.0, 4.0}) {
        const double volume = double(tricell::stencil_cells(k)) / (k * k * k);
        EXPECT_LT(volume, previous);
        EXPECT_GT(volume, 4.18879);
        previous = volume;
    }
}

TEST(SkinCostModel, PredictionFollowsTheFormula) {
    const SkinCostModel m = lj_model();
    const auto p = tricell::predict_skin_cost(m, 0.4, CellSize::half_list_radius);
    const double r = 2.9, h = r / 2, pi = 3.14159265358979323846;
    EXPECT_DOUBLE_EQ(p.steps_per_build, 1 + 0.4 / 0.04);
    EXPECT_NEAR(p.candidates_per_atom, 0.5 * 0.8 * 4 * pi / 3 * r * r * r, 1e-12);
    EXPECT_NEAR(p.build_tests_per_atom, 0.5 * 0.8 * 125 * h * h * h, 1e-12);
    const double build =
        2e-7 + 2e-9 * p.build_tests_per_atom + 5e-9 * 0.5 * 125 / (0.8 * h * h * h);
    EXPECT_NEAR(p.build_cost, build, 1e-20);
    EXPECT_NEAR(p.cost_per_step, build / p.steps_per_build + 2e-8 + 1.5e-9 * p.candidates_per_atom,
                1e-20);
    // A full list filters every pair's both orientations, but its build walks the half stencil.
    SkinCostModel full = m;
    full.half = false;
    const auto f = tricell::predict_skin_cost(full, 0.4, CellSize::half_list_radius);
    EXPECT_NEAR(f.candidates_per_atom, 2 * p.candidates_per_atom, 1e-12);
    EXPECT_EQ(f.build_tests_per_atom, p.build_tests_per_atom);
    EXPECT_EQ(f.build_cost, p.build_cost);
}

TEST(SkinCostModel, TunedSkinIsTheMinimum) {
    const SkinCostModel m = lj_model();
    for (const CellSize rule : {CellSize::list_radius, CellSize::cutoff, CellSize::half_list_radius,
                                CellSize::third_list_radius}) {
        SCOPED_TRACE(int(rule));
        const auto best = tricell::tune_skin(m, rule);
        EXPECT_GT(best.skin, 0);
        EXPECT_LT(best.skin, m.cutoff);
        for (int k = 0; k <= 250; ++k) {
            const double skin = m.cutoff * k / 250;
            EXPECT_LE(best.cost_per_step,
                      tricell::predict_skin_cost(m, skin, rule).cost_per_step * (1 + 1e-12));
        }
    }
    const auto overall = tricell::tune_skin(m);
    for (const CellSize rule : {CellSize::list_radius, CellSize::cutoff, CellSize::half_list_radius,
                                CellSize::third_list_radius}) {
        EXPECT_LE(overall.cost_per_step, tricell::tune_skin(m, rule).cost_per_step);
    }
    // Faster atoms want a thicker skin.
    SkinCostModel fast = m;
    fast.displacement_per_step *= 4;
    EXPECT_GT(tricell::tune_skin(fast).skin, overall.skin);
}

TEST(SkinCostModel, ClosedFormForPureCubicCosts) {
    // Only r_l^3 terms: C = r_l^3 (B / L + F) with L = 1 + skin / (2 v). The optimum solves
    // 3 F y^2 + 4 v B y - 2 v B (r_c - 2 v) = 0 with y = skin + 2 v.
    SkinCostModel m;
    m.cutoff = 2.5;
    m.density = 0.8;
    m.displacement_per_step = 0.015;
    m.build_per_test = 3e-9;
    m.refresh_per_candidate = 1e-9;
    const double pi = 3.14159265358979323846;
    const double b = 3e-9 * 0.5 * 0.8 * 27, f = 1e-9 * 0.5 * 0.8 * 4 * pi / 3;
    const double v = m.displacement_per_step, rc = m.cutoff;
    const double y =
        (-4 * v * b + std::sqrt(16 * v * v * b * b + 24 * f * v * b * (rc - 2 * v))) / (6 * f);
    EXPECT_NEAR(tricell::tune_skin(m, CellSize::list_radius).skin, y - 2 * v, 1e-6);
}

TEST(SkinCostModel, ErrorsNameTheValue) {
    SkinCostModel m = lj_model();
    m.displacement_per_step = 0;
    EXPECT_THROW_MSG(tricell::tune_skin(m), InvalidArgument,
                     "displacement_per_step must be > 0 (got 0)");
    m = lj_model();
    m.density = -1;
    EXPECT_THROW_MSG(tricell::tune_skin(m), InvalidArgument, "density must be > 0 (got -1)");
    m = lj_model();
    m.refresh_per_candidate = -2;
    EXPECT_THROW_MSG(m.validate(), InvalidArgument, "refresh_per_candidate must be >= 0 (got -2)");
    EXPECT_THROW_MSG(tricell::predict_skin_cost(lj_model(), -0.5, CellSize::cutoff),
                     InvalidArgument, "skin must be >= 0 (got -0.5)");
    EXPECT_THROW_MSG(tricell::stencil_cells(0.5), InvalidArgument,
                     "cells_per_cutoff must be in [1, 1000) (got 0.5)");
}

// ---- the md_lj example -------------------------------------------------------------------------

// Lennard-Jones forces (shifted potential) by brute force over all atom pairs and every image
// the perpendicular widths allow. Plain doubles: it also runs in unoptimised sanitizer builds.
double brute_force_lj(const Box& box, const std::vector<Eigen::Vector3d>& x, double cutoff,
                      std::vector<Eigen::Vector3d>& forces) {
    const std::size_t n = x.size();
    double h[3][3], w[3];
    for (int r = 0; r < 3; ++r) {
        w[r] = box.perpendicular_widths()[r];
        for (int c = 0; c < 3; ++c) {
            h[r][c] = box.matrix()(r, c);
        }
    }
    const double cutoff_sq = cutoff * cutoff;
    const double inv_rc6 = 1 / (cutoff_sq * cutoff_sq * cutoff_sq);
    const double energy_shift = 4 * inv_rc6 * (inv_rc6 - 1);
    std::vector<Eigen::Vector3d> s(n);
    for (std::size_t i = 0; i < n; ++i) {
        s[i] = box.inverse() * x[i];
    }
    forces.assign(n, Eigen::Vector3d::Zero());
    double potential = 0;
    for (std::size_t i = 0; i < n; ++i) {
        double f[3] = {0, 0, 0};
        for (std::size_t j = 0; j < n; ++j) {
            int lo[3], hi[3];
            double base[3];
            for (int k = 0; k < 3; ++k) {
                const double centre = s[i][k] - s[j][k], reach = cutoff / w[k] + 1e-6;
                lo[k] = int(std::ceil(centre - reach));
                hi[k] = int(std::floor(centre + reach));
                base[k] = x[j][k] - x[i][k];
            }
            for (int a = lo[0]; a <= hi[0]; ++a) {
                for (int b = lo[1]; b <= hi[1]; ++b) {
                    for (int c = lo[2]; c <= hi[2]; ++c) {
                        if (i == j && a == 0 && b == 0 && c == 0) {
                            continue;
                        }
                        double d[3], r_sq = 0;
                        for (int k = 0; k < 3; ++k) {
                            d[k] = base[k] + h[k][0] * a + h[k][1] * b + h[k][2] * c;
                            r_sq += d[k] * d[k];
                        }
                        if (r_sq >= cutoff_sq) {
                            continue;
                        }
                        const double inv_r6 = 1 / (r_sq * r_sq * r_sq);
                        potential += 0.5 * (4 * inv_r6 * (inv_r6 - 1) - energy_shift);
                        const double scale = 24 * inv_r6 * (2 * inv_r6 - 1) / r_sq;
                        for (int k = 0; k < 3; ++k) {
                            f[k] -= scale * d[k];
                        }
                    }
                }
            }
        }
        forces[i] = Eigen::Vector3d(f[0], f[1], f[2]);
    }
    return potential;
}

TEST(LjMd, ForcesEqualBruteForceAndEnergyIsConserved) {
    // 108 atoms melting from FCC at T = 1, rho = 0.8, dt = 0.005: 600 steps. Bound on the drift
    // of the total energy: |E(t) - E(0)| / N < 1e-3 at every step (the largest deviation in
    // this run is 5.1e-4, from the force jump at the cutoff of the energy-shifted potential).
    constexpr std::uint64_t seed = 3;
    SCOPED_TRACE(seed);
    md_lj::MdOptions options;
    options.skin = 0.3;
    md_lj::LjSimulation sim(md_lj::make_fcc(3, 0.8, 1.0, seed), options);
    const double n = double(sim.system().positions.size());
    const double e0 = sim.total_energy();
    double worst_drift = 0;
    std::vector<Eigen::Vector3d> expected;
    for (int step = 0; step <= 600; ++step) {
        SCOPED_TRACE(step);
        if (step > 0) {
            sim.step();
        }
        const auto& sys = sim.system();
        const double potential = brute_force_lj(sys.box, sys.positions, options.cutoff, expected);
        EXPECT_NEAR(sim.potential_energy(), potential, 1e-9 * n);
        for (std::size_t i = 0; i < expected.size(); ++i) {
            ASSERT_LT((sys.forces[i] - expected[i]).norm(), 1e-9 * (1 + expected[i].norm()))
                << "atom " << i;
        }
        worst_drift = std::max(worst_drift, std::abs(sim.total_energy() - e0) / n);
    }
    EXPECT_LT(worst_drift, 1e-3);
    // The list was reused: far fewer builds than steps, but more than one.
    EXPECT_GT(sim.builds(), 5u);
    EXPECT_LT(sim.builds(), 200u);
}

} // namespace
