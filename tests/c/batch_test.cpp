// tricell_neighbors_batch: the C arrays equal compute_neighbors_batch's bit for bit (the binding
// adds nothing), every structure's slice equals the brute-force oracle, and every validation
// branch gives its status and message and leaves the list empty.
#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "c_api_support.hpp"
#include "tricell.h"
#include "tricell/tricell.hpp"

using namespace tricell::testing;

namespace {

#ifdef TRICELL_C_CASES
constexpr std::uint64_t batch_count = TRICELL_C_CASES / 4;
#else
constexpr std::uint64_t batch_count = 150;
#endif

struct BatchDeleter {
    void operator()(tricell_batch_list* p) const { tricell_batch_list_destroy(p); }
};
using BatchHandle = std::unique_ptr<tricell_batch_list, BatchDeleter>;

BatchHandle make_batch() {
    tricell_batch_list* p = nullptr;
    EXPECT_EQ(tricell_batch_list_create(&p), TRICELL_OK);
    return BatchHandle(p);
}

// A batch of random systems (tests/support) sharing the first one's cutoff.
struct Batch {
    std::vector<RandomSystem> systems;
    std::vector<tricell_structure> c;
    std::vector<tricell::BatchStructure> cxx;
};

Batch random_batch(std::uint64_t seed) {
    Batch b;
    std::mt19937_64 rng(seed);
    const std::size_t count = rng() % 9;
    for (std::size_t s = 0; s < count; ++s) {
        b.systems.push_back(random_system(1000 * seed + s));
        b.systems.back().cutoff = b.systems.front().cutoff;
    }
    for (const RandomSystem& sys : b.systems) {
        b.c.push_back(tricell_structure{c_box(sys), xyz(sys.positions), sys.positions.size()});
        b.cxx.push_back(tricell::BatchStructure{sys.box(), sys.positions});
    }
    return b;
}

} // namespace

// Global indices through the C API: the positions of every structure concatenated into one
// array, each structure's pointer into it; the arrays equal the C++ call's with
// BatchIndices::global bit for bit, and i, j are the local ones plus the structure's first row.
TEST(CApiBatch, GlobalIndicesAreRowsOfTheConcatenatedPositions) {
    auto global = make_batch();
    auto local = make_batch();
    for (std::uint64_t seed = 0; seed < batch_count / 3; ++seed) {
        SCOPED_TRACE(seed);
        Batch b = random_batch(seed);
        std::vector<double> all;
        for (const RandomSystem& sys : b.systems) {
            for (const Eigen::Vector3d& x : sys.positions) {
                all.insert(all.end(), {x.x(), x.y(), x.z()});
            }
        }
        std::size_t first = 0;
        for (tricell_structure& c : b.c) {
            c.positions = c.n == 0 ? nullptr : all.data() + 3 * first;
            first += c.n;
        }
        tricell_neighbor_options o;
        ASSERT_EQ(tricell_neighbor_options_init(&o), TRICELL_OK);
        o.cutoff = b.systems.empty() ? 1.0 : b.systems.front().cutoff;
        o.half = int(seed % 2);
        o.threads = int(seed % 3);
        ASSERT_EQ(tricell_neighbors_batch_indexed(b.c.data(), b.c.size(), &o, TRICELL_BATCH_GLOBAL,
                                                  global.get()),
                  TRICELL_OK)
            << tricell_last_error();
        ASSERT_EQ(tricell_neighbors_batch_indexed(b.c.data(), b.c.size(), &o, TRICELL_BATCH_LOCAL,
                                                  local.get()),
                  TRICELL_OK);
        tricell_batch_pairs g, l;
        ASSERT_EQ(tricell_batch_list_pairs(global.get(), &g), TRICELL_OK);
        ASSERT_EQ(tricell_batch_list_pairs(local.get(), &l), TRICELL_OK);
        tricell::NeighborOptions cxx_options;
        cxx_options.cutoff = o.cutoff;
        cxx_options.half = o.half == 1;
        tricell::BatchList cxx;
        tricell::compute_neighbors_batch(b.cxx, cxx_options, cxx, tricell::BatchIndices::global);
        ASSERT_EQ(g.pairs.size, cxx.size());
        expect_same_array(cxx.i(), g.pairs.i, g.pairs.size);
        expect_same_array(cxx.j(), g.pairs.j, g.pairs.size);
        expect_same_array(cxx.distances(), g.pairs.distances, g.pairs.size);
        for (std::size_t s = 0; s < g.structures; ++s) {
            for (std::size_t k = g.pair_offsets[s]; k < g.pair_offsets[s + 1]; ++k) {
                ASSERT_EQ(g.pairs.i[k], l.pairs.i[k] + g.atom_offsets[s]);
                ASSERT_EQ(g.pairs.j[k], l.pairs.j[k] + g.atom_offsets[s]);
                ASSERT_LT(g.pairs.j[k], g.atom_offsets[s + 1]);
            }
        }
    }
    tricell_neighbor_options o;
    ASSERT_EQ(tricell_neighbor_options_init(&o), TRICELL_OK);
    o.cutoff = 1;
    EXPECT_STATUS(tricell_neighbors_batch_indexed(nullptr, 0, &o, 2, global.get()),
                  TRICELL_ERROR_INVALID_ARGUMENT,
                  "tricell_neighbors_batch_indexed: indices must be TRICELL_BATCH_LOCAL (0) or "
                  "TRICELL_BATCH_GLOBAL (1) (got 2)");
}

TEST(CApiBatch, MatchesCxxBitForBitAndBruteForce) {
    auto list = make_batch();
    std::size_t pairs_seen = 0, structures_seen = 0;
    for (std::uint64_t seed = 0; seed < batch_count; ++seed) {
        SCOPED_TRACE(seed);
        const Batch b = random_batch(seed);
        std::mt19937_64 rng(seed + 5);
        tricell_neighbor_options o;
        ASSERT_EQ(tricell_neighbor_options_init(&o), TRICELL_OK);
        o.cutoff = b.systems.empty() ? 1.0 : b.systems.front().cutoff;
        o.half = int(rng() % 2);
        o.sorted = int(rng() % 2);
        o.vectors = 1;
        o.threads = int(rng() % 3); // 0 (all cores), 1 or 2
        o.grouped = o.sorted == 0 ? int(rng() % 2) : 0;
        ASSERT_EQ(tricell_neighbors_batch(b.c.data(), b.c.size(), &o, list.get()), TRICELL_OK)
            << tricell_last_error();
        tricell_batch_pairs view;
        ASSERT_EQ(tricell_batch_list_pairs(list.get(), &view), TRICELL_OK);

        tricell::NeighborOptions cxx_options;
        cxx_options.cutoff = o.cutoff;
        cxx_options.half = o.half == 1;
        cxx_options.sorted = o.sorted == 1;
        cxx_options.grouped = o.grouped == 1;
        cxx_options.quantities.vectors = true;
        cxx_options.threads = 1;
        tricell::BatchList cxx;
        tricell::compute_neighbors_batch(b.cxx, cxx_options, cxx);

        ASSERT_EQ(view.structures, b.c.size());
        expect_same_array(cxx.pair_offsets(), view.pair_offsets, b.c.size() + 1);
        expect_same_array(cxx.atom_offsets(), view.atom_offsets, b.c.size() + 1);
        const tricell_pairs& p = view.pairs;
        ASSERT_EQ(p.size, cxx.size());
        expect_same_array(cxx.i(), p.i, p.size);
        expect_same_array(cxx.j(), p.j, p.size);
        expect_same_array(cxx.shifts(), p.shifts, 3 * p.size);
        expect_same_array(cxx.distances(), p.distances, p.size);
        expect_same_array(cxx.vectors(), p.vectors, 3 * p.size);
        ASSERT_EQ(p.offsets != nullptr, cxx_options.with_offsets());
        if (cxx_options.with_offsets() && !cxx.offsets().empty()) {
            ASSERT_EQ(p.atoms, cxx.atom_offsets().back());
            expect_same_array(cxx.offsets(), p.offsets, p.atoms + 1);
        }

        // Each structure's slice against the oracle.
        for (std::size_t s = 0; s < b.systems.size(); ++s) {
            SCOPED_TRACE(s);
            const RandomSystem& sys = b.systems[s];
            const std::size_t from = view.pair_offsets[s], to = view.pair_offsets[s + 1];
            tricell_pairs slice = p;
            slice.size = to - from;
            slice.i += from;
            slice.j += from;
            slice.shifts += 3 * from;
            slice.distances += from;
            slice.vectors += 3 * from;
            PairMap expected = brute_force_pairs(sys.box(), sys.positions, o.cutoff);
            if (o.half == 1) {
                expected = canonical_half(expected);
            }
            expect_same_pairs(expected, to_map(slice), o.cutoff, tolerance(sys));
            pairs_seen += slice.size;
            ++structures_seen;
        }
    }
    EXPECT_GT(pairs_seen, 1000u);                // the batches are not all trivially empty
    EXPECT_GT(structures_seen, 2 * batch_count); // 0 to 8 structures a batch
}

TEST(CApiBatch, EveryValidationBranch) {
    auto list = make_batch();
    const Batch b = random_batch(3);
    ASSERT_GE(b.c.size(), 2u);
    tricell_neighbor_options o;
    ASSERT_EQ(tricell_neighbor_options_init(&o), TRICELL_OK);
    o.cutoff = b.systems.front().cutoff;
    // A good call first, so that each failure below is seen to empty the list.
    auto fill = [&] {
        ASSERT_EQ(tricell_neighbors_batch(b.c.data(), b.c.size(), &o, list.get()), TRICELL_OK);
        tricell_batch_pairs view;
        ASSERT_EQ(tricell_batch_list_pairs(list.get(), &view), TRICELL_OK);
        ASSERT_GT(view.pairs.size, 0u);
    };
    auto expect_empty = [&] {
        tricell_batch_pairs view;
        ASSERT_EQ(tricell_batch_list_pairs(list.get(), &view), TRICELL_OK);
        EXPECT_EQ(view.structures, 0u);
        EXPECT_EQ(view.pairs.size, 0u);
    };

    EXPECT_STATUS(tricell_batch_list_create(nullptr), TRICELL_ERROR_INVALID_ARGUMENT,
                  "tricell_batch_list_create: list must not be NULL");
    EXPECT_STATUS(tricell_neighbors_batch(b.c.data(), b.c.size(), &o, nullptr),
                  TRICELL_ERROR_INVALID_ARGUMENT, "tricell_neighbors_batch: list must not be NULL");
    tricell_batch_pairs view;
    EXPECT_STATUS(tricell_batch_list_pairs(nullptr, &view), TRICELL_ERROR_INVALID_ARGUMENT,
                  "tricell_batch_list_pairs: list must not be NULL");
    EXPECT_STATUS(tricell_batch_list_pairs(list.get(), nullptr), TRICELL_ERROR_INVALID_ARGUMENT,
                  "tricell_batch_list_pairs: pairs must not be NULL");

    fill();
    EXPECT_STATUS(tricell_neighbors_batch(b.c.data(), b.c.size(), nullptr, list.get()),
                  TRICELL_ERROR_INVALID_ARGUMENT,
                  "tricell_neighbors_batch: options must not be NULL");
    expect_empty();
    fill();
    EXPECT_STATUS(tricell_neighbors_batch(nullptr, 2, &o, list.get()),
                  TRICELL_ERROR_INVALID_ARGUMENT,
                  "tricell_neighbors_batch: structures must not be NULL");
    expect_empty();
    EXPECT_STATUS(tricell_neighbors_batch(nullptr, 0, &o, list.get()), TRICELL_OK, "");
    expect_empty();

    // Options: per-atom arrays refused, flags checked, values left to the C++ validation.
    const double radii[2] = {1, 1};
    const std::int32_t species[2] = {1, 1};
    for (int which = 0; which < 2; ++which) {
        fill();
        tricell_neighbor_options per_atom = o;
        if (which == 0) {
            per_atom.radii = radii;
        } else {
            per_atom.species = species;
        }
        EXPECT_STATUS(tricell_neighbors_batch(b.c.data(), b.c.size(), &per_atom, list.get()),
                      TRICELL_ERROR_INVALID_ARGUMENT,
                      "tricell_neighbors_batch: options.radii and options.species must be NULL "
                      "(one set of options serves every structure of a batch)");
        expect_empty();
    }
    fill();
    tricell_neighbor_options bad = o;
    bad.sorted = 2;
    EXPECT_STATUS(tricell_neighbors_batch(b.c.data(), b.c.size(), &bad, list.get()),
                  TRICELL_ERROR_INVALID_ARGUMENT, "options.sorted must be 0 or 1 (got 2)");
    expect_empty();
    fill();
    bad = o;
    bad.grouped = -1;
    EXPECT_STATUS(tricell_neighbors_batch(b.c.data(), b.c.size(), &bad, list.get()),
                  TRICELL_ERROR_INVALID_ARGUMENT, "options.grouped must be 0 or 1 (got -1)");
    expect_empty();
    fill();
    bad = o;
    bad.cutoff = -1.5;
    tricell::NeighborOptions cxx_bad;
    cxx_bad.cutoff = -1.5;
    std::string expected;
    try {
        cxx_bad.validate();
    } catch (const tricell::Error& e) {
        expected = e.what();
    }
    ASSERT_FALSE(expected.empty());
    EXPECT_STATUS(tricell_neighbors_batch(b.c.data(), b.c.size(), &bad, list.get()),
                  TRICELL_ERROR_INVALID_ARGUMENT, expected);
    expect_empty();
    fill();
    bad = o;
    bad.max_pairs = 1;
    tricell::NeighborOptions cxx_max;
    cxx_max.cutoff = o.cutoff;
    cxx_max.max_pairs = 1;
    tricell::BatchList cxx_list;
    expected.clear();
    try {
        tricell::compute_neighbors_batch(b.cxx, cxx_max, cxx_list);
    } catch (const tricell::PairLimitError& e) {
        expected = e.subject(); // "structure s: ..." or the batch's total
    }
    ASSERT_FALSE(expected.empty());
    EXPECT_STATUS(tricell_neighbors_batch(b.c.data(), b.c.size(), &bad, list.get()),
                  TRICELL_ERROR_INVALID_ARGUMENT,
                  expected +
                      ", more than max_pairs = 1; raise tricell_neighbor_options.max_pairs to "
                      "allow it");
    expect_empty();

    // Per structure: a hand-written bad box, a singular one, NULL or non-finite positions;
    // the message names the structure (the lowest one when several are bad).
    std::vector<tricell_structure> c = b.c;
    c[1].box.periodic[2] = 3;
    fill();
    EXPECT_STATUS(tricell_neighbors_batch(c.data(), c.size(), &o, list.get()),
                  TRICELL_ERROR_INVALID_ARGUMENT,
                  "structure 1: periodic[2] must be 0 or 1 (got 3)");
    expect_empty();
    c = b.c;
    for (int k = 0; k < 3; ++k) {
        c[1].box.vectors[1][k] = c[1].box.vectors[0][k]; // a == b, both periodic: singular
        c[1].box.periodic[k] = 1;
    }
    std::string singular;
    try {
        const Eigen::Matrix3d rows =
            Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(&c[1].box.vectors[0][0]);
        tricell::Box::from_rows(rows, tricell::Periodicity::all());
    } catch (const tricell::Error& e) {
        singular = e.what();
    }
    ASSERT_FALSE(singular.empty());
    fill();
    EXPECT_STATUS(tricell_neighbors_batch(c.data(), c.size(), &o, list.get()),
                  TRICELL_ERROR_GEOMETRY, "structure 1: " + singular);
    expect_empty();
    c = b.c;
    c[1].positions = nullptr;
    c[1].n = 3;
    fill();
    EXPECT_STATUS(tricell_neighbors_batch(c.data(), c.size(), &o, list.get()),
                  TRICELL_ERROR_INVALID_ARGUMENT, "structure 1: positions: null data for 3 points");
    expect_empty();
    std::vector<double> nan_xyz = {0, std::numeric_limits<double>::quiet_NaN(), 0};
    c = b.c;
    c[1].positions = nan_xyz.data();
    c[1].n = 1;
    c[0].positions = nullptr;
    c[0].n = 2;
    fill();
    EXPECT_STATUS(tricell_neighbors_batch(c.data(), c.size(), &o, list.get()),
                  TRICELL_ERROR_INVALID_ARGUMENT, "structure 0: positions: null data for 2 points");
    expect_empty();
    c[0] = b.c[0];
    fill();
    EXPECT_STATUS(tricell_neighbors_batch(c.data(), c.size(), &o, list.get()),
                  TRICELL_ERROR_INVALID_ARGUMENT,
                  "structure 1: position 0 is not finite (got 0, nan, 0)");
    expect_empty();
}
