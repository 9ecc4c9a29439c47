// Random neighbour-search cases for property tests, each from one explicit seed.
//
// The kinds cover what the bug trackers of other neighbour-list libraries are full of: general
// and strongly skewed triclinic boxes, tiny cells with the cutoff many times the box, widths
// between one and three cutoffs, atoms exactly on faces and corners, coincident atoms, atoms
// many box lengths outside the box, and every combination of periodic axes.
#pragma once

#include <cmath>
#include <cstddef>
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

/// A system of the random campaign (tests/property/random_campaign_test.cpp): up to
/// `max_atoms` atoms (at least `min_atoms`, log-uniform between) in a box scaled to a random
/// density. `cutoff` comes from the density of the occupied region (a handful to a few dozen
/// neighbours per atom), tiny, or several boxes for systems small enough that the pairs stay few;
/// `neighbours` is the expected neighbours per atom.
struct CampaignSystem : RandomSystem {
    double neighbours = 0;
};

inline CampaignSystem random_campaign_system(std::uint64_t seed, std::size_t max_atoms,
                                             std::size_t min_atoms = 0) {
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> unit(0, 1);
    auto uniform = [&](double lo, double hi) { return lo + (hi - lo) * unit(rng); };
    auto integer = [&](int lo, int hi) { return std::uniform_int_distribution<int>(lo, hi)(rng); };
    std::normal_distribution<double> normal;

    CampaignSystem sys;
    // log-uniform in [min_atoms, max_atoms]: many small systems, a few large ones
    const double lo = std::log(double(std::max<std::size_t>(min_atoms, 1)));
    const double hi = std::log(double(std::max<std::size_t>(max_atoms, 1)));
    std::size_t n = std::size_t(std::exp(uniform(lo, hi)) + 0.5);
    n = std::max(min_atoms, std::min(max_atoms, n));
    const int shape = integer(0, 3); // uniform, clustered, slab, droplet
    const int cell = integer(0, 3);  // mild, skewed, strongly skewed, left-handed
    const double skew = cell == 0 ? 0.2 : cell == 1 ? 0.8 : cell == 2 ? 3.0 : 0.5;
    Eigen::Matrix3d h = random_box_matrix(rng, 1, 2.5, skew, false);
    if (cell == 3) {
        h.col(2) = -h.col(2);
    }
    const double density = uniform(0.02, 0.12);
    h *= std::cbrt(std::max<double>(double(n), 1) / density / std::abs(h.determinant()));
    sys.h = h;
    const int bits = integer(0, 2) == 0 ? integer(0, 7) : 7;
    sys.pbc = Periodicity{{bool(bits & 1), bool(bits & 2), bool(bits & 4)}};

    // Fractional positions of the occupied region; `occupied` is its share of the box.
    double occupied = 1;
    const int slab_axis = integer(0, 2);
    const double slab = uniform(0.15, 0.5);
    const double drop = uniform(0.2, 0.45); // droplet radius, fractional
    const int clusters = std::max(1, int(n / std::size_t(integer(20, 400))));
    const double sigma = uniform(0.03, 0.1);
    std::vector<Eigen::Vector3d> centres;
    switch (shape) {
    case 0:
        sys.kind = "uniform";
        break;
    case 1:
        sys.kind = "clustered";
        for (int c = 0; c < clusters; ++c) {
            centres.emplace_back(unit(rng), unit(rng), unit(rng));
        }
        occupied = std::min(1.0, clusters * 15.7 * sigma * sigma * sigma);
        break;
    case 2:
        sys.kind = "slab";
        occupied = slab;
        break;
    default:
        sys.kind = "droplet";
        occupied = 4.19 * drop * drop * drop;
        break;
    }
    sys.kind += cell == 0   ? ", mild cell"
                : cell == 1 ? ", skewed cell"
                : cell == 2 ? ", strongly skewed cell"
                            : ", left-handed cell";
    sys.kind += std::string(", periodic ") + (bits & 1 ? "a" : "-") + (bits & 2 ? "b" : "-") +
                (bits & 4 ? "c" : "-");
    const double local = density / occupied; // atoms per volume where the atoms are

    const int regime = integer(0, 9);
    const Box box = Box::from_columns(sys.h, Periodicity::all());
    const double max_width = box.perpendicular_widths().maxCoeff();
    if (regime == 0) {
        sys.kind += ", tiny cutoff";
        sys.cutoff = uniform(1e-6, 0.05) / std::cbrt(local);
    } else if (regime == 1 && n <= 30) {
        sys.kind += ", cutoff several boxes";
        sys.cutoff = uniform(1.0, 2.5) * max_width;
    } else {
        // A handful to a few dozen neighbours per atom, fewer for the largest systems.
        const double k = n > 20000 ? uniform(4, 30) : uniform(2, 60);
        sys.cutoff = std::cbrt(3 * k / (4 * 3.14159265358979 * local));
    }
    sys.neighbours = local * 4.19 * sys.cutoff * sys.cutoff * sys.cutoff;

    const double outside = integer(0, 3) == 0 ? uniform(0, 0.3) : 0; // share of far-away atoms
    const double special = integer(0, 3) == 0 ? 0.1 : 0;             // on faces, coincident
    const double faces[] = {0.0, 0.5, 1.0, -1.0};
    for (std::size_t i = 0; i < n; ++i) {
        Eigen::Vector3d s(unit(rng), unit(rng), unit(rng));
        if (shape == 1) {
            const Eigen::Vector3d& c = centres[std::size_t(integer(0, clusters - 1))];
            s = c + sigma * Eigen::Vector3d(normal(rng), normal(rng), normal(rng));
        } else if (shape == 2) {
            s[slab_axis] = 0.5 + slab * (s[slab_axis] - 0.5);
        } else if (shape == 3) {
            Eigen::Vector3d v(normal(rng), normal(rng), normal(rng));
            s = Eigen::Vector3d::Constant(0.5) + v.normalized() * drop * std::cbrt(unit(rng));
        }
        if (unit(rng) < special) {
            if (i > 0 && integer(0, 1) == 0) { // coincident with an earlier atom
                sys.positions.push_back(sys.positions[std::size_t(integer(0, int(i) - 1))]);
                continue;
            }
            s[integer(0, 2)] = faces[integer(0, 3)];
        }
        if (unit(rng) < outside) {
            // Whole boxes away; along an open axis only in small systems, since a grid over the
            // atoms' extent (capped at a few cells per atom) then holds most atoms in a few cells.
            for (int k = 0; k < 3; ++k) {
                if (sys.pbc[k] || n <= 2000) {
                    s[k] += std::round(uniform(-300, 300));
                }
            }
        }
        sys.positions.push_back(sys.h * s);
    }
    return sys;
}

} // namespace tricell::testing
