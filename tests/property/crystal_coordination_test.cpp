// Perfect crystals have exact coordination numbers: FCC, BCC, HCP and diamond supercells,
// also in tilted boxes (tilt exactly 1/2 of the box edge) and in one-atom primitive cells with
// the cutoff beyond the box. Each atom must see exactly the textbook shells.
#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include "tricell/neighbor_list.hpp"

using tricell::Box;

namespace {

struct Crystal {
    Eigen::Matrix3d lattice;            // columns: primitive or conventional vectors
    std::vector<Eigen::Vector3d> basis; // fractional in `lattice`
};

Crystal fcc() {
    return {Eigen::Matrix3d::Identity(), {{0, 0, 0}, {0, .5, .5}, {.5, 0, .5}, {.5, .5, 0}}};
}
Crystal bcc() {
    return {Eigen::Matrix3d::Identity(), {{0, 0, 0}, {.5, .5, .5}}};
}
Crystal diamond() {
    Crystal c = fcc();
    const std::size_t n = c.basis.size();
    for (std::size_t k = 0; k < n; ++k) {
        c.basis.push_back(c.basis[k] + Eigen::Vector3d(.25, .25, .25));
    }
    return c;
}
Crystal hcp() { // a = 1, ideal c/a
    Eigen::Matrix3d lattice;
    const double c = std::sqrt(8.0 / 3.0);
    lattice << 1, -0.5, 0,        //
        0, std::sqrt(3.0) / 2, 0, //
        0, 0, c;
    return {lattice, {{1.0 / 3, 2.0 / 3, 0.25}, {2.0 / 3, 1.0 / 3, 0.75}}};
}

// All crystal sites inside the supercell `box` (which must be spanned by lattice vectors).
std::vector<Eigen::Vector3d> fill(const Crystal& crystal, const Box& box) {
    std::vector<Eigen::Vector3d> sites;
    const int reach = 12;
    for (int a = -reach; a <= reach; ++a) {
        for (int b = -reach; b <= reach; ++b) {
            for (int c = -reach; c <= reach; ++c) {
                for (const Eigen::Vector3d& f : crystal.basis) {
                    const Eigen::Vector3d r = crystal.lattice * (f + Eigen::Vector3d(a, b, c));
                    const Eigen::Vector3d s = box.inverse() * r;
                    if ((s.array() >= -1e-9).all() && (s.array() < 1 - 1e-9).all()) {
                        sites.push_back(r);
                    }
                }
            }
        }
    }
    return sites;
}

std::vector<int> coordination(const Box& box, const std::vector<Eigen::Vector3d>& x, double cutoff,
                              bool half) {
    tricell::NeighborOptions o;
    o.cutoff = cutoff;
    o.half = half;
    const tricell::NeighborList list = tricell::compute_neighbors(box, x, o);
    std::vector<int> count(x.size(), 0);
    for (std::size_t k = 0; k < list.size(); ++k) {
        ++count[list.i()[k]];
        if (half) {
            ++count[list.j()[k]];
        }
    }
    return count;
}

void expect_uniform_coordination(const Crystal& crystal, const Box& box, double cutoff,
                                 int expected, std::size_t expected_atoms) {
    const std::vector<Eigen::Vector3d> x = fill(crystal, box);
    ASSERT_EQ(x.size(), expected_atoms);
    for (const bool half : {false, true}) {
        SCOPED_TRACE(half ? "half" : "full");
        const std::vector<int> count = coordination(box, x, cutoff, half);
        for (std::size_t i = 0; i < count.size(); ++i) {
            ASSERT_EQ(count[i], expected) << "atom " << i;
        }
    }
}

Box supercell(int n, double tilt_xy = 0, double tilt_xz = 0, double tilt_yz = 0) {
    return Box::from_lammps(n, n, n, tilt_xy * n, tilt_xz * n, tilt_yz * n);
}

} // namespace

TEST(CrystalCoordination, FccShells) {
    for (const double tilt : {0.0, 0.5}) {
        SCOPED_TRACE(tilt);
        const Box box = supercell(2, tilt, tilt, tilt);
        expect_uniform_coordination(fcc(), box, 0.8, 12, 32); // nn 1/sqrt(2)
        expect_uniform_coordination(fcc(), box, 1.1, 18, 32); // + 6 at 1
        expect_uniform_coordination(fcc(), box, 1.3, 42, 32); // + 24 at sqrt(3/2)
    }
}

TEST(CrystalCoordination, BccShells) {
    for (const double tilt : {0.0, 0.5}) {
        SCOPED_TRACE(tilt);
        const Box box = supercell(2, tilt, 0, tilt);
        expect_uniform_coordination(bcc(), box, 0.9, 8, 16);  // nn sqrt(3)/2
        expect_uniform_coordination(bcc(), box, 1.2, 14, 16); // + 6 at 1
        expect_uniform_coordination(bcc(), box, 1.5, 26, 16); // + 12 at sqrt(2)
    }
}

TEST(CrystalCoordination, DiamondShells) {
    for (const double tilt : {0.0, 0.5}) {
        SCOPED_TRACE(tilt);
        const Box box = supercell(2, 0, tilt, tilt);
        expect_uniform_coordination(diamond(), box, 0.5, 4, 64);  // nn sqrt(3)/4
        expect_uniform_coordination(diamond(), box, 0.8, 16, 64); // + 12 at 1/sqrt(2)
    }
}

TEST(CrystalCoordination, HcpShells) {
    const Crystal crystal = hcp();
    // 3 x 3 x 2 supercell of the hexagonal cell, and a tilted one (c tilted by a/2... exactly
    // half of the 3a edge is not a lattice vector, so tilt c by a full a, 1/3 of the edge).
    Eigen::Matrix3d h = crystal.lattice;
    h.col(0) *= 3;
    h.col(1) *= 3;
    h.col(2) *= 2;
    expect_uniform_coordination(crystal, Box::from_columns(h), 1.1, 12, 36);
    h.col(2) += crystal.lattice.col(0);
    expect_uniform_coordination(crystal, Box::from_columns(h), 1.1, 12, 36);
    // Second shell: 6 at sqrt(2) (for ideal c/a: 6 at sqrt(2), 2 at sqrt(8/3)).
    expect_uniform_coordination(crystal, Box::from_columns(h), 1.5, 18, 36);
}

TEST(CrystalCoordination, OneAtomPrimitiveCellWithCutoffBeyondTheBox) {
    // Primitive FCC: one atom, every neighbour is the atom's own image.
    Eigen::Matrix3d h;
    h << 0, .5, .5, //
        .5, 0, .5,  //
        .5, .5, 0;
    const Box box = Box::from_columns(h);
    const std::vector<Eigen::Vector3d> one{{0.1, 0.2, 0.3}};
    EXPECT_EQ(coordination(box, one, 0.8, false)[0], 12);
    EXPECT_EQ(coordination(box, one, 1.1, false)[0], 18);
    EXPECT_EQ(coordination(box, one, 1.3, false)[0], 42);
    EXPECT_EQ(coordination(box, one, 1.3, true)[0], 42);
    // FCC shells up to r^2 = 4 (in units of a^2/2: 12, 6, 24, 12, 24, 8, 48, 6): 140 neighbours.
    EXPECT_EQ(coordination(box, one, std::sqrt(4.0) + 1e-6, false)[0], 140);
}

TEST(CrystalCoordination, TwoAtomPrimitiveDiamondWithCutoffBeyondTheBox) {
    Eigen::Matrix3d h;
    h << 0, .5, .5, //
        .5, 0, .5,  //
        .5, .5, 0;
    const Box box = Box::from_columns(h);
    const std::vector<Eigen::Vector3d> two{{0, 0, 0}, {.25, .25, .25}};
    for (const int count : coordination(box, two, 0.5, false)) {
        EXPECT_EQ(count, 4);
    }
    for (const int count : coordination(box, two, 0.8, true)) {
        EXPECT_EQ(count, 16);
    }
}
