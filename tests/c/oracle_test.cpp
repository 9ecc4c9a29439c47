// The C API against the C++ API (the same arrays, bit for bit and in the same order: the
// binding adds nothing) and against the brute-force oracle, on random seeded systems:
// triclinic and strongly skewed boxes, every combination of periodic axes, cutoffs several
// times the box, atoms far outside it. Verlet lists along a random trajectory likewise.
#include <algorithm>
#include <atomic>
#include <cstdint>
#include <random>
#include <string>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

#include "c_api_support.hpp"
#include "tricell.h"
#include "tricell/tricell.hpp"

using namespace tricell::testing;

namespace {

// The sanitizer build runs fewer cases (tests/c/CMakeLists.txt).
#ifdef TRICELL_C_CASES
constexpr std::uint64_t case_count = TRICELL_C_CASES;
#else
constexpr std::uint64_t case_count = 600;
#endif

template <class A, class B> void expect_same_array(const A& cxx, const B* c, std::size_t n) {
    ASSERT_EQ(cxx.size(), n);
    for (std::size_t k = 0; k < n; ++k) {
        if (cxx[k] != c[k]) {
            ADD_FAILURE() << "entry " << k << " differs: " << cxx[k] << " vs " << c[k];
            return;
        }
    }
}

// Every stored array of the C view equals the C++ list's, in order.
void expect_same_list(const tricell::NeighborList& cxx, const tricell_pairs& c,
                      const tricell::Quantities& q, bool offsets) {
    ASSERT_EQ(cxx.size(), c.size);
    expect_same_array(cxx.i(), c.i, c.size);
    expect_same_array(cxx.j(), c.j, c.size);
    ASSERT_EQ(c.shifts != nullptr, q.shifts);
    ASSERT_EQ(c.distances != nullptr, q.distances);
    ASSERT_EQ(c.vectors != nullptr, q.vectors);
    if (q.shifts) {
        expect_same_array(cxx.shifts(), c.shifts, 3 * c.size);
    }
    if (q.distances) {
        expect_same_array(cxx.distances(), c.distances, c.size);
    }
    if (q.vectors) {
        expect_same_array(cxx.vectors(), c.vectors, 3 * c.size);
    }
    ASSERT_EQ(c.offsets != nullptr, offsets);
    if (offsets && !cxx.offsets().empty()) {
        expect_same_array(cxx.offsets(), c.offsets, c.atoms + 1);
    }
}

} // namespace

TEST(CApiOracle, Neighbors_MatchCxxAndBruteForce) {
    auto search = make_search();
    auto list = make_list();
    std::size_t pairs_seen = 0;
    for (std::uint64_t seed = 0; seed < case_count; ++seed) {
        SCOPED_TRACE(seed);
        const RandomSystem sys = random_system(seed);
        SCOPED_TRACE(sys.kind);
        std::mt19937_64 rng(seed + 17);
        tricell_neighbor_options o;
        ASSERT_EQ(tricell_neighbor_options_init(&o), TRICELL_OK);
        o.cutoff = sys.cutoff;
        o.half = int(rng() % 2);
        o.sorted = int(rng() % 2);
        o.vectors = 1;
        o.threads = rng() % 3 == 0 ? 3 : 1;
        const tricell_box box = c_box(sys);
        ASSERT_EQ(tricell_neighbors(search.get(), &box, xyz(sys.positions), sys.positions.size(),
                                    &o, list.get()),
                  TRICELL_OK)
            << tricell_last_error();
        tricell_pairs pairs;
        ASSERT_EQ(tricell_neighbor_list_pairs(list.get(), &pairs), TRICELL_OK);
        pairs_seen += pairs.size;

        tricell::NeighborOptions cxx_options;
        cxx_options.cutoff = sys.cutoff;
        cxx_options.half = o.half == 1;
        cxx_options.sorted = o.sorted == 1;
        cxx_options.quantities.vectors = true;
        cxx_options.threads = o.threads;
        const tricell::NeighborList cxx =
            tricell::compute_neighbors(sys.box(), sys.positions, cxx_options);
        expect_same_list(cxx, pairs, cxx_options.quantities, cxx_options.sorted);
        if (o.sorted == 1) {
            EXPECT_EQ(pairs.atoms, sys.positions.size());
        }

        PairMap expected = brute_force_pairs(sys.box(), sys.positions, sys.cutoff);
        if (o.half == 1) {
            expected = canonical_half(expected);
        }
        expect_same_pairs(expected, to_map(pairs), sys.cutoff, tolerance(sys));
    }
    EXPECT_GT(pairs_seen, 1000u); // the cases are not all trivially empty
}

TEST(CApiOracle, Neighbors_QuantitiesSubsetsAndStablePointers) {
    const RandomSystem sys = random_system(3);
    const tricell_box box = c_box(sys);
    auto search = make_search();
    auto list = make_list();
    for (int mask = 0; mask < 8; ++mask) {
        SCOPED_TRACE(mask);
        tricell_neighbor_options o;
        ASSERT_EQ(tricell_neighbor_options_init(&o), TRICELL_OK);
        o.cutoff = sys.cutoff;
        o.shifts = mask & 1;
        o.distances = (mask >> 1) & 1;
        o.vectors = (mask >> 2) & 1;
        o.sorted = 1;
        ASSERT_EQ(tricell_neighbors(search.get(), &box, xyz(sys.positions), sys.positions.size(),
                                    &o, list.get()),
                  TRICELL_OK);
        tricell_pairs first, second;
        ASSERT_EQ(tricell_neighbor_list_pairs(list.get(), &first), TRICELL_OK);
        ASSERT_EQ(tricell_neighbor_list_pairs(list.get(), &second), TRICELL_OK);
        EXPECT_EQ(first.i, second.i); // a view, not a copy
        EXPECT_EQ(first.vectors, second.vectors);
        tricell::NeighborOptions c;
        c.cutoff = sys.cutoff;
        c.sorted = true;
        c.quantities = tricell::Quantities{o.shifts == 1, o.distances == 1, o.vectors == 1};
        expect_same_list(tricell::compute_neighbors(sys.box(), sys.positions, c), first,
                         c.quantities, true);
    }
}

TEST(CApiOracle, Box_ConstructorsMatchCxx) {
    const double rows[9] = {10, 0, 0, 9, 10, 0, 2, -3, 12};
    const int periodic[3] = {1, 1, 0};
    Eigen::Matrix3d m;
    m << 10, 0, 0, 9, 10, 0, 2, -3, 12;
    const tricell::Periodicity pbc{{true, true, false}};
    tricell_box from_rows, from_columns, from_parameters;
    ASSERT_EQ(tricell_box_from_rows(rows, periodic, &from_rows), TRICELL_OK);
    double columns[9];
    for (int k = 0; k < 9; ++k) {
        columns[k] = rows[3 * (k % 3) + k / 3];
    }
    ASSERT_EQ(tricell_box_from_columns(columns, periodic, &from_columns), TRICELL_OK);
    ASSERT_EQ(tricell_box_from_parameters(5, 6, 7, 80, 95, 105, periodic, &from_parameters),
              TRICELL_OK);
    const Eigen::Matrix3d h_rows = tricell::Box::from_rows(m, pbc).matrix();
    const Eigen::Matrix3d h_param = tricell::Box::from_parameters(5, 6, 7, 80, 95, 105).matrix();
    for (int k = 0; k < 3; ++k) {
        EXPECT_EQ(from_rows.periodic[k], periodic[k]);
        EXPECT_EQ(from_parameters.periodic[k], periodic[k]);
        for (int c = 0; c < 3; ++c) {
            EXPECT_EQ(from_rows.vectors[k][c], rows[3 * k + c]);
            EXPECT_EQ(from_columns.vectors[k][c], rows[3 * k + c]);
            EXPECT_EQ(from_rows.vectors[k][c], h_rows(c, k));
            EXPECT_EQ(from_parameters.vectors[k][c], h_param(c, k));
        }
    }
}

TEST(CApiOracle, Verlet_MatchesCxxAlongATrajectory) {
    const std::uint64_t systems = std::max<std::uint64_t>(case_count / 20, 10);
    std::size_t rebuilds = 0, steps = 0;
    for (std::uint64_t seed = 0; seed < systems; ++seed) {
        SCOPED_TRACE(seed);
        RandomSystem sys = random_system(seed);
        SCOPED_TRACE(sys.kind);
        std::mt19937_64 rng(seed + 99);
        tricell_verlet_options o;
        ASSERT_EQ(tricell_verlet_options_init(&o), TRICELL_OK);
        o.neighbors.cutoff = sys.cutoff;
        o.neighbors.half = int(rng() % 2);
        o.neighbors.vectors = 1;
        o.skin = 0.1 * sys.cutoff;
        tricell_verlet* raw = nullptr;
        ASSERT_EQ(tricell_verlet_create(&o, &raw), TRICELL_OK) << tricell_last_error();
        VerletHandle verlet(raw);

        tricell::VerletOptions c;
        c.cutoff = sys.cutoff;
        c.half = o.neighbors.half == 1;
        c.quantities.vectors = true;
        c.skin = o.skin;
        tricell::VerletList cxx(c);

        std::normal_distribution<double> step(0, 0.02 * sys.cutoff);
        const tricell_box box = c_box(sys);
        for (int t = 0; t < 12; ++t) {
            SCOPED_TRACE(t);
            for (auto& x : sys.positions) {
                x += Eigen::Vector3d(step(rng), step(rng), step(rng));
            }
            int rebuilt = -1;
            ASSERT_EQ(tricell_verlet_update(verlet.get(), &box, xyz(sys.positions),
                                            sys.positions.size(), &rebuilt),
                      TRICELL_OK)
                << tricell_last_error();
            const bool cxx_rebuilt = cxx.update(sys.box(), sys.positions);
            EXPECT_EQ(rebuilt, cxx_rebuilt ? 1 : 0);
            rebuilds += std::size_t(rebuilt);
            ++steps;
            tricell_pairs pairs;
            ASSERT_EQ(tricell_verlet_pairs(verlet.get(), &pairs), TRICELL_OK);
            expect_same_list(cxx.pairs(), pairs, c.quantities, true);
            PairMap expected = brute_force_pairs(sys.box(), sys.positions, sys.cutoff);
            if (c.half) {
                expected = canonical_half(expected);
            }
            expect_same_pairs(expected, to_map(pairs), sys.cutoff, tolerance(sys));
        }
    }
    EXPECT_LT(rebuilds, steps); // some updates only refreshed
}

TEST(CApiErrors, MessageIsPerThread) {
    constexpr int thread_count = 4;
    std::atomic<int> failed{0}, checked{0};
    std::vector<std::string> seen(thread_count);
    std::vector<std::thread> threads;
    for (int t = 0; t < thread_count; ++t) {
        threads.emplace_back([&, t] {
            auto search = make_search();
            auto list = make_list();
            const double rows[9] = {4, 0, 0, 0, 4, 0, 0, 0, 4};
            const int periodic[3] = {1, 1, 1};
            tricell_box box;
            tricell_box_from_rows(rows, periodic, &box);
            tricell_neighbor_options o;
            tricell_neighbor_options_init(&o);
            o.cutoff = -double(t + 1);
            tricell_neighbors(search.get(), &box, nullptr, 0, &o, list.get());
            // Wait until every thread has failed, then read this thread's message.
            ++failed;
            while (failed.load() < thread_count) {
                std::this_thread::yield();
            }
            seen[std::size_t(t)] = tricell_last_error();
            ++checked;
        });
    }
    for (auto& t : threads) {
        t.join();
    }
    ASSERT_EQ(checked.load(), thread_count);
    for (int t = 0; t < thread_count; ++t) {
        EXPECT_EQ(seen[std::size_t(t)], "cutoff must be > 0 (got -" + std::to_string(t + 1) + ")");
    }
}

TEST(CApiVersion, FunctionsMatchTheHeader) {
    EXPECT_EQ(tricell_version_major(), TRICELL_VERSION_MAJOR);
    EXPECT_EQ(tricell_version_minor(), TRICELL_VERSION_MINOR);
    EXPECT_EQ(tricell_version_patch(), TRICELL_VERSION_PATCH);
    EXPECT_EQ(std::string(tricell_version()), TRICELL_VERSION_STRING);
    EXPECT_EQ(TRICELL_VERSION,
              TRICELL_VERSION_MAJOR * 10000 + TRICELL_VERSION_MINOR * 100 + TRICELL_VERSION_PATCH);
    EXPECT_EQ(std::string(tricell_version()), std::to_string(TRICELL_VERSION_MAJOR) + "." +
                                                  std::to_string(TRICELL_VERSION_MINOR) + "." +
                                                  std::to_string(TRICELL_VERSION_PATCH));
}
