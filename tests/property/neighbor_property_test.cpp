// Property tests of the neighbour search against the brute-force oracle over thousands of
// random cases with fixed seeds (the seed is printed on failure). One value-parameterised suite
// runs every property on every backend of the registry (tricell::search_backends(), `auto`
// included), and every backend is compared with the dense one pair for pair.
#include <algorithm>
#include <array>
#include <cstdint>
#include <cstring>
#include <numeric>
#include <ostream>
#include <random>
#include <utility>
#include <vector>

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include "support/brute_force.hpp"
#include "support/identical_lists.hpp"
#include "support/random_systems.hpp"
#include "tricell/neighbor_list.hpp"

using tricell::Box;
using tricell::NeighborList;
using tricell::NeighborOptions;
using tricell::SearchBackend;
using tricell::testing::PairMap;
using tricell::testing::RandomSystem;

namespace {

// The sanitizer build runs fewer cases (TRICELL_PROPERTY_CASES from tests/CMakeLists.txt).
#ifdef TRICELL_PROPERTY_CASES
constexpr std::uint64_t case_count = TRICELL_PROPERTY_CASES;
#else
constexpr std::uint64_t case_count = 1000;
#endif

double tolerance(const RandomSystem& sys) {
    double scale = 1;
    for (const auto& x : sys.positions) {
        scale = std::max(scale, x.cwiseAbs().maxCoeff());
    }
    return 1e-10 * scale;
}

// Equal as sets of (i, j, S), with equal d and D; an entry missing from one side is allowed
// only when its distance is within the tolerance of the cutoff (rounding decides it).
void expect_same_pairs(const PairMap& expected, const PairMap& actual, double cutoff, double tol,
                       const char* what) {
    SCOPED_TRACE(what);
    int reported = 0;
    for (const auto& [key, value] : expected) {
        const auto found = actual.find(key);
        if (found == actual.end()) {
            if (std::abs(value.distance - cutoff) > tol && reported++ < 5) {
                const auto& [i, j, a, b, c] = key;
                ADD_FAILURE() << "missing pair i=" << i << " j=" << j << " S=(" << a << "," << b
                              << "," << c << ") d=" << value.distance;
            }
            continue;
        }
        if (std::abs(found->second.distance - value.distance) > tol ||
            (found->second.vector - value.vector).norm() > tol) {
            if (reported++ < 5) {
                ADD_FAILURE() << "distance differs: " << found->second.distance << " vs "
                              << value.distance;
            }
        }
    }
    for (const auto& [key, value] : actual) {
        if (expected.count(key) == 0 && std::abs(value.distance - cutoff) > tol && reported++ < 5) {
            const auto& [i, j, a, b, c] = key;
            ADD_FAILURE() << "extra pair i=" << i << " j=" << j << " S=(" << a << "," << b << ","
                          << c << ") d=" << value.distance;
        }
    }
}

// Random tuning knobs: none of them may change the result.
NeighborOptions options_for(std::uint64_t seed, double cutoff, SearchBackend backend) {
    std::mt19937_64 rng(seed * 7919 + 1);
    NeighborOptions o;
    o.cutoff = cutoff;
    o.backend = backend;
    o.quantities.vectors = true;
    o.cells_per_cutoff = 1 + double(rng() % 3);
    if (rng() % 5 == 0) {
        o.max_cells = 1 + rng() % 8; // force the dense grid's cap to bite
    }
    if (rng() % 3 == 0) {
        o.hash_table_size = 1 + rng() % 5; // a tiny hash table: collisions everywhere
    }
    if (rng() % 2 == 0) {
        o.leaf_size = 1 + rng() % 12; // octree leaves from one atom up
    }
    if (rng() % 2 == 0) {
        o.threads = 1 + int(rng() % 4); // the threaded build and the ordered in-place output
    }
    return o;
}

NeighborList run(const RandomSystem& sys, NeighborOptions o, bool half) {
    o.half = half;
    return tricell::compute_neighbors(sys.box(), sys.positions, o);
}

// The suite's parameter: a backend of the registry, printed by its name (so that ctest names the
// tests .../dense, .../direct).
struct Backend {
    SearchBackend value;
};
void PrintTo(const Backend& backend, std::ostream* os) {
    *os << tricell::backend_name(backend.value);
}
std::vector<Backend> registry_backends() {
    std::vector<Backend> out;
    for (const SearchBackend backend : tricell::search_backends()) {
        out.push_back({backend});
    }
    return out;
}

class NeighborProperty : public ::testing::TestWithParam<Backend> {
  protected:
    SearchBackend backend() const { return GetParam().value; }
    NeighborOptions options(std::uint64_t seed, double cutoff) const {
        return options_for(seed, cutoff, backend());
    }
    // The direct backend tests N^2 pairs through every image: it is meant for tiny cells, so its
    // suite takes the cases of up to 40 atoms (about two thirds of them).
    bool skip(const RandomSystem& sys) const {
        return backend() == SearchBackend::direct && sys.positions.size() > 40;
    }
    // Calls check(sys, seed) on the random system of each seed first, first + step, ... below
    // case_count that this backend takes, under a trace naming the seed and the kind; stops at
    // the first failure.
    template <class Check>
    void for_each_case(std::uint64_t first, std::uint64_t step, const Check& check) const {
        for (std::uint64_t seed = first; seed < case_count; seed += step) {
            RandomSystem sys = tricell::testing::random_system(seed);
            if (skip(sys)) {
                continue;
            }
            SCOPED_TRACE(testing::Message() << "seed " << seed << " (" << sys.kind << ")");
            check(sys, seed);
            if (::testing::Test::HasFailure()) {
                return;
            }
        }
    }
};

INSTANTIATE_TEST_SUITE_P(EveryBackend, NeighborProperty, ::testing::ValuesIn(registry_backends()));

} // namespace

TEST_P(NeighborProperty, FullListEqualsBruteForce_RandomCases) {
    for (std::uint64_t seed = 0; seed < case_count; ++seed) {
        const RandomSystem sys = tricell::testing::random_system(seed);
        if (skip(sys)) {
            continue;
        }
        SCOPED_TRACE(testing::Message() << "seed " << seed << " (" << sys.kind << "), N "
                                        << sys.positions.size() << ", cutoff " << sys.cutoff);
        const PairMap expected =
            tricell::testing::brute_force_pairs(sys.box(), sys.positions, sys.cutoff);
        const NeighborOptions o = options(seed, sys.cutoff);
        const PairMap full = tricell::testing::to_map(run(sys, o, false));
        expect_same_pairs(expected, full, sys.cutoff, tolerance(sys), "full vs oracle");
        if (::testing::Test::HasFailure()) {
            return;
        }
    }
}

// Molecules, slabs and wires as data sets give them: the vectors of open axes zero (ASE's Atoms
// without a cell), or parallel to a periodic one. The pairs are the brute-force ones of the
// same positions in the system's own box (any open vectors give the same pairs), full and half.
TEST_P(NeighborProperty, ZeroVectorsOfOpenAxesGiveTheBruteForcePairs_RandomCases) {
    for (std::uint64_t seed = 0; seed < case_count; ++seed) {
        RandomSystem sys = tricell::testing::random_system(seed);
        if (skip(sys)) {
            continue;
        }
        std::mt19937_64 rng(seed * 31 + 7);
        if (sys.pbc.count() == 3) { // a molecule, a slab or a wire
            sys.pbc.axes = {{false, false, false}};
            for (std::size_t k = 0, periodic = rng() % 3; k < periodic; ++k) {
                sys.pbc.axes[(seed + k) % 3] = true;
            }
        }
        Eigen::Matrix3d given = sys.h;
        for (int k = 0; k < 3; ++k) {
            if (!sys.pbc[k]) {
                // Zero mostly; sometimes along a periodic vector (or the first one).
                const int other = sys.pbc[(k + 1) % 3] ? (k + 1) % 3 : (k + 2) % 3;
                given.col(k) = rng() % 4 == 0 ? Eigen::Vector3d(2.5 * sys.h.col(other))
                                              : Eigen::Vector3d::Zero();
            }
        }
        SCOPED_TRACE(testing::Message()
                     << "seed " << seed << " (" << sys.kind << "), N " << sys.positions.size()
                     << ", periodic " << sys.pbc.axes[0] << sys.pbc.axes[1] << sys.pbc.axes[2]);
        const PairMap expected =
            tricell::testing::brute_force_pairs(sys.box(), sys.positions, sys.cutoff);
        NeighborOptions o = options(seed, sys.cutoff);
        const Box box = Box::from_columns(given, sys.pbc);
        o.half = false;
        const PairMap full =
            tricell::testing::to_map(tricell::compute_neighbors(box, sys.positions, o));
        expect_same_pairs(expected, full, sys.cutoff, tolerance(sys), "full vs oracle");
        o.half = true;
        const PairMap half =
            tricell::testing::to_map(tricell::compute_neighbors(box, sys.positions, o));
        expect_same_pairs(tricell::testing::canonical_half(expected), half, sys.cutoff,
                          tolerance(sys), "half vs oracle");
        for (const auto& [key, value] : full) {
            const auto& [i, j, a, b, c] = key;
            const int shift[3] = {a, b, c};
            for (int k = 0; k < 3; ++k) {
                ASSERT_TRUE(sys.pbc[k] || shift[k] == 0) << "a shift along open axis " << k;
            }
        }
        if (::testing::Test::HasFailure()) {
            return;
        }
    }
}

TEST_P(NeighborProperty, HalfListEqualsCanonicalFull_RandomCases) {
    for_each_case(0, 1, [&](const RandomSystem& sys, std::uint64_t seed) {
        const NeighborOptions o = options(seed, sys.cutoff);
        const NeighborList full_list = run(sys, o, false);
        const NeighborList half_list = run(sys, o, true);
        const PairMap full = tricell::testing::to_map(full_list);
        const PairMap half = tricell::testing::to_map(half_list);
        EXPECT_EQ(half.size(), half_list.size()) << "duplicates in the half list";
        expect_same_pairs(tricell::testing::canonical_half(full), half, sys.cutoff, tolerance(sys),
                          "half vs canonical(full)");
        // Reciprocity: (i, j, S) in the full list iff (j, i, -S), with D negated.
        for (const auto& [key, value] : full) {
            const auto& [i, j, a, b, c] = key;
            const auto reverse = full.find({j, i, -a, -b, -c});
            ASSERT_NE(reverse, full.end());
            EXPECT_LT((reverse->second.vector + value.vector).norm(), tolerance(sys));
        }
    });
}

TEST_P(NeighborProperty, SameListAsTheDenseBackend_RandomCases) {
    for_each_case(0, 2, [&](const RandomSystem& sys, std::uint64_t seed) {
        NeighborOptions o = options(seed, sys.cutoff);
        o.sorted = true;
        NeighborOptions dense = o;
        dense.backend = SearchBackend::dense;
        for (const bool half : {false, true}) {
            const NeighborList expected = run(sys, dense, half);
            const NeighborList actual = run(sys, o, half);
            tricell::testing::expect_identical(expected, actual);
            if (::testing::Test::HasFatalFailure()) {
                return;
            }
        }
    });
}

// The bits of a double (+0 and -0 differ).
std::uint64_t bits(double v) {
    std::uint64_t out;
    std::memcpy(&out, &v, sizeof out);
    return out;
}

// D is rounded as (x_j - x_i) + H S with a zero component stored as +0 (docs/contract.md), so
// it is a function of (i, j, S) alone: (j, i, -S) has exactly -D (a zero stays +0) and the same
// d, and a half list's pair has the full list's D and d of the same (i, j, S), bit for bit,
// whichever orientation the backend found it in. With a uniform cutoff and with per-atom radii
// (the variable-cutoff path orients pair by pair).
TEST_P(NeighborProperty, HalfAndReversedPairsHaveExactlyNegatedVectors_RandomCases) {
    const auto negated = [](double v) { return v == 0.0 ? 0.0 : -v; };
    for_each_case(3, 4, [&](const RandomSystem& sys, std::uint64_t seed) {
        NeighborOptions o = options(seed, sys.cutoff);
        if (seed % 8 == 7 && !sys.positions.empty()) {
            std::mt19937_64 rng(seed);
            std::uniform_real_distribution<double> unit(0.2, 0.5);
            o.radii.resize(sys.positions.size());
            for (double& r : o.radii) {
                r = unit(rng) * sys.cutoff;
            }
            o.cutoff = 0;
        }
        const PairMap full = tricell::testing::to_map(run(sys, o, false));
        const PairMap half = tricell::testing::to_map(run(sys, o, true));
        for (const auto& [key, value] : full) {
            const auto& [i, j, a, b, c] = key;
            const auto reverse = full.find({j, i, -a, -b, -c});
            ASSERT_NE(reverse, full.end());
            ASSERT_EQ(bits(reverse->second.distance), bits(value.distance));
            for (int k = 0; k < 3; ++k) {
                ASSERT_EQ(bits(value.vector[k]), bits(value.vector[k] + 0.0)) << "a -0 in D";
                ASSERT_EQ(bits(reverse->second.vector[k]), bits(negated(value.vector[k])))
                    << "i " << i << " j " << j << " S (" << a << "," << b << "," << c << ")";
            }
        }
        ASSERT_EQ(2 * half.size(), full.size());
        for (const auto& [key, value] : half) {
            const auto same = full.find(key);
            ASSERT_NE(same, full.end());
            ASSERT_EQ(bits(same->second.distance), bits(value.distance));
            for (int k = 0; k < 3; ++k) {
                ASSERT_EQ(bits(same->second.vector[k]), bits(value.vector[k]));
            }
        }
    });
}

// Per-atom radii and per-species tables: the oracle at the largest cutoff, filtered by each
// pair's own cutoff; a pair may differ only within rounding of its own cutoff.
TEST_P(NeighborProperty, VariableCutoffsEqualBruteForce_RandomCases) {
    for_each_case(7, 3, [&](const RandomSystem& sys, std::uint64_t seed) {
        std::mt19937_64 rng(seed + 99);
        std::uniform_real_distribution<double> unit(0, 1);
        const std::size_t n = sys.positions.size();
        NeighborOptions o = options(seed, sys.cutoff);
        o.cutoff = 0;
        o.half = seed % 2 == 0;
        const bool by_species = seed % 3 == 1;
        std::vector<double> radius(n);
        std::vector<std::int32_t> species(n);
        // Species 0..2; the table covers (0,0), (0,1), (1,2) and (2,2): (0,2) and (1,1) never
        // count.
        const double table[3][3] = {{0.6, 0.9, 0.0}, {0.9, 0.0, 0.7}, {0.0, 0.7, 1.0}};
        for (std::size_t i = 0; i < n; ++i) {
            radius[i] = unit(rng) < 0.1 ? 0.0 : 0.5 * sys.cutoff * unit(rng);
            species[i] = std::int32_t(rng() % 3);
        }
        if (by_species) {
            o.species = species;
            o.species_cutoffs = {{0, 0, 0.6 * sys.cutoff},
                                 {1, 0, 0.9 * sys.cutoff},
                                 {1, 2, 0.7 * sys.cutoff},
                                 {2, 2, 1.0 * sys.cutoff}};
        } else {
            o.radii = radius;
        }
        auto cutoff_of = [&](std::uint32_t i, std::uint32_t j) {
            return by_species ? table[species[i]][species[j]] * sys.cutoff : radius[i] + radius[j];
        };
        PairMap expected;
        for (const auto& [key, value] :
             tricell::testing::brute_force_pairs(sys.box(), sys.positions, sys.cutoff)) {
            if (value.distance < cutoff_of(std::get<0>(key), std::get<1>(key))) {
                expected[key] = value;
            }
        }
        if (o.half) {
            expected = tricell::testing::canonical_half(expected);
        }
        const NeighborList list = tricell::compute_neighbors(sys.box(), sys.positions, o);
        const PairMap actual = tricell::testing::to_map(list);
        ASSERT_EQ(actual.size(), list.size()) << "duplicates";
        const double tol = tolerance(sys);
        for (const auto& [key, value] : expected) {
            const double c = cutoff_of(std::get<0>(key), std::get<1>(key));
            if (actual.count(key) == 0 && std::abs(value.distance - c) > tol) {
                ADD_FAILURE() << "missing pair d=" << value.distance << " cutoff " << c;
            }
        }
        for (const auto& [key, value] : actual) {
            const double c = cutoff_of(std::get<0>(key), std::get<1>(key));
            if (!(value.distance < c)) {
                ADD_FAILURE() << "pair at d=" << value.distance << " not below its cutoff " << c;
            }
            if (expected.count(key) == 0 && std::abs(value.distance - c) > tol) {
                ADD_FAILURE() << "extra pair d=" << value.distance << " cutoff " << c;
            }
        }
    });
}

TEST_P(NeighborProperty, ResultDoesNotDependOnTheGrid_RandomCases) {
    for_each_case(1, 3, [&](const RandomSystem& sys, std::uint64_t /*seed*/) {
        NeighborOptions coarse;
        coarse.backend = backend();
        coarse.cutoff = sys.cutoff;
        coarse.cells_per_cutoff = 1;
        coarse.max_cells = 1; // one cell: every pair found through images only
        coarse.quantities.vectors = true;
        NeighborOptions fine = coarse;
        fine.cells_per_cutoff = 4;
        fine.max_cells = 0;
        for (const bool half : {false, true}) {
            const PairMap a = tricell::testing::to_map(run(sys, coarse, half));
            const PairMap b = tricell::testing::to_map(run(sys, fine, half));
            expect_same_pairs(a, b, sys.cutoff, tolerance(sys), "one cell vs fine grid");
        }
    });
}

TEST_P(NeighborProperty, InvariantUnderLatticeTranslationOfAnyAtom_RandomCases) {
    for (std::uint64_t seed = 2; seed < case_count; seed += 4) {
        RandomSystem sys = tricell::testing::random_system(seed);
        if (skip(sys)) {
            continue;
        }
        if (sys.positions.empty() || !sys.pbc.any()) {
            continue;
        }
        SCOPED_TRACE(testing::Message() << "seed " << seed << " (" << sys.kind << ")");
        std::mt19937_64 rng(seed);
        const std::uint32_t moved = std::uint32_t(rng() % sys.positions.size());
        Eigen::Vector3i t;
        for (int k = 0; k < 3; ++k) {
            t[k] = sys.pbc[k] ? int(rng() % 41) - 20 : 0;
        }
        const NeighborOptions o = options(seed, sys.cutoff);
        const PairMap before = tricell::testing::to_map(run(sys, o, false));
        sys.positions[moved] += sys.h * t.cast<double>();
        const PairMap after = tricell::testing::to_map(run(sys, o, false));
        // x_k + H t: pairs (k, j, S) become (k, j, S + t) and (i, k, S) become (i, k, S - t).
        PairMap expected;
        for (const auto& [key, value] : before) {
            auto [i, j, a, b, c] = key;
            Eigen::Vector3i s(a, b, c);
            if (i == moved && j != moved) {
                s += t;
            } else if (j == moved && i != moved) {
                s -= t;
            }
            expected[{i, j, s[0], s[1], s[2]}] = value;
        }
        expect_same_pairs(expected, after, sys.cutoff, tolerance(sys) * 100, "translated");
        if (::testing::Test::HasFailure()) {
            return;
        }
    }
}

TEST_P(NeighborProperty, InvariantUnderRotationOfTheWholeSystem_RandomCases) {
    for_each_case(3, 5, [&](RandomSystem& sys, std::uint64_t seed) {
        std::mt19937_64 rng(seed);
        std::normal_distribution<double> normal;
        const Eigen::Matrix3d rotation =
            Eigen::Quaterniond(
                Eigen::Vector4d(normal(rng), normal(rng), normal(rng), normal(rng)).normalized())
                .toRotationMatrix();
        const NeighborOptions o = options(seed, sys.cutoff);
        const PairMap before = tricell::testing::to_map(run(sys, o, true));
        sys.h = rotation * sys.h;
        for (auto& x : sys.positions) {
            x = rotation * x;
        }
        PairMap expected;
        for (const auto& [key, value] : before) {
            expected[key] = {value.distance, rotation * value.vector};
        }
        const PairMap after = tricell::testing::to_map(run(sys, o, true));
        expect_same_pairs(expected, after, sys.cutoff, tolerance(sys) * 100, "rotated");
    });
}

TEST_P(NeighborProperty, VisitorSeesExactlyTheStoredPairs_RandomCases) {
    for_each_case(4, 7, [&](const RandomSystem& sys, std::uint64_t seed) {
        NeighborOptions o = options(seed, sys.cutoff);
        o.half = seed % 2 == 0;
        const PairMap stored =
            tricell::testing::to_map(tricell::compute_neighbors(sys.box(), sys.positions, o));
        PairMap visited;
        tricell::for_each_pair(sys.box(), sys.positions, o, [&](const tricell::Pair& p) {
            visited[{p.i, p.j, p.shift[0], p.shift[1], p.shift[2]}] = {p.distance(), p.vector};
        });
        ASSERT_EQ(stored.size(), visited.size());
        expect_same_pairs(stored, visited, sys.cutoff, 0.0, "visitor vs stored");
    });
}

TEST_P(NeighborProperty, OutputIdenticalForAnyThreadCount_RandomCases) {
    for_each_case(5, 11, [&](const RandomSystem& sys, std::uint64_t seed) {
        NeighborOptions o = options(seed, sys.cutoff);
        o.half = seed % 2 == 1;
        o.threads = 1;
        const NeighborList one = tricell::compute_neighbors(sys.box(), sys.positions, o);
        for (const int threads : {2, 3, 4, 0}) {
            o.threads = threads;
            const NeighborList many = tricell::compute_neighbors(sys.box(), sys.positions, o);
            ASSERT_EQ(one.i(), many.i()) << threads << " threads";
            ASSERT_EQ(one.j(), many.j());
            ASSERT_EQ(one.shifts(), many.shifts());
            ASSERT_EQ(one.distances(), many.distances());
            ASSERT_EQ(one.vectors(), many.vectors());
        }
    });
}

namespace {

// Every pair of `list` as (i, j, S, d, D) (0 for a column not stored), in ascending order.
std::vector<std::array<double, 9>> rows_in_order(const NeighborList& list) {
    std::vector<std::array<double, 9>> rows(list.size());
    for (std::size_t p = 0; p < list.size(); ++p) {
        std::array<double, 9>& r = rows[p];
        r.fill(0);
        r[0] = list.i()[p], r[1] = list.j()[p];
        for (std::size_t a = 0; a < 3 && !list.shifts().empty(); ++a) {
            r[2 + a] = list.shifts()[3 * p + a];
        }
        r[5] = list.distances().empty() ? 0 : list.distances()[p];
        for (std::size_t a = 0; a < 3 && !list.vectors().empty(); ++a) {
            r[6 + a] = list.vectors()[3 * p + a];
        }
    }
    std::sort(rows.begin(), rows.end());
    return rows;
}

} // namespace

// grouped: a half list is the unordered list stably grouped by i (checked against a stable sort
// of it by i); a full list holds the unordered list's pairs with the same values (the unordered
// one comes from the half stencil, turned around, the grouped one from the full stencil in runs
// of each atom); both with per-atom offsets equal to the sorted list's; with any thread count,
// and without stored shifts, distances or vectors too (so that each column in turn is the
// widest). One list object is reused over all the cases, as a caller in a loop does (the grouping
// keeps its scratch in it), and must equal a fresh list each time.
TEST_P(NeighborProperty, GroupedListIsTheUnorderedListGroupedByI_RandomCases) {
    NeighborList reused;
    for_each_case(2, 3, [&](const RandomSystem& sys, std::uint64_t seed) {
        NeighborOptions o = options(seed, sys.cutoff);
        o.half = seed % 2 == 1;
        o.quantities.shifts = seed % 5 != 0;
        o.quantities.distances = seed % 7 != 3;
        o.quantities.vectors = seed % 4 != 2;
        const NeighborList plain = tricell::compute_neighbors(sys.box(), sys.positions, o);
        o.grouped = true;
        const NeighborList grouped = tricell::compute_neighbors(sys.box(), sys.positions, o);
        tricell::compute_neighbors(sys.box(), sys.positions, o, reused);
        tricell::testing::expect_identical(grouped, reused);
        if (::testing::Test::HasFatalFailure()) {
            return;
        }
        ASSERT_EQ(reused.offsets(), grouped.offsets());
        o.grouped = false;
        o.sorted = true;
        const NeighborList sorted = tricell::compute_neighbors(sys.box(), sys.positions, o);

        ASSERT_EQ(grouped.size(), plain.size());
        if (!o.half) {
            EXPECT_EQ(rows_in_order(grouped), rows_in_order(plain));
        }
        std::vector<std::size_t> order(plain.size());
        std::iota(order.begin(), order.end(), std::size_t(0));
        std::stable_sort(order.begin(), order.end(),
                         [&](std::size_t a, std::size_t b) { return plain.i()[a] < plain.i()[b]; });
        for (std::size_t k = 0; k < order.size() && o.half; ++k) {
            const std::size_t p = order[k];
            ASSERT_EQ(grouped.i()[k], plain.i()[p]) << "pair " << k;
            ASSERT_EQ(grouped.j()[k], plain.j()[p]) << "pair " << k;
            if (o.quantities.distances) {
                ASSERT_EQ(grouped.distances()[k], plain.distances()[p]) << "pair " << k;
            }
            for (std::size_t a = 0; a < 3; ++a) {
                if (o.quantities.vectors) {
                    ASSERT_EQ(grouped.vectors()[3 * k + a], plain.vectors()[3 * p + a]);
                }
                if (o.quantities.shifts) {
                    ASSERT_EQ(grouped.shifts()[3 * k + a], plain.shifts()[3 * p + a]);
                }
            }
        }
        ASSERT_EQ(grouped.shifts().size(), plain.shifts().size());
        ASSERT_EQ(grouped.distances().size(), plain.distances().size());
        ASSERT_EQ(grouped.vectors().size(), plain.vectors().size());
        ASSERT_EQ(grouped.offsets(), sorted.offsets());
        ASSERT_EQ(grouped.offsets().size(), sys.positions.size() + 1);
        ASSERT_EQ(grouped.offsets().front(), 0u);
        ASSERT_EQ(grouped.offsets().back(), grouped.size());
        for (std::size_t atom = 0; atom < sys.positions.size(); ++atom) {
            for (std::size_t k = grouped.offsets()[atom]; k < grouped.offsets()[atom + 1]; ++k) {
                ASSERT_EQ(grouped.i()[k], atom) << "pair " << k;
            }
        }
        EXPECT_TRUE(plain.offsets().empty());
    });
}

TEST_P(NeighborProperty, CellReductionDoesNotChangeTheList_RandomCases) {
    for_each_case(1, 6,
                  [&](const RandomSystem& sys, std::uint64_t seed) { // the strongly skewed kind
                      NeighborOptions o = options(seed, sys.cutoff);
                      o.half = seed % 4 == 1;
                      o.reduce_cell = false;
                      const PairMap plain = tricell::testing::to_map(run(sys, o, o.half));
                      o.reduce_cell = true;
                      const PairMap with_reduction = tricell::testing::to_map(run(sys, o, o.half));
                      expect_same_pairs(plain, with_reduction, sys.cutoff, tolerance(sys) * 100,
                                        "reduced vs plain frame");
                  });
}

TEST(NeighborSearch, ShearedBoxUsesItsReducedTwin) {
    // A box sheared by whole lattice vectors is the same lattice as the cube: the search must
    // find the same pairs, with shifts expressed in the sheared vectors.
    const Box cube = Box::from_lammps(10, 10, 10, 0, 0, 0);
    const Box sheared = Box::from_lammps(10, 10, 10, 30, -20, 40); // b += 3a, c += -2a + 4b
    std::mt19937_64 rng(8);
    std::uniform_real_distribution<double> u(0, 10);
    std::vector<Eigen::Vector3d> x(200);
    for (auto& r : x) {
        r = Eigen::Vector3d(u(rng), u(rng), u(rng));
    }
    NeighborOptions o;
    o.cutoff = 3.0;
    o.quantities.vectors = true;
    const PairMap in_cube = tricell::testing::to_map(tricell::compute_neighbors(cube, x, o));
    const NeighborList in_sheared = tricell::compute_neighbors(sheared, x, o);
    ASSERT_EQ(in_sheared.size(), in_cube.size());
    for (std::size_t k = 0; k < in_sheared.size(); ++k) {
        const Eigen::Vector3d d = x[in_sheared.j()[k]] - x[in_sheared.i()[k]] +
                                  sheared.matrix() * in_sheared.shift(k).cast<double>();
        ASSERT_NEAR(d.norm(), in_sheared.distances()[k], 1e-9);
    }
    tricell::NeighborSearch search;
    search.build(sheared, x, o);
    EXPECT_TRUE(search.info().reduced_frame);
    EXPECT_EQ(search.info().cells, (std::array<int, 3>{{3, 3, 3}})); // the cube's grid
}

// The dense grid's cluster boxes (each cell's atoms sorted along the stencil rows and cut into
// clusters of at most 8; each atom tests only the clusters of a stencil row from the first to the
// last whose atoms' box comes within the cutoff) change no pair and no bit: crowded triclinic
// and strongly skewed systems of 3 to 6 cells per axis and `per_cell` atoms per cell (where the
// boxes are built and tested), some atoms far outside the box (images), some on faces and
// corners, some coincident, full and half lists on 1 and 2 threads and cells of one and of half a
// cutoff (whose stencil may wrap round a small grid), each against the linked cells (which test
// every candidate of the same stencil) bit for bit and, every third case, against the
// brute-force oracle. Returns the candidates the dense grid and the linked cells test over the
// cases (the scanner's counts, NeighborSearch::unit_work()).
static std::pair<std::uint64_t, std::uint64_t>
check_cluster_boxes(std::size_t per_cell, std::uint64_t cases, std::uint64_t first_seed) {
    std::uint64_t pruned = 0, whole = 0;
    for (std::uint64_t seed = 0; seed < cases; ++seed) {
        std::mt19937_64 rng(seed + first_seed);
        std::uniform_real_distribution<double> unit(0, 1);
        RandomSystem sys;
        sys.h = tricell::testing::random_box_matrix(rng, 8, 16, seed % 3 == 0 ? 2.0 : 0.5);
        sys.pbc = tricell::Periodicity::all();
        const Box box = Box::from_columns(sys.h, tricell::Periodicity::all());
        const int cells = 3 + int(rng() % 4);
        sys.cutoff = box.perpendicular_widths().minCoeff() / (cells + 0.2 * unit(rng));
        const double special[] = {0.0, 0.5, 1.0, 0.25};
        const std::size_t n = per_cell * std::size_t(cells * cells * cells);
        for (std::size_t k = 0; k < n; ++k) {
            Eigen::Vector3d s(unit(rng), unit(rng), unit(rng));
            if (rng() % 8 == 0) {
                s[int(rng() % 3)] = special[rng() % 4];
            }
            if (rng() % 8 == 0) {
                s[int(rng() % 3)] += std::round(200 * unit(rng) - 100);
            }
            sys.positions.push_back(k > 0 && rng() % 20 == 0 ? sys.positions[rng() % k]
                                                             : Eigen::Vector3d(sys.h * s));
        }
        SCOPED_TRACE(testing::Message()
                     << "seed " << seed << ", N " << n << ", cutoff " << sys.cutoff);
        NeighborOptions o;
        o.cutoff = sys.cutoff;
        o.quantities.vectors = true;
        o.sorted = true;
        o.cells_per_cutoff = 1 + double(seed % 2);
        o.threads = 1 + int(seed % 4 == 3);
        NeighborOptions linked = o;
        o.backend = SearchBackend::dense;
        linked.backend = SearchBackend::linked;
        for (const bool half : {false, true}) {
            const NeighborList expected = run(sys, linked, half);
            const NeighborList actual = run(sys, o, half);
            tricell::testing::expect_identical(expected, actual);
            if (::testing::Test::HasFatalFailure()) {
                return {pruned, whole};
            }
            if (seed % 3 == 0) {
                PairMap oracle =
                    tricell::testing::brute_force_pairs(sys.box(), sys.positions, sys.cutoff);
                if (half) {
                    oracle = tricell::testing::canonical_half(oracle);
                }
                expect_same_pairs(oracle, tricell::testing::to_map(actual), sys.cutoff,
                                  tolerance(sys), "dense vs oracle");
            }
            const auto tests = [&](NeighborOptions options) {
                options.half = half;
                tricell::NeighborSearch search;
                search.build(sys.box(), sys.positions, options);
                const tricell::UnitWork work = search.unit_work();
                return std::accumulate(work.measured.begin(), work.measured.end(), 0.0);
            };
            pruned += std::uint64_t(tests(o));
            whole += std::uint64_t(tests(linked));
        }
        if (::testing::Test::HasFailure()) {
            break;
        }
    }
    return {pruned, whole};
}

// About 8 atoms per cell: a cluster is about a cell.
TEST(NeighborSearch, CellBoxesChangeNoPair) {
    const auto [pruned, whole] =
        check_cluster_boxes(8, std::min<std::uint64_t>(case_count / 10, 60), 4100);
    EXPECT_LT(double(pruned), 0.9 * double(whole));
}

// About 40 atoms per cell: five clusters per cell, thin slabs along the rows, which leave far
// fewer candidates than the cells' boxes alone (0.45 of the linked cells' on these cases, where
// the boxes of whole cells leave 0.77).
TEST(NeighborSearch, ClusterBoxesChangeNoPair) {
    const auto [pruned, whole] =
        check_cluster_boxes(40, std::min<std::uint64_t>(case_count / 20, 30), 5100);
    EXPECT_LT(double(pruned), 0.6 * double(whole));
}
