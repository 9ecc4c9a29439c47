// Random neighbour-search cases for property tests, each from one explicit seed.
//
// The kinds cover what the bug trackers of other neighbour-list libraries are full of: general
// and strongly skewed triclinic boxes, tiny cells with the cutoff many times the box, widths
// between one and three cutoffs, atoms exactly on faces and corners, coincident atoms, atoms
// many box lengths outside the box, and every combination of periodic axes.
#pragma once

#include <cstdint>
#include <random>
#include <string>
#include <vector>

#include "support/random_boxes.hpp"
#include "tricell/box.hpp"

namespace tricell::testing {

struct RandomSystem {
    Eigen::Matrix3d h;
    Periodicity pbc;
    std::vector<Eigen::Vector3d> positions;
    double cutoff = 1;
    std::string kind;
    Box box() const { return Box::from_columns(h, pbc); }
};

inline RandomSystem random_system(std::uint64_t seed) {
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> unit(0, 1);
    auto uniform = [&](double lo, double hi) { return lo + (hi - lo) * unit(rng); };
    auto integer = [&](int lo, int hi) { return std::uniform_int_distribution<int>(lo, hi)(rng); };

    RandomSystem sys;
    const int kind = static_cast<int>(seed % 6);
    int n = integer(0, 3) == 0 ? integer(0, 250) : integer(0, 50);
    double skew = 0.5;
    double min_len = 3, max_len = 12;
    switch (kind) {
    case 0:
        sys.kind = "triclinic";
        break;
    case 1:
        sys.kind = "strongly skewed";
        skew = 3.0;
        break;
    case 2:
        sys.kind = "tiny cell, cutoff many boxes";
        min_len = 0.8, max_len = 3;
        n = integer(1, 8);
        break;
    case 3:
        sys.kind = "faces, corners, coincident atoms";
        skew = 0.3;
        break;
    case 4:
        sys.kind = "far outside the box";
        break;
    default:
        sys.kind = "mixed";
        skew = uniform(0, 2);
        break;
    }
    sys.h = random_box_matrix(rng, min_len, max_len, skew);
    const int bits = integer(0, 1) == 0 ? 7 : integer(0, 7);
    sys.pbc = Periodicity{{bool(bits & 1), bool(bits & 2), bool(bits & 4)}};

    const Box box = Box::from_columns(sys.h, Periodicity::all());
    const double min_width = box.perpendicular_widths().minCoeff();
    if (kind == 2) {
        sys.cutoff = uniform(1.5, 6.0) * min_width;
    } else {
        // widths between about one and three cutoffs, sometimes a cutoff beyond the box
        sys.cutoff = min_width / uniform(integer(0, 4) == 0 ? 0.3 : 1.0, 3.0);
    }

    const double special[] = {0.0, 0.5, 1.0, -1.0, 0.25, 2.0};
    for (int i = 0; i < n; ++i) {
        Eigen::Vector3d s(unit(rng), unit(rng), unit(rng));
        if (kind == 3) {
            for (int k = 0; k < 3; ++k) {
                if (integer(0, 1) == 0) {
                    s[k] = special[integer(0, 5)];
                }
            }
            if (i > 0 && integer(0, 4) == 0) { // coincident with an earlier atom
                sys.positions.push_back(sys.positions[std::size_t(integer(0, i - 1))]);
                continue;
            }
        }
        if (kind == 4 || (kind == 5 && integer(0, 3) == 0)) {
            for (int k = 0; k < 3; ++k) {
                s[k] += std::round(uniform(-1000, 1000));
            }
        }
        sys.positions.push_back(sys.h * s);
    }
    return sys;
}

} // namespace tricell::testing
