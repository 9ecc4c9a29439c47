#include <gtest/gtest.h>

#include "support/expect_throw_msg.hpp"
#include "tricell/error.hpp"
#include "tricell/grid.hpp"

using tricell::Box;
using tricell::CellGrid;
using tricell::GridOptions;

namespace {
GridOptions options(double radius, double k, std::size_t max_cells) {
    GridOptions o;
    o.search_radius = radius;
    o.cells_per_cutoff = k;
    o.max_cells = max_cells;
    return o;
}
const Eigen::Vector3d zero = Eigen::Vector3d::Zero();
} // namespace

TEST(FloorDiv, MatchesMathematicalFloorForNegatives) {
    for (int n = 1; n <= 5; ++n) {
        for (int a = -23; a <= 23; ++a) {
            const int q = tricell::floor_div(a, n);
            const int r = tricell::floor_mod(a, n);
            EXPECT_EQ(q * n + r, a);
            EXPECT_GE(r, 0);
            EXPECT_LT(r, n);
            EXPECT_EQ(q, static_cast<int>(std::floor(double(a) / n)));
        }
    }
}

TEST(CellGrid, CellsFollowPerpendicularWidthsNotEdgeLengths) {
    // Edge b is long (sheared) but the width across b is only 10.
    const Box box = Box::from_lammps(10, 10, 10, 30, 0, 0);
    const CellGrid grid(box, options(2.5, 1, 1000), zero, zero);
    EXPECT_EQ(grid.dims()[0], 1); // width across a: 10 / sqrt(1 + 3^2) = 3.16, edge 10
    EXPECT_EQ(grid.dims()[1], 4);
    EXPECT_EQ(grid.dims()[2], 4);
    for (int k = 0; k < 3; ++k) {
        const double cell_thickness = box.perpendicular_widths()[k] / grid.dims()[std::size_t(k)];
        EXPECT_GE(cell_thickness, 2.5);
        EXPECT_EQ(grid.reach()[std::size_t(k)], 1);
    }
}

TEST(CellGrid, ReachCoversCutoffLargerThanBox) {
    const Box box = Box::from_parameters(2, 2, 2, 90, 90, 90);
    const CellGrid grid(box, options(7.0, 2, 1000), zero, zero);
    EXPECT_EQ(grid.dims(), (std::array<int, 3>{{1, 1, 1}}));
    EXPECT_EQ(grid.reach(), (std::array<int, 3>{{4, 4, 4}})); // ceil(7 / 2)
}

TEST(CellGrid, CapKeepsCellsProportionalToAtomsInDiluteBox) {
    const Box box = Box::from_parameters(1e4, 1e4, 1e4, 90, 90, 90);
    const CellGrid grid(box, options(1.0, 2, 100), zero, zero);
    EXPECT_TRUE(grid.capped());
    EXPECT_LE(grid.cell_count(), 100u);
    EXPECT_GE(grid.cell_count(), 27u);
}

TEST(CellGrid, OpenAxisSpansThePositions) {
    const Box box = Box::from_parameters(10, 10, 10, 90, 90, 90, {{true, true, false}});
    const CellGrid grid(box, options(2.0, 1, 10000), Eigen::Vector3d(0, 0, -3.0),
                        Eigen::Vector3d(0, 0, 5.0));
    EXPECT_EQ(grid.dims()[2], 40); // 8 box lengths of 10 / 2
    EXPECT_DOUBLE_EQ(grid.origin()[2], -3.0);
    EXPECT_EQ(grid.coordinate(2, -3.0), 0);
    EXPECT_EQ(grid.coordinate(2, 5.0), 39); // clamped at the upper edge
    EXPECT_EQ(grid.reach()[2], 1);
}

TEST(CellGrid, OpenAxisWithAllAtomsInOnePlaneHasOneCell) {
    const Box box = Box::from_parameters(10, 10, 10, 90, 90, 90, tricell::Periodicity::none());
    const CellGrid grid(box, options(2.0, 1, 10000), Eigen::Vector3d(0.1, 0.2, 0.5),
                        Eigen::Vector3d(0.3, 0.2, 0.5));
    EXPECT_EQ(grid.dims()[1], 1);
    EXPECT_EQ(grid.dims()[2], 1);
    EXPECT_EQ(grid.reach()[1], 0);
}

TEST(CellGrid, CoordinateClampsRoundingAtTheUpperEdge) {
    const Box box = Box::from_parameters(9, 9, 9, 90, 90, 90);
    const CellGrid grid(box, options(3.0, 1, 1000), zero, zero);
    EXPECT_EQ(grid.coordinate(0, std::nextafter(1.0, 0.0)), 2);
    EXPECT_EQ(grid.coordinate(0, 0.0), 0);
}

TEST(CellGrid, RejectsBadOptions) {
    const Box box = Box::from_parameters(9, 9, 9, 90, 90, 90);
    EXPECT_THROW_MSG(CellGrid(box, options(0.0, 1, 10), zero, zero), tricell::InvalidArgument,
                     "search radius must be > 0 (got 0)");
    EXPECT_THROW_MSG(CellGrid(box, options(1.0, 0.5, 10), zero, zero), tricell::InvalidArgument,
                     "cells per cutoff must be >= 1 (got 0.5)");
    EXPECT_THROW_MSG(CellGrid(box, options(1.0, 1, 0), zero, zero), tricell::InvalidArgument,
                     "max_cells must be >= 1 (got 0)");
    EXPECT_THROW_MSG(CellGrid(box, options(1e9, 1, 10), zero, zero), tricell::InvalidArgument,
                     "spans more than a million cells");
}
