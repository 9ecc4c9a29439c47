// The C API against the C++ API (the same arrays, bit for bit and in the same order: the
// binding adds nothing) and against the brute-force oracle, on random seeded systems:
// triclinic and strongly skewed boxes, every combination of periodic axes, cutoffs several
// times the box, atoms far outside it. Verlet lists along a random trajectory likewise.
#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <functional>
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

// The pairs tricell_neighbors() gives for `sys` with `o`: a view into `list`.
void c_neighbors(tricell_neighbor_search* search, tricell_neighbor_list* list,
                 const RandomSystem& sys, const tricell_neighbor_options& o, tricell_pairs& pairs) {
    const tricell_box box = c_box(sys);
    ASSERT_EQ(tricell_neighbors(search, &box, xyz(sys.positions), sys.positions.size(), &o, list),
              TRICELL_OK)
        << tricell_last_error();
    ASSERT_EQ(tricell_neighbor_list_pairs(list, &pairs), TRICELL_OK);
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
        o.grouped = o.sorted == 0 ? int(rng() % 2) : 0;
        tricell_pairs pairs;
        ASSERT_NO_FATAL_FAILURE(c_neighbors(search.get(), list.get(), sys, o, pairs));
        pairs_seen += pairs.size;

        tricell::NeighborOptions cxx_options;
        cxx_options.cutoff = sys.cutoff;
        cxx_options.half = o.half == 1;
        cxx_options.sorted = o.sorted == 1;
        cxx_options.grouped = o.grouped == 1;
        cxx_options.quantities.vectors = true;
        cxx_options.threads = o.threads;
        const tricell::NeighborList cxx =
            tricell::compute_neighbors(sys.box(), sys.positions, cxx_options);
        expect_same_list(cxx, pairs, cxx_options.quantities, cxx_options.with_offsets());
        if (cxx_options.with_offsets()) {
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

// Molecules, slabs and wires with zero vectors along their open axes, given by hand in a
// tricell_box, through tricell_box_from_rows and in a batch: the brute-force pairs.
TEST(CApiOracle, ZeroVectorsOfOpenAxes_MatchBruteForce) {
    auto search = make_search();
    auto list = make_list();
    tricell_batch_list* batch = nullptr;
    ASSERT_EQ(tricell_batch_list_create(&batch), TRICELL_OK);
    std::size_t pairs_seen = 0;
    for (std::uint64_t seed = 0; seed < case_count / 4; ++seed) {
        SCOPED_TRACE(seed);
        RandomSystem sys = random_system(seed);
        sys.pbc.axes = {{false, false, false}};
        for (std::size_t k = 0; k < seed % 3; ++k) { // a molecule, a wire or a slab
            sys.pbc.axes[(seed / 3 + k) % 3] = true;
        }
        tricell_box box;
        double rows[9];
        for (int k = 0; k < 3; ++k) {
            box.periodic[k] = sys.pbc[k] ? 1 : 0;
            for (int c = 0; c < 3; ++c) {
                box.vectors[k][c] = sys.pbc[k] ? sys.h(c, k) : 0.0;
                rows[3 * k + c] = box.vectors[k][c];
            }
        }
        tricell_box from_rows;
        ASSERT_EQ(tricell_box_from_rows(rows, box.periodic, &from_rows), TRICELL_OK)
            << tricell_last_error();
        tricell_neighbor_options o;
        ASSERT_EQ(tricell_neighbor_options_init(&o), TRICELL_OK);
        o.cutoff = sys.cutoff;
        o.half = int(seed / 3 % 2);
        o.vectors = 1;
        PairMap expected = brute_force_pairs(sys.box(), sys.positions, sys.cutoff);
        if (o.half == 1) {
            expected = canonical_half(expected);
        }
        for (const tricell_box* b : {&box, &from_rows}) {
            ASSERT_EQ(tricell_neighbors(search.get(), b, xyz(sys.positions), sys.positions.size(),
                                        &o, list.get()),
                      TRICELL_OK)
                << tricell_last_error();
            tricell_pairs pairs;
            ASSERT_EQ(tricell_neighbor_list_pairs(list.get(), &pairs), TRICELL_OK);
            expect_same_pairs(expected, to_map(pairs), sys.cutoff, tolerance(sys));
            pairs_seen += pairs.size;
        }
        const tricell_structure one{box, xyz(sys.positions), sys.positions.size()};
        ASSERT_EQ(tricell_neighbors_batch(&one, 1, &o, batch), TRICELL_OK) << tricell_last_error();
        tricell_batch_pairs in_batch;
        ASSERT_EQ(tricell_batch_list_pairs(batch, &in_batch), TRICELL_OK);
        expect_same_pairs(expected, to_map(in_batch.pairs), sys.cutoff, tolerance(sys));
    }
    tricell_batch_list_destroy(batch);
    EXPECT_GT(pairs_seen, 1000u);
}

// The k nearest within the cutoff through the C options: the C++ list, bit for bit.
TEST(CApiOracle, NearestWithin_MatchesCxx) {
    auto search = make_search();
    auto list = make_list();
    for (std::uint64_t seed = 0; seed < case_count / 4; ++seed) {
        SCOPED_TRACE(seed);
        const RandomSystem sys = random_system(seed);
        tricell_neighbor_options o;
        ASSERT_EQ(tricell_neighbor_options_init(&o), TRICELL_OK);
        EXPECT_EQ(o.max_neighbors, 0u);
        EXPECT_EQ(o.tie_tolerance, 0.0);
        EXPECT_EQ(o.symmetric, 0);
        o.cutoff = sys.cutoff;
        o.max_neighbors = 1 + seed % 7;
        o.tie_tolerance = seed % 3 == 0 ? 0.1 : 0.0;
        o.symmetric = int(seed % 2);
        o.vectors = 1;
        tricell_pairs pairs;
        ASSERT_NO_FATAL_FAILURE(c_neighbors(search.get(), list.get(), sys, o, pairs));
        tricell::NeighborOptions cxx_options;
        cxx_options.cutoff = sys.cutoff;
        cxx_options.max_neighbors = o.max_neighbors;
        cxx_options.tie_tolerance = o.tie_tolerance;
        cxx_options.symmetric = o.symmetric == 1;
        cxx_options.quantities.vectors = true;
        expect_same_list(tricell::compute_neighbors(sys.box(), sys.positions, cxx_options), pairs,
                         cxx_options.quantities, true);
    }
    tricell_neighbor_options o;
    ASSERT_EQ(tricell_neighbor_options_init(&o), TRICELL_OK);
    o.cutoff = 1;
    o.max_neighbors = 2;
    o.symmetric = 2;
    const RandomSystem sys = random_system(1);
    const tricell_box box = c_box(sys);
    EXPECT_STATUS(tricell_neighbors(search.get(), &box, xyz(sys.positions), sys.positions.size(),
                                    &o, list.get()),
                  TRICELL_ERROR_INVALID_ARGUMENT, "options.symmetric must be 0 or 1 (got 2)");
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
        c.neighbors.cutoff = sys.cutoff;
        c.neighbors.half = o.neighbors.half == 1;
        c.neighbors.quantities.vectors = true;
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
            expect_same_list(cxx.pairs(), pairs, c.neighbors.quantities, true);
            PairMap expected = brute_force_pairs(sys.box(), sys.positions, sys.cutoff);
            if (c.neighbors.half) {
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

TEST(CApiOracle, BackendsAndVariableCutoffs_MatchCxxAndBruteForce) {
    auto search = make_search();
    auto list = make_list();
    const std::uint64_t systems = std::max<std::uint64_t>(case_count / 3, 40);
    std::size_t pairs_seen = 0, refused = 0;
    for (std::uint64_t seed = 0; seed < systems; ++seed) {
        SCOPED_TRACE(seed);
        const RandomSystem sys = random_system(seed + 5000);
        SCOPED_TRACE(sys.kind);
        const std::size_t n = sys.positions.size();
        std::mt19937_64 rng(seed + 31);
        std::uniform_real_distribution<double> unit(0, 1);
        const int rule = int(seed % 3); // 0: one cutoff, 1: radii, 2: species table
        std::vector<double> radii(n);
        std::vector<std::int32_t> species(n);
        for (std::size_t k = 0; k < n; ++k) {
            radii[k] = sys.cutoff * (0.1 + 0.4 * unit(rng));
            species[k] = std::int32_t(rng() % 3) - 1; // -1, 0, 1
        }
        // Species pair (-1, 1) is missing from the table: such pairs never count.
        const std::vector<tricell_species_cutoff> table = {{-1, -1, 0.5 * sys.cutoff},
                                                           {0, -1, 0.8 * sys.cutoff},
                                                           {1, 0, sys.cutoff},
                                                           {1, 1, 0.3 * sys.cutoff}};
        tricell_neighbor_options o;
        ASSERT_EQ(tricell_neighbor_options_init(&o), TRICELL_OK);
        // Any backend of the library's table, the direct one included.
        const std::vector<tricell::SearchBackend>& backends = tricell::search_backends();
        o.backend = int(backends[rng() % backends.size()]);
        o.half = int(rng() % 2);
        o.sorted = int(rng() % 2);
        o.vectors = 1;
        o.threads = rng() % 3 == 0 ? 2 : 1;
        tricell::NeighborOptions c;
        c.backend = static_cast<tricell::SearchBackend>(o.backend);
        c.half = o.half == 1;
        c.sorted = o.sorted == 1;
        c.quantities.vectors = true;
        c.threads = o.threads;
        std::function<double(std::uint32_t, std::uint32_t)> cutoff_of;
        const double largest = sys.cutoff; // radii are at most 0.5 cutoff each, the table 1
        if (rule == 0) {
            o.cutoff = c.cutoff = sys.cutoff;
            cutoff_of = [&](std::uint32_t, std::uint32_t) { return sys.cutoff; };
        } else if (rule == 1) {
            o.cutoff = 0;
            o.radii = radii.data();
            c.radii = radii;
            cutoff_of = [&](std::uint32_t i, std::uint32_t j) { return radii[i] + radii[j]; };
        } else {
            o.cutoff = 0;
            o.species = species.data();
            o.species_cutoffs = table.data();
            o.species_cutoff_count = table.size();
            c.species = species;
            for (const auto& e : table) {
                c.species_cutoffs.push_back({e.a, e.b, e.cutoff});
            }
            cutoff_of = [&](std::uint32_t i, std::uint32_t j) {
                for (const auto& e : table) {
                    if ((e.a == species[i] && e.b == species[j]) ||
                        (e.b == species[i] && e.a == species[j])) {
                        return e.cutoff;
                    }
                }
                return 0.0;
            };
        }
        const tricell_box box = c_box(sys);
        const tricell_status status =
            tricell_neighbors(search.get(), &box, xyz(sys.positions), n, &o, list.get());
        tricell::NeighborList cxx;
        try {
            tricell::compute_neighbors(sys.box(), sys.positions, c, cxx);
        } catch (const tricell::InvalidArgument& e) {
            // Whatever the C++ call refuses, the C API must refuse the same way.
            EXPECT_EQ(status, TRICELL_ERROR_INVALID_ARGUMENT);
            EXPECT_EQ(std::string(tricell_last_error()), e.what());
            ++refused;
            continue;
        }
        ASSERT_EQ(status, TRICELL_OK) << tricell_last_error();
        tricell_pairs pairs;
        ASSERT_EQ(tricell_neighbor_list_pairs(list.get(), &pairs), TRICELL_OK);
        pairs_seen += pairs.size;
        expect_same_list(cxx, pairs, c.quantities, c.sorted);
        PairMap expected = brute_force_pairs(sys.box(), sys.positions, largest, cutoff_of);
        if (c.half) {
            expected = canonical_half(expected);
        }
        // Pairs within rounding of their own cutoff may go either way.
        const PairMap actual = to_map(pairs);
        const double tol = tolerance(sys);
        for (const auto& [key, value] : expected) {
            if (actual.count(key) == 0 &&
                std::abs(value.distance - cutoff_of(std::get<0>(key), std::get<1>(key))) > tol) {
                ADD_FAILURE() << "missing pair i=" << std::get<0>(key) << " j=" << std::get<1>(key);
                break;
            }
        }
        for (const auto& [key, value] : actual) {
            if (expected.count(key) == 0 &&
                std::abs(value.distance - cutoff_of(std::get<0>(key), std::get<1>(key))) > tol) {
                ADD_FAILURE() << "extra pair i=" << std::get<0>(key) << " j=" << std::get<1>(key);
                break;
            }
        }
    }
    EXPECT_GT(pairs_seen, 1000u);
    EXPECT_LT(refused, systems / 4);
}

TEST(CApiOracle, QuerySubset_MatchesCxx) {
    // options.query: the C list is the C++ subset list, array for array (whose rules
    // tests/unit/subset_search_test.cpp checks against the oracle).
    auto search = make_search();
    auto list = make_list();
    for (std::uint64_t seed = 0; seed < case_count / 10; ++seed) {
        SCOPED_TRACE(seed);
        const RandomSystem sys = random_system(seed);
        std::mt19937_64 rng(seed + 29);
        std::vector<std::uint32_t> query;
        for (std::uint32_t k = 0; k < sys.positions.size(); ++k) {
            if (rng() % 3 == 0) {
                query.push_back(k);
            }
        }
        tricell_neighbor_options o;
        ASSERT_EQ(tricell_neighbor_options_init(&o), TRICELL_OK);
        EXPECT_EQ(o.query, nullptr);
        o.cutoff = sys.cutoff;
        o.half = int(seed % 2);
        o.vectors = 1;
        const std::uint32_t none = 0;
        o.query = query.empty() ? &none : query.data(); // NULL would mean every point
        o.query_count = query.size();
        tricell_pairs pairs;
        ASSERT_NO_FATAL_FAILURE(c_neighbors(search.get(), list.get(), sys, o, pairs));
        tricell::NeighborOptions cxx_options;
        cxx_options.cutoff = sys.cutoff;
        cxx_options.half = o.half == 1;
        cxx_options.quantities.vectors = true;
        cxx_options.query = query;
        const tricell::NeighborList cxx =
            tricell::compute_neighbors(sys.box(), sys.positions, cxx_options);
        expect_same_list(cxx, pairs, cxx_options.quantities, false);
    }
    tricell_neighbor_options o;
    ASSERT_EQ(tricell_neighbor_options_init(&o), TRICELL_OK);
    o.cutoff = 1;
    o.query_count = 5;
    const double x[3] = {0, 0, 0};
    tricell_box box;
    const double rows[9] = {4, 0, 0, 0, 4, 0, 0, 0, 4};
    const int periodic[3] = {1, 1, 1};
    ASSERT_EQ(tricell_box_from_rows(rows, periodic, &box), TRICELL_OK);
    EXPECT_NE(tricell_neighbors(search.get(), &box, x, 1, &o, list.get()), TRICELL_OK);
    EXPECT_NE(std::string(tricell_last_error())
                  .find("options.query is NULL but options.query_count is 5"),
              std::string::npos)
        << tricell_last_error();
    const std::uint32_t bad[1] = {1};
    o.query = bad;
    o.query_count = 1;
    EXPECT_NE(tricell_neighbors(search.get(), &box, x, 1, &o, list.get()), TRICELL_OK);
    EXPECT_NE(std::string(tricell_last_error()).find("query[0] is 1"), std::string::npos)
        << tricell_last_error();
}
