// Inputs the search fuzzer (search_fuzzer.cpp) found failing, as plain tests that every build
// runs: each case on every backend gives the brute-force oracle's pairs or a tricell::Error,
// and returns (a hang shows as the ctest timeout). The first four failed before the backend
// rewrite of the search (undefined behaviour, seconds of work for nothing); the last was the
// oracle's own mistake. The two separate tests failed on main until f538cc9.
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include <tricell/error.hpp>
#include <tricell/neighbor_list.hpp>

#include "support/brute_force.hpp"

namespace {

using tricell::Box;
using tricell::NeighborOptions;
using tricell::SearchBackend;

struct Case {
    const char* name;
    Eigen::Matrix3d h; // lattice vectors as columns
    tricell::Periodicity pbc;
    std::vector<Eigen::Vector3d> x;
    NeighborOptions options;
    double tolerance = 1e-9; // on d against the oracle's (rounding of the coordinates)
};

void expect_oracle(Case c) {
    const Box box = Box::from_columns(c.h, c.pbc);
    tricell::testing::PairMap expected =
        tricell::testing::brute_force_pairs(box, c.x, c.options.cutoff);
    if (c.options.half) {
        expected = tricell::testing::canonical_half(expected);
    }
    c.options.quantities.vectors = true;
    for (const SearchBackend backend : tricell::search_backends()) {
        SCOPED_TRACE(tricell::backend_name(backend));
        c.options.backend = backend;
        const tricell::NeighborList list = tricell::compute_neighbors(box, c.x, c.options);
        const tricell::testing::PairMap found = tricell::testing::to_map(list);
        ASSERT_EQ(found.size(), expected.size());
        for (const auto& [key, value] : expected) {
            ASSERT_EQ(found.count(key), 1u);
            EXPECT_NEAR(found.at(key).distance, value.distance, c.tolerance);
        }
    }
}

std::vector<Case> cases() {
    std::vector<Case> out;
    {
        // The pair estimate was 0 * 0 / 0 = NaN (the sphere and the open-axis thickness both
        // underflow) and was cast to size_t.
        Case c{"tiny cutoff with open axes", 0.1 * Eigen::Matrix3d::Identity(), {}, {}, {}};
        c.pbc.axes = {false, false, true};
        c.x = {{0, 0, 0}, {0, 0, 0.05}};
        c.options.cutoff = 1e-200;
        out.push_back(c);
    }
    {
        // No atoms: nothing stopped a stencil of (2 * 1000 / 5)^3 offsets.
        Case c{"no atoms, cutoff 200 box lengths",
               Eigen::Vector3d(5, 5, 5.98).asDiagonal(),
               {},
               {},
               {}};
        c.options.cutoff = 1000;
        out.push_back(c);
    }
    {
        // ~120 perpendicular widths in a skewed box searched without reduction took 10-30 s.
        Case c{"skewed unreduced box, cutoff of many widths", Eigen::Matrix3d::Zero(), {}, {}, {}};
        c.h << 5, 15, 0, 0, 1, 0, 0, 0, 10;
        c.x = {{0, 0, 0}, {0, 0, 0}};
        c.options.cutoff = 40.36;
        c.options.half = true;
        c.options.reduce_cell = false;
        out.push_back(c);
    }
    {
        // Coincident atoms are neighbours at d = 0 < 1e-300 (the oracle squared the cutoff).
        Case c{"coincident atoms, tiny cutoff",
               Eigen::Vector3d(5, 5, 0.7).asDiagonal(),
               {},
               std::vector<Eigen::Vector3d>(3, Eigen::Vector3d::Zero()),
               {}};
        c.options.cutoff = 1e-300;
        out.push_back(c);
    }
    return out;
}

// The search radius, the cutoff plus a rounding margin, overflowed to inf for a finite cutoff
// near the largest double: the grid backends refused it, the direct and octree backends
// accepted it. In an open box every pair counts.
TEST(SearchRegressions, LargestFiniteCutoffInAnOpenBox) {
    Case c{"cutoff near the largest double", 5 * Eigen::Matrix3d::Identity(), {}, {}, {}};
    c.pbc.axes = {false, false, false};
    c.x = {{0, 1.445499193939207e-07, 0.31249999999998568},
           {0, 0, 2.7381881326162194},
           {0, -5.0000000000000005e-17, 0}};
    c.options.cutoff = 1.7976931348609993e+308;
    c.options.sorted = true;
    expect_oracle(c);
}

// The direct backend's interval of c images lay wholly above [-m, m] (c nearly orthogonal to a
// long row), and its lower end, clamped on one side only, was cast to int from 7e11 (UBSan).
TEST(SearchRegressions, DirectImageIntervalAboveItsRange) {
    Eigen::Matrix3d h;
    h << -4.25, -1e-12, -1e-12, -1e-12, -1e-12, -1e-12, -1e-12, 1, -1e-12;
    Case c{"c-image interval above [-m, m]", h, {}, {}, {}};
    c.pbc.axes = {true, false, false};
    const Eigen::Vector3d a(-0.58333333333447346, -1.27734375e-12, 0.14008884803807842);
    c.x = {a, a, a, a, a, {-4.2499999999999991, -9.9999999999999978e-13, -9.9999999999999978e-13},
           a, a};
    c.options.cutoff = 1e-300;
    c.options.threads = 2;
    c.options.reduce_cell = true;
    expect_oracle(c);
}

// Coincident atoms near the largest double along an open axis: their Cartesian spread in the
// direct backend was inf - inf = NaN, and the NaN image count was refused where every other
// backend answered.
TEST(SearchRegressions, DirectSpreadOfHugeCoordinatesIsNotNaN) {
    Eigen::Matrix3d h;
    h << 5, 5, 5, 0, 5, 5, 0, 0, 0.7973541784932775;
    Case c{"coordinates near the largest double", h, {}, {}, {}};
    c.pbc.axes = {true, false, false};
    c.x.assign(6, Eigen::Vector3d(-10.706230845080926, -1e-12, 9.9715791068690752e+307));
    c.options.cutoff = 1e-300;
    expect_oracle(c);
}

// A denormal extent along an open axis made the automatic choice's cell scale inf, and an atom
// at the extent's origin got cell NaN, cast to an integer (UBSan).
TEST(SearchRegressions, OpenSpanThatOverflowsPutsEveryAtomInOneCell) {
    // Fractional coordinates about 1.5e308 apart on open axes: the span of the grid overflowed
    // to inf, its cell size with it, and an atom at an infinite distance from the grid's origin
    // was at inf * 0 = NaN cells, cast to int (undefined; seen under UBSan).
    Eigen::Matrix3d h;
    h << 4.5990795321831959, 38.465817681281656, 0, -1.3577722925005249, -7.5938578850253844,
        7.6211316803418523, 1.4159526328134955, 7.9192535632841103, 7.307985587416967;
    Case c{"open span past the largest double", h, {}, {}, {}};
    c.pbc.axes = {false, false, false};
    c.x = {{19.843137254874705, -1.520541218865301e+308, 1},
           {0, 0, -2.6085842803901214e+307},
           {-109.35155438551985, -1.520541218865301e+308, -48.929575350543722},
           {19.843137254874705, -1.520541218865301e+308, 1}};
    c.options.cutoff = 1e-300;
    expect_oracle(c);
}

TEST(SearchRegressions, OpenThicknessThatOverflowsGivesTheCellsTheCutoffAsksFor) {
    // Coordinates near the largest double on open axes and a cutoff of 1.43e308: the fractional
    // span times the width overflowed to inf, so the uncapped hash grid took 2^20 cells along a,
    // and its stencil reached 2^20 - 1 of them (ten million offsets, seconds for five atoms).
    Eigen::Matrix3d h;
    h << 1.4914716966093655, 6.2638413572929528, 6.2638413572929528, 3.9230834053831449,
        2.6970325588255601, 8.3913159785590103, 2.7175225431669503, 1.8682362878665073,
        -6.3521734547040385;
    Case c{"open thickness past the largest double", h, {}, {}, {}};
    c.pbc.axes = {false, false, false};
    c.x = {{1.4311047308903924e+308, 1.4311047308903924e+308, 1.4311047308903924e+308},
           {1.4311047308903924e+308, 1.4311047308903924e+308, 1.431084501432212e+308},
           {1.7916309677670916e+308, 4.9406564584124654e-324, -3.3703116638213762e+298},
           {3.4303152138260473, 4.5954003659046281, -3.4786891939980742},
           {-6.2638413572929528e-17, -2.6970325588255602e-17, -1.8682362878665076e-17}};
    c.options.cutoff = 1.4311047308969323e+308;
    c.options.half = true;
    c.options.cells_per_cutoff = 3;
    expect_oracle(c);
    NeighborOptions options = c.options;
    options.backend = SearchBackend::hash;
    tricell::NeighborSearch search;
    search.build(Box::from_columns(c.h, c.pbc), c.x, options);
    for (const int cells : search.info().cells) {
        EXPECT_LE(cells, 16);
    }
}

TEST(SearchRegressions, ReducedFrameRefusesWhatTheCallerFrameRefuses) {
    // b = 333 a + (0, 1, 0): the search runs in the reduced frame a, b - 333 a, where an atom
    // 3.4e7 lengths along y is 3.4e7 box lengths away, but in the caller's box it is 1.1e10 box
    // lengths along a, past Box::max_fractional. The reduced search took it, and mapping its
    // shifts to the caller's frame overflowed an int (-333 * 33333334; c_api_fuzzer, UBSan).
    // Refused now, with the caller's box's message, whether the cell is reduced or not.
    Eigen::Matrix3d h;
    h << 1, 333, 0, 0, 1, 0, 0, 0, 1;
    const Box box = Box::from_columns(h, tricell::Periodicity{});
    const std::vector<Eigen::Vector3d> x = {{0, 0, 0}, {0.25, 3.4e7, 0}};
    NeighborOptions options;
    options.cutoff = 0.5;
    options.quantities.shifts = true;
    std::string unreduced;
    options.reduce_cell = false;
    try {
        tricell::compute_neighbors(box, x, options);
    } catch (const tricell::InvalidArgument& e) {
        unreduced = e.what();
    }
    ASSERT_FALSE(unreduced.empty());
    options.reduce_cell = true;
    for (const SearchBackend backend : tricell::search_backends()) {
        SCOPED_TRACE(tricell::backend_name(backend));
        options.backend = backend;
        try {
            tricell::compute_neighbors(box, x, options);
            ADD_FAILURE() << "accepted a position 1.1e10 caller box lengths away";
        } catch (const tricell::InvalidArgument& e) {
            EXPECT_EQ(std::string(e.what()), unreduced);
        }
    }
}

TEST(SearchRegressions, ReducedFrameShiftsAreMappedWithoutOverflow) {
    // An atom 999 999 999 box lengths along a (within Box::max_fractional) in a box the search
    // reduces: its shifts in the reduced frame mapped to the caller's as T S' with a product
    // 6 * 999999999 past an int, though the sum fits (search_fuzzer, UBSan). Mapped in 64 bits.
    Eigen::Matrix3d h;
    h << 5, 5, 25.470873303711414, 0, 5, 0, 0, 0, 2;
    Case c{"reduced frame, far atom", h, {}, {}, {}};
    c.pbc.axes = {true, false, true};
    c.x = {{4999999995, -5.0000000000000005e-17, -2.0000000000000001e-17}, {0, 0, 0}};
    c.options.cutoff = 27.436570245818242;
    c.options.half = true;
    c.options.sorted = true;
    c.options.cells_per_cutoff = 1.5;
    c.tolerance = 1e-6; // the far atom's coordinate 5e9 is known to 1e-6
    expect_oracle(c);
}

TEST(SearchRegressions, AutomaticChoiceWithADenormalOpenExtent) {
    Eigen::Matrix3d h;
    h << 5, 0, 0, 0, 5, 0, 0, 0, 1;
    Case c{"denormal extent on an open axis", h, {}, {}, {}};
    c.pbc.axes = {true, true, false};
    c.x = {{5.0000000000000005e-17, 0, 0},
           {4.9406564584124654e-324, 10, 4.9406564584124654e-324},
           {19.999466007575393, -15, 0}};
    c.options.cutoff = 1e-300;
    expect_oracle(c);
}

TEST(SearchRegressions, FuzzerFindsAgreeWithTheOracleOnEveryBackend) {
    for (const Case& c : cases()) {
        SCOPED_TRACE(c.name);
        expect_oracle(c);
    }
}

// The grid grew its cell size by 1.1 until the cells fit, and for a denormal cutoff 1.1 h
// rounded back to h, so build() never returned (still so after the backend rewrite).
TEST(SearchRegressions, DenormalCutoffReturns) {
    Case c{"denormal cutoff", Eigen::Matrix3d::Identity(), {}, {{0.5, 0.5, 0.5}}, {}};
    c.options.cutoff = 4.9406564584124654e-324;
    expect_oracle(c);
}

// In an open box a cutoff whose cube underflows made the pair estimate 0 * 0 / 0 = NaN, which
// compute() cast to size_t (undefined behaviour, caught by UBSan; 2^63 as a reserve hint
// without it).
TEST(SearchRegressions, TinyCutoffInAnOpenBoxHasAFiniteEstimate) {
    Case c{"tiny cutoff, open box", Eigen::Matrix3d::Zero(), tricell::Periodicity::none(), {}, {}};
    c.h << 5, 0, 2.5, 0, 5, 0, 0, 0, 5;
    c.x = {{2, 5.4117635591436155, 1e-300}, {0, 0, 0}, {2, 5.4117635591436155, 1e-300}};
    c.options.cutoff = 1e-300;
    expect_oracle(c);
}

// A denormal cutoff over cells_per_cutoff 2 underflowed the cell size to 0, and the open axis a
// of zero thickness then had 0 / 0 = NaN cells, cast to int (undefined behaviour, caught by
// UBSan); grid.cpp's cells_along now gives such an axis one cell.
TEST(SearchRegressions, DenormalCutoffWithFinerCellsAndAFlatOpenAxis) {
    Case c{"denormal cutoff, 2 cells per cutoff",
           Eigen::Vector3d(5, 5, 0.7).asDiagonal(),
           {},
           std::vector<Eigen::Vector3d>(2, Eigen::Vector3d::Zero()),
           {}};
    c.pbc.axes = {false, true, true};
    c.options.cutoff = 4.9406564584124654e-324;
    c.options.cells_per_cutoff = 2;
    c.options.half = true;
    expect_oracle(c);
}

} // namespace
