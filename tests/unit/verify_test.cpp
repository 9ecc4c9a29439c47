// tricell::verify: it accepts the library's own lists on random systems (every backend, full and
// half, radii and species tables, brute-force and backend references), agrees with the test
// oracle (tests/support/brute_force.hpp) on what the list should hold, and reports each kind of
// defect planted in a correct list with the words that name it.
#include <cstdint>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "support/brute_force.hpp"
#include "support/expect_throw_msg.hpp"
#include "support/random_systems.hpp"
#include "tricell/error.hpp"
#include "tricell/neighbor_list.hpp"
#include "tricell/verify.hpp"

namespace {

using tricell::Box;
using tricell::NeighborList;
using tricell::NeighborOptions;
using tricell::PairArrays;
using tricell::SearchBackend;
using tricell::VerifyReport;
using tricell::testing::random_system;
using tricell::testing::RandomSystem;

#ifdef TRICELL_VERIFY_CASES
constexpr std::uint64_t cases = TRICELL_VERIFY_CASES;
#else
constexpr std::uint64_t cases = 120;
#endif

NeighborOptions all_quantities(double cutoff, bool half) {
    NeighborOptions o;
    o.cutoff = cutoff;
    o.half = half;
    o.quantities.vectors = true;
    return o;
}

// Variable cutoffs for seed: per-atom radii or a species table, about the system's cutoff.
NeighborOptions variable_cutoffs(const RandomSystem& sys, std::uint64_t seed, bool half) {
    std::mt19937_64 rng(seed);
    NeighborOptions o = all_quantities(0, half);
    const std::size_t n = sys.positions.size();
    if (seed % 2 == 0) {
        for (std::size_t i = 0; i < n; ++i) {
            o.radii.push_back(sys.cutoff * (0.2 + 0.3 * double(rng() % 1000) / 1000));
        }
    } else {
        for (std::size_t i = 0; i < n; ++i) {
            o.species.push_back(std::int32_t(rng() % 3));
        }
        o.species_cutoffs = {
            {0, 0, 0.6 * sys.cutoff}, {0, 1, sys.cutoff}, {2, 2, 0.8 * sys.cutoff}};
    }
    return o;
}

// A list as plain int64 arrays, the way another library hands it over.
struct Arrays {
    std::vector<std::int64_t> i, j, s;
    std::vector<double> d, v;
    explicit Arrays(const NeighborList& list) {
        for (std::size_t k = 0; k < list.size(); ++k) {
            i.push_back(list.i()[k]);
            j.push_back(list.j()[k]);
            for (int a = 0; a < 3; ++a) {
                s.push_back(list.shifts()[3 * k + std::size_t(a)]);
                v.push_back(list.vectors()[3 * k + std::size_t(a)]);
            }
            d.push_back(list.distances()[k]);
        }
    }
    void add(std::size_t k) { // a copy of entry k at the end
        i.push_back(i[k]);
        j.push_back(j[k]);
        d.push_back(d[k]);
        for (int a = 0; a < 3; ++a) {
            s.push_back(s[3 * k + std::size_t(a)]);
            v.push_back(v[3 * k + std::size_t(a)]);
        }
    }
    void erase(std::size_t k) {
        i.erase(i.begin() + std::ptrdiff_t(k));
        j.erase(j.begin() + std::ptrdiff_t(k));
        d.erase(d.begin() + std::ptrdiff_t(k));
        s.erase(s.begin() + std::ptrdiff_t(3 * k), s.begin() + std::ptrdiff_t(3 * k + 3));
        v.erase(v.begin() + std::ptrdiff_t(3 * k), v.begin() + std::ptrdiff_t(3 * k + 3));
    }
    void turn(std::size_t k) { // (i, j, S, D) -> (j, i, -S, -D)
        std::swap(i[k], j[k]);
        for (std::size_t a = 0; a < 3; ++a) {
            s[3 * k + a] = -s[3 * k + a];
            v[3 * k + a] = -v[3 * k + a];
        }
    }
    PairArrays view() const {
        return PairArrays{i.size(), i.data(), j.data(), s.data(), d.data(), v.data()};
    }
};

TEST(Verify, AcceptsOwnListsOnRandomSystems_EveryBackend) {
    for (std::uint64_t seed = 0; seed < cases; ++seed) {
        const RandomSystem sys = random_system(seed);
        const Box box = sys.box();
        const bool half = seed % 2 == 1;
        NeighborOptions o = all_quantities(sys.cutoff, half);
        o.backend = tricell::search_backends()[seed % tricell::search_backends().size()];
        SCOPED_TRACE("seed " + std::to_string(seed) + " (" + sys.kind + ", backend " +
                     tricell::backend_name(o.backend) + (half ? ", half)" : ", full)"));
        const NeighborList list = tricell::compute_neighbors(box, sys.positions, o);
        const VerifyReport report = tricell::verify(box, sys.positions, o, list);
        EXPECT_TRUE(report.ok) << report.message;
        EXPECT_EQ(report.entries, list.size());
        // The reference agrees with the test oracle, up to pairs at the cutoff.
        auto oracle = tricell::testing::brute_force_pairs(box, sys.positions, sys.cutoff);
        if (half) {
            oracle = tricell::testing::canonical_half(oracle);
        }
        EXPECT_NEAR(double(report.expected), double(oracle.size()), double(report.near_cutoff));
        EXPECT_EQ(report.reference, "brute force");
        // The same list as plain arrays, each half-list pair turned around, is accepted too.
        Arrays arrays(list);
        if (half) {
            for (std::size_t k = 0; k < arrays.i.size(); k += 2) {
                arrays.turn(k);
            }
        }
        const VerifyReport again = tricell::verify(box, sys.positions, o, arrays.view());
        EXPECT_TRUE(again.ok) << again.message;
    }
}

TEST(Verify, AcceptsOwnListsWithVariableCutoffs) {
    for (std::uint64_t seed = 0; seed < cases / 2; ++seed) {
        const RandomSystem sys = random_system(seed);
        const Box box = sys.box();
        NeighborOptions o = variable_cutoffs(sys, seed, seed % 4 >= 2);
        SCOPED_TRACE("seed " + std::to_string(seed) + " (" + sys.kind + ")");
        const NeighborList list = tricell::compute_neighbors(box, sys.positions, o);
        const VerifyReport report = tricell::verify(box, sys.positions, o, list);
        EXPECT_TRUE(report.ok) << report.message;
        // A wrong table is noticed whenever it changes the list.
        NeighborOptions other = o;
        if (!other.radii.empty()) {
            other.radii[0] *= 2;
        } else {
            other.species_cutoffs[1].cutoff *= 0.5;
        }
        const auto count = tricell::compute_neighbors(box, sys.positions, other).size();
        if (count != list.size()) {
            EXPECT_FALSE(tricell::verify(box, sys.positions, other, list).ok);
        }
    }
}

// A list of a query's pairs (NeighborOptions::query) is checked against the reference's pairs
// of the query; the same list under options of every point misses the others' pairs.
TEST(Verify, ChecksTheListOfAQuery) {
    for (std::uint64_t seed = 0; seed < cases / 4; ++seed) {
        const RandomSystem sys = random_system(seed);
        const Box box = sys.box();
        NeighborOptions o = all_quantities(sys.cutoff, seed % 2 == 1);
        std::vector<std::uint32_t> query;
        for (std::uint32_t k = 0; k < sys.positions.size(); k += 3) {
            query.push_back(k);
        }
        o.query = query;
        SCOPED_TRACE("seed " + std::to_string(seed) + " (" + sys.kind + ")");
        const NeighborList list = tricell::compute_neighbors(box, sys.positions, o);
        const VerifyReport report = tricell::verify(box, sys.positions, o, list);
        EXPECT_TRUE(report.ok) << report.message;
        NeighborOptions every = o;
        every.query.reset();
        const std::size_t all = tricell::compute_neighbors(box, sys.positions, every).size();
        if (all > list.size()) {
            EXPECT_FALSE(tricell::verify(box, sys.positions, every, list).ok);
        }
        if (list.size() > 0) {
            Arrays arrays(list);
            arrays.erase(0);
            EXPECT_FALSE(tricell::verify(box, sys.positions, o, arrays.view()).ok);
        }
    }
}

// Systems above the brute-force budget: the reference is a backend the automatic choice does
// not take, and it agrees with the list of every backend.
TEST(Verify, LargeSystemsUseAnotherBackend) {
    std::mt19937_64 rng(7);
    std::uniform_real_distribution<double> unit(0, 1);
    const Box box = Box::from_parameters(30, 32, 34, 80, 95, 110);
    std::vector<Eigen::Vector3d> x;
    for (int k = 0; k < 3000; ++k) {
        x.push_back(box.matrix() * Eigen::Vector3d(unit(rng), unit(rng), unit(rng)));
    }
    for (const SearchBackend backend : tricell::search_backends()) {
        if (backend == SearchBackend::direct) {
            continue; // every pair through every image: too slow for this test
        }
        NeighborOptions o = all_quantities(4.0, backend == SearchBackend::hash);
        o.backend = backend;
        const NeighborList list = tricell::compute_neighbors(box, x, o);
        const VerifyReport report = tricell::verify(box, x, o, list);
        EXPECT_TRUE(report.ok) << tricell::backend_name(backend) << ": " << report.message;
        EXPECT_NE(report.reference, "brute force");
        EXPECT_EQ(report.expected, list.size());
        Arrays arrays(list);
        arrays.erase(arrays.i.size() / 2);
        const VerifyReport missing = tricell::verify(box, x, o, arrays.view());
        EXPECT_FALSE(missing.ok);
        EXPECT_EQ(missing.missing, 1u) << missing.message;
    }
}

// A small periodic-along-a-and-b system with pairs through images, for the planted defects.
struct Planted {
    Box box =
        Box::from_parameters(4, 4.5, 5, 85, 95, 100, tricell::Periodicity{{true, true, false}});
    std::vector<Eigen::Vector3d> x;
    NeighborOptions options;
    NeighborList list;
    explicit Planted(bool half) {
        std::mt19937_64 rng(11);
        std::uniform_real_distribution<double> unit(0, 1);
        for (int k = 0; k < 12; ++k) {
            x.push_back(box.matrix() * Eigen::Vector3d(unit(rng), unit(rng), unit(rng)));
        }
        options = all_quantities(3.0, half);
        options.sorted = true;
        list = tricell::compute_neighbors(box, x, options);
    }
    VerifyReport check(const Arrays& arrays) const {
        return tricell::verify(box, x, options, arrays.view());
    }
};

void expect_defect(const VerifyReport& report, const std::string& words) {
    EXPECT_FALSE(report.ok);
    EXPECT_NE(report.message.find(words), std::string::npos) << "message: " << report.message;
}

TEST(Verify, ReportsEachKindOfDefect) {
    const Planted p(false);
    ASSERT_GT(p.list.size(), 20u);
    const Arrays good(p.list);
    ASSERT_TRUE(p.check(good).ok) << p.check(good).message;

    Arrays dropped = good;
    dropped.erase(5);
    const PairArrays v = good.view();
    const std::string pair5 = "(" + std::to_string(v.i[5]) + ", " + std::to_string(v.j[5]) + ", [" +
                              std::to_string(v.shifts[15]) + " " + std::to_string(v.shifts[16]) +
                              " " + std::to_string(v.shifts[17]) + "])";
    VerifyReport r = p.check(dropped);
    expect_defect(r, "pair " + pair5 + " at distance ");
    expect_defect(r, " < cutoff 3 is missing");
    EXPECT_EQ(r.missing, 1u);

    Arrays twice = good;
    twice.add(5);
    r = p.check(twice);
    expect_defect(r, "pair " + pair5 + " is listed twice (entries 5 and " +
                         std::to_string(good.i.size()) + ")");
    EXPECT_EQ(r.duplicates, 1u);

    Arrays flipped = good; // S of an entry with a nonzero shift along a periodic axis, negated
    std::size_t k = 0;
    while (k < good.i.size() && good.s[3 * k] == 0) {
        ++k;
    }
    ASSERT_LT(k, good.i.size());
    flipped.s[3 * k] = -flipped.s[3 * k];
    r = p.check(flipped);
    EXPECT_FALSE(r.ok);
    EXPECT_EQ(r.wrong_values, 1u) << r.message; // its D no longer fits
    EXPECT_EQ(r.missing, 1u) << r.message;

    Arrays self = good;
    self.add(0);
    self.j.back() = self.i.back();
    std::fill(self.s.end() - 3, self.s.end(), 0);
    r = p.check(self);
    expect_defect(r, "entry " + std::to_string(good.i.size()) + " (" +
                         std::to_string(self.i.back()) + ", " + std::to_string(self.i.back()) +
                         ", [0 0 0]): an atom paired with itself");
    EXPECT_EQ(r.rule_breaks, 1u);

    Arrays open = good;
    open.s[3 * 2 + 2] = 1;
    r = p.check(open);
    expect_defect(r, "entry 2 ");
    expect_defect(r, "a shift along the open axis c (Sc = 1)");

    Arrays distance = good;
    distance.d[3] += 0.01;
    r = p.check(distance);
    expect_defect(r, "entry 3 ");
    expect_defect(r, ": distance ");
    expect_defect(r, " but the positions give ");
    EXPECT_EQ(r.wrong_values, 1u);

    Arrays vector = good;
    vector.v[3 * 4 + 1] = -vector.v[3 * 4 + 1] + 0.5;
    expect_defect(p.check(vector), "entry 4 ");

    Arrays nan = good;
    nan.d[6] = std::nan("");
    expect_defect(p.check(nan), "entry 6 ");

    Arrays range = good;
    range.j[7] = 12;
    expect_defect(p.check(range), "index 12 is out of range for 12 positions");
    range.j[7] = -1;
    expect_defect(p.check(range), "index -1 is out of range for 12 positions");

    Arrays extra = good; // a pair beyond the cutoff
    extra.add(0);
    extra.s[extra.s.size() - 3] += 3;
    extra.d.back() = (p.x[std::size_t(extra.j.back())] - p.x[std::size_t(extra.i.back())] +
                      p.box.matrix() * Eigen::Vector3d(double(extra.s[extra.s.size() - 3]),
                                                       double(extra.s[extra.s.size() - 2]), 0))
                         .norm();
    extra.v.resize(0);
    PairArrays no_vectors = extra.view();
    no_vectors.vectors = nullptr;
    r = tricell::verify(p.box, p.x, p.options, no_vectors);
    expect_defect(r, ">= cutoff 3 is not a pair");
    EXPECT_EQ(r.extra, 1u);
}

TEST(Verify, HalfListsTakeEitherOrientationOnce) {
    const Planted p(true);
    const Arrays good(p.list);
    ASSERT_TRUE(p.check(good).ok);
    Arrays turned = good;
    for (std::size_t k = 0; k < turned.i.size(); ++k) {
        turned.turn(k);
    }
    EXPECT_TRUE(p.check(turned).ok) << p.check(turned).message;

    Arrays both = good; // a pair in both orientations
    both.add(3);
    both.turn(both.i.size() - 1);
    const VerifyReport r = p.check(both);
    expect_defect(r, "is listed twice (entries 3 and " + std::to_string(good.i.size()) +
                         "), in both orientations; a half list holds each pair once");

    // A full list where a half one is expected, and the other way round.
    const Planted full(false);
    const VerifyReport as_half = tricell::verify(p.box, p.x, p.options, full.list);
    EXPECT_FALSE(as_half.ok);
    EXPECT_EQ(as_half.duplicates, full.list.size() / 2) << as_half.message;
    const VerifyReport as_full = tricell::verify(full.box, full.x, full.options, p.list);
    EXPECT_EQ(as_full.missing, p.list.size()) << as_full.message;
}

// A pair within rounding of its cutoff may be listed or not.
TEST(Verify, PairsAtTheCutoffMayBeEitherWay) {
    const Box box = Box::from_parameters(10, 10, 10, 90, 90, 90);
    const std::vector<Eigen::Vector3d> x = {{0.1, 0.2, 0.3}, {0.1 + 2.5, 0.2, 0.3}};
    NeighborOptions o = all_quantities((x[1] - x[0]).norm(), false);
    const std::int64_t i[] = {0, 1}, j[] = {1, 0}, s[6] = {0, 0, 0, 0, 0, 0};
    const VerifyReport with = tricell::verify(box, x, o, PairArrays{2, i, j, s, nullptr, nullptr});
    EXPECT_TRUE(with.ok) << with.message;
    EXPECT_EQ(with.near_cutoff, 2u);
    const VerifyReport without = tricell::verify(box, x, o, PairArrays{});
    EXPECT_TRUE(without.ok) << without.message;
    o.cutoff *= 1 + 1e-9;
    expect_defect(tricell::verify(box, x, o, PairArrays{}), "pair (0, 1, [0 0 0]) at distance 2.5");
}

TEST(Verify, BadArgumentsAreRefused) {
    const Planted p(false);
    std::vector<Eigen::Vector3d> x = p.x;
    x[3].y() = std::nan("");
    EXPECT_THROW_MSG(tricell::verify(p.box, x, p.options, p.list), tricell::InvalidArgument,
                     "position 3 is not finite");
    NeighborOptions o = p.options;
    o.cutoff = -1;
    EXPECT_THROW_MSG(tricell::verify(p.box, p.x, o, p.list), tricell::InvalidArgument,
                     "cutoff must be > 0 (got -1)");
    o = p.options;
    o.radii = {1.0};
    o.cutoff = 0;
    EXPECT_THROW_MSG(tricell::verify(p.box, p.x, o, p.list), tricell::InvalidArgument,
                     "radii has 1 entries for 12 positions");
    PairArrays no_shifts = Arrays(p.list).view();
    EXPECT_THROW_MSG(tricell::verify(p.box, p.x, p.options,
                                     PairArrays{no_shifts.size, no_shifts.i, no_shifts.j, nullptr,
                                                nullptr, nullptr}),
                     tricell::InvalidArgument, "the list has no shifts S");
    EXPECT_THROW_MSG(tricell::verify(p.box, p.x, p.options,
                                     PairArrays{3, nullptr, nullptr, nullptr, nullptr, nullptr}),
                     tricell::InvalidArgument, "the list has 3 entries but i is null");
}

} // namespace
