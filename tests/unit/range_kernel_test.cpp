#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "scan/distance_kernel.hpp"
#include "scan/range_kernel.hpp"

using tricell::detail::CandidateRange;
using tricell::detail::kernel_slack;
using tricell::detail::PairSlots;
using tricell::detail::range_kernels;
using tricell::detail::RangeScanInput;

namespace {

// One random scan: atoms in a small box, ranges of them through random shifts (a zero shift
// over the home atoms on some), a full or half list, images or none, and some columns left out.
struct Case {
    std::vector<double> x, y, z;
    std::vector<std::uint32_t> index;
    std::vector<std::int32_t> image;
    std::vector<CandidateRange> ranges;
    RangeScanInput in{};
    std::uint32_t a0 = 0, a1 = 0, candidates = 0;
    bool shifts = true, distances = true, vectors = true, squares = false;
};

Case random_case(std::mt19937_64& rng, int trial) {
    std::uniform_real_distribution<double> u(-2, 2);
    Case c;
    const std::uint32_t atoms = 1 + std::uint32_t(rng() % 40);
    for (std::uint32_t k = 0; k < atoms; ++k) {
        c.x.push_back(u(rng)), c.y.push_back(u(rng)), c.z.push_back(u(rng));
        c.index.push_back(k);
        for (int axis = 0; axis < 3; ++axis) {
            c.image.push_back(std::int32_t(rng() % 5) - 2);
        }
    }
    // The caller's indices, shuffled (each atom once: i == j only for an atom's own image).
    std::shuffle(c.index.begin(), c.index.end(), rng);
    c.a0 = std::uint32_t(rng() % atoms);
    c.a1 = c.a0 + 1 + std::uint32_t(rng() % std::min<std::uint32_t>(8, atoms - c.a0));
    const std::uint32_t count = std::uint32_t(rng() % 6);
    for (std::uint32_t q = 0; q < count; ++q) {
        CandidateRange r{};
        r.own = q == 0 && trial % 2 == 0;
        if (r.own) {
            // the home cell: its atoms from a0, at least up to a1
            r.b0 = c.a0, r.b1 = std::uint32_t(c.a1 + rng() % (atoms - c.a1 + 1));
        } else {
            r.b0 = std::uint32_t(rng() % atoms);
            r.b1 = r.b0 + std::uint32_t(rng() % (atoms - r.b0 + 1));
        }
        for (int axis = 0; axis < 3; ++axis) {
            r.s[axis] = r.own ? 0 : std::int32_t(rng() % 3) - 1;
            r.v[axis] = r.own ? 0.0 : 1.7 * r.s[axis] + 0.3 * u(rng);
        }
        r.self_turn = rng() % 2 == 0;
        c.candidates += (c.a1 - c.a0) * (r.b1 - r.b0);
        c.ranges.push_back(r);
    }
    // A candidate exactly at the cutoff (not a pair) and one exactly on an atom.
    if (atoms > 2) {
        c.x[atoms - 1] = c.x[c.a0] + 1.5, c.y[atoms - 1] = c.y[c.a0], c.z[atoms - 1] = c.z[c.a0];
        c.x[atoms - 2] = c.x[c.a0], c.y[atoms - 2] = c.y[c.a0], c.z[atoms - 2] = c.z[c.a0];
    }
    c.in.x = c.x.data(), c.in.y = c.y.data(), c.in.z = c.z.data();
    c.in.index = c.index.data(), c.in.image = c.image.data();
    c.in.zero_images = trial % 3 == 0;
    c.in.cutoff_sq = 2.25;
    c.in.half_stencil = trial % 4 >= 2;
    c.in.orient =
        c.in.half_stencil && trial % 8 != 2; // a mirrored full list's half stencil otherwise
    c.shifts = trial % 5 != 1, c.distances = trial % 7 != 2, c.vectors = trial % 3 != 2;
    c.squares = trial % 11 == 3;
    return c;
}

// The columns one kernel writes for a case.
struct Columns {
    std::vector<std::uint32_t> i, j;
    std::vector<std::int32_t> s;
    std::vector<double> d, v;
    std::uint32_t n = 0;
};

Columns run(tricell::detail::RangeKernel scan, const Case& c, std::uint64_t* tested = nullptr) {
    Columns out;
    const std::size_t room = c.candidates + kernel_slack;
    out.i.resize(room), out.j.resize(room), out.s.resize(3 * room), out.d.resize(room);
    out.v.resize(3 * room);
    const PairSlots slots{out.i.data(),
                          out.j.data(),
                          c.shifts ? out.s.data() : nullptr,
                          c.distances ? out.d.data() : nullptr,
                          c.vectors ? out.v.data() : nullptr,
                          c.squares};
    std::uint64_t count = 0;
    out.n = scan(c.in, c.a0, c.a1, c.ranges.data(), std::uint32_t(c.ranges.size()), slots, count);
    if (tested != nullptr) {
        *tested += count;
    }
    return out;
}

// The candidates of a case without boxes: every atom against every range, in the own range of a
// half stencil only b > a.
std::uint64_t whole_candidates(const Case& c) {
    std::uint64_t whole = 0;
    for (const CandidateRange& r : c.ranges) {
        for (std::uint32_t a = c.a0; a < c.a1; ++a) {
            const std::uint32_t first = r.own && c.in.half_stencil ? std::max(r.b0, a + 1) : r.b0;
            whole += r.b1 > first ? r.b1 - first : 0;
        }
    }
    return whole;
}

// Whether two runs wrote the same pairs in the same order with the same bits.
void expect_same(const Case& c, const Columns& got, const Columns& expected) {
    ASSERT_EQ(got.n, expected.n);
    for (std::uint32_t p = 0; p < got.n; ++p) {
        ASSERT_EQ(got.i[p], expected.i[p]) << p;
        ASSERT_EQ(got.j[p], expected.j[p]) << p;
        for (int k = 0; k < 3; ++k) {
            if (c.shifts) {
                ASSERT_EQ(got.s[3 * p + k], expected.s[3 * p + k]) << p;
            }
            if (c.vectors) {
                // bit for bit, +0 and -0 told apart
                ASSERT_EQ(std::signbit(got.v[3 * p + k]), std::signbit(expected.v[3 * p + k]));
                ASSERT_EQ(got.v[3 * p + k], expected.v[3 * p + k]) << p;
            }
        }
        if (c.distances) {
            ASSERT_EQ(got.d[p], expected.d[p]) << p;
        }
    }
}

// A scan of cells with their bounding boxes: cells along x (some empty, each cell's atoms
// within half a unit of its centre, on a grid of 1/8 in some trials so that distances fall
// exactly on the cutoff and boxes exactly at its reach), a home cell's atoms against ranges of
// consecutive cells through skewed translations (as a triclinic cell's), more ranges than the
// kernel prunes in some trials.
struct CellCase {
    Case c;
    std::vector<double> boxes;
    std::vector<std::uint32_t> starts;
};

CellCase random_cell_case(std::mt19937_64& rng, int trial) {
    std::uniform_real_distribution<double> u(-0.5, 0.5);
    CellCase cc;
    Case& c = cc.c;
    const std::uint32_t cells = 1 + std::uint32_t(rng() % 12);
    const bool grid = trial % 3 == 0;
    cc.starts.push_back(0);
    for (std::uint32_t k = 0; k < cells; ++k) {
        // up to 11 atoms: enough that the kernel finds the boxes worth testing in most calls
        const std::uint32_t count = std::uint32_t(rng() % 12);
        for (std::uint32_t m = 0; m < count; ++m) {
            double p[3] = {double(k) + u(rng), u(rng), u(rng)};
            for (double& v : p) {
                v = grid ? std::round(8 * v) / 8 : v;
            }
            c.x.push_back(p[0]), c.y.push_back(p[1]), c.z.push_back(p[2]);
            for (int axis = 0; axis < 3; ++axis) {
                c.image.push_back(std::int32_t(rng() % 5) - 2);
            }
        }
        cc.starts.push_back(std::uint32_t(c.x.size()));
    }
    const auto atoms = std::uint32_t(c.x.size());
    for (std::uint32_t k = 0; k < atoms; ++k) {
        c.index.push_back(k);
    }
    std::shuffle(c.index.begin(), c.index.end(), rng);
    double bound = 0;
    for (std::uint32_t k = 0; k < cells; ++k) {
        const double inf = std::numeric_limits<double>::infinity();
        double lo[3] = {inf, inf, inf}, hi[3] = {-inf, -inf, -inf};
        for (std::uint32_t a = cc.starts[k]; a < cc.starts[k + 1]; ++a) {
            const double p[3] = {c.x[a], c.y[a], c.z[a]};
            for (int axis = 0; axis < 3; ++axis) {
                lo[axis] = std::min(lo[axis], p[axis]), hi[axis] = std::max(hi[axis], p[axis]);
                bound = std::max(bound, std::abs(p[axis]));
            }
        }
        cc.boxes.insert(cc.boxes.end(), {lo[0], lo[1], lo[2], hi[0], hi[1], hi[2]});
    }
    // the home cell: a non-empty one (none: no atoms, no ranges)
    std::uint32_t home = std::uint32_t(rng() % cells);
    for (std::uint32_t k = 0; k < cells && cc.starts[home] == cc.starts[home + 1]; ++k) {
        home = (home + 1) % cells;
    }
    c.in.cutoff_sq = 2.25;
    c.in.zero_images = trial % 5 == 0;
    c.in.half_stencil = trial % 4 >= 2;
    c.in.orient =
        c.in.half_stencil && trial % 8 != 2; // a mirrored full list's half stencil otherwise
    c.shifts = trial % 5 != 1, c.distances = trial % 7 != 2, c.vectors = trial % 3 != 2;
    c.squares = trial % 11 == 3;
    if (atoms == 0) {
        return cc;
    }
    c.a0 = cc.starts[home] + std::uint32_t(rng() % (cc.starts[home + 1] - cc.starts[home]));
    c.a1 = std::min(cc.starts[home + 1], c.a0 + 1 + std::uint32_t(rng() % 8));
    const std::uint32_t count = trial % 17 == 0 ? 70 : std::uint32_t(rng() % 7);
    for (std::uint32_t q = 0; q < count; ++q) {
        CandidateRange r{};
        r.own = q == 0 && trial % 2 == 0;
        if (r.own) {
            r.c0 = home - std::uint32_t(rng() % (home + 1));
            r.c1 = home + std::uint32_t(rng() % (cells - home));
        } else {
            r.c0 = std::uint32_t(rng() % cells);
            r.c1 = r.c0 + std::uint32_t(rng() % (cells - r.c0));
        }
        r.b0 = cc.starts[r.c0], r.b1 = cc.starts[r.c1 + 1];
        for (int axis = 0; axis < 3; ++axis) {
            r.s[axis] = r.own ? 0 : std::int32_t(rng() % 3) - 1;
        }
        if (!r.own) {
            // a skewed lattice: H = (cells, 0, 0; 0.6, 2, 0; -0.7, 0.4, 2.5) by columns
            r.v[0] = double(cells) * r.s[0] + 0.6 * r.s[1] - 0.7 * r.s[2];
            r.v[1] = 2.0 * r.s[1] + 0.4 * r.s[2];
            r.v[2] = 2.5 * r.s[2];
        }
        r.self_turn = rng() % 2 == 0;
        r.reach_sq = tricell::detail::cell_reach_sq(1.5, bound, r.v);
        c.candidates += (c.a1 - c.a0) * (r.b1 - r.b0);
        c.ranges.push_back(r);
    }
    c.in.x = c.x.data(), c.in.y = c.y.data(), c.in.z = c.z.data();
    c.in.index = c.index.data(), c.in.image = c.image.data();
    return cc;
}

} // namespace

// Every range kernel this processor can run (AVX-512, AVX2, the portable one) writes the same
// pairs in the same order with the same bits as the portable one, for any mix of ranges, own
// ranges, images, half lists (oriented, or the unoriented half stencil of a mirrored full list)
// and stored columns; and the portable one finds exactly the candidates with d^2 < cutoff^2, one
// pair each, in the canonical orientation of a half list and as found otherwise.
TEST(RangeKernel, EveryVersionMatchesThePortableOneBitForBit) {
    const auto versions = range_kernels();
    ASSERT_EQ(std::string(versions.back().name), "generic");
    std::mt19937_64 rng(41);
    for (int trial = 0; trial < 4000; ++trial) {
        SCOPED_TRACE(trial);
        const Case c = random_case(rng, trial);
        const Columns expected = run(versions.back().scan, c);
        std::uint32_t hits = 0;
        for (const CandidateRange& r : c.ranges) {
            for (std::uint32_t a = c.a0; a < c.a1; ++a) {
                const std::uint32_t first =
                    r.own && c.in.half_stencil ? std::max(r.b0, a + 1) : r.b0;
                for (std::uint32_t b = first; b < r.b1; ++b) {
                    const double dx = (c.x[b] - c.x[a]) + r.v[0], dy = (c.y[b] - c.y[a]) + r.v[1],
                                 dz = (c.z[b] - c.z[a]) + r.v[2];
                    hits += dx * dx + dy * dy + dz * dz < c.in.cutoff_sq && !(r.own && a == b);
                }
            }
        }
        ASSERT_EQ(expected.n, hits);
        // Oriented: i <= j. Not oriented: as found, i the home atom's index.
        for (std::uint32_t p = 0; p < expected.n && c.in.orient; ++p) {
            ASSERT_LE(expected.i[p], expected.j[p]);
        }
        std::uint32_t unturned = 0;
        for (std::uint32_t p = 0; p < expected.n && !c.in.orient; ++p) {
            for (std::uint32_t a = c.a0; a < c.a1; ++a) {
                unturned += c.index[a] == expected.i[p];
            }
        }
        ASSERT_EQ(unturned, c.in.orient ? 0 : expected.n);
        for (const auto& version : versions) {
            SCOPED_TRACE(version.name);
            std::uint64_t tested = 0;
            expect_same(c, run(version.scan, c, &tested), expected);
            EXPECT_EQ(tested, whole_candidates(c));
        }
    }
}

// With the cells' bounding boxes every version writes exactly what the portable one writes
// without them (pruning leaves out only candidates beyond the cutoff, and changes no order),
// while testing fewer candidates; the cases hold distances and boxes exactly at the cutoff.
TEST(RangeKernel, CellBoxesPruneNoPair) {
    const auto versions = range_kernels();
    std::mt19937_64 rng(43);
    std::uint64_t whole = 0, pruned = 0;
    for (int trial = 0; trial < 4000; ++trial) {
        SCOPED_TRACE(trial);
        CellCase cc = random_cell_case(rng, trial);
        Case& c = cc.c;
        if (c.x.empty()) {
            continue;
        }
        std::uint64_t all = 0;
        const Columns expected = run(versions.back().scan, c, &all);
        ASSERT_EQ(all, whole_candidates(c)); // without boxes every candidate is tested
        whole += all;
        c.in.boxes = cc.boxes.data();
        c.in.cluster_start = cc.starts.data();
        std::uint64_t portable = 0;
        run(versions.back().scan, c, &portable);
        pruned += portable;
        for (const auto& version : versions) {
            SCOPED_TRACE(version.name);
            std::uint64_t tested = 0;
            expect_same(c, run(version.scan, c, &tested), expected);
            EXPECT_EQ(tested, portable);
        }
    }
    EXPECT_LT(double(pruned), 0.5 * double(whole));
}
