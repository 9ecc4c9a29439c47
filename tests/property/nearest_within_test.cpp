// The k nearest within the cutoff (NeighborOptions::max_neighbors, tie_tolerance, symmetric)
// against its definition applied to the full list: each centre's pairs sorted by (d, j, S), the
// first k kept, with a tie tolerance every other pair with d <= d_k + tolerance, with the
// symmetric rule every kept pair's reverse, each centre's kept pairs in (d, j, S) order. Random
// systems and perfect crystals (many exactly equal distances), every backend of the registry,
// 1 to 4 threads, random quantities; the list must equal the definition's entry for entry, bit
// for bit.
#include <algorithm>
#include <array>
#include <cstdint>
#include <cstring>
#include <map>
#include <ostream>
#include <random>
#include <set>
#include <tuple>
#include <vector>

#include <gtest/gtest.h>

#include "support/expect_throw_msg.hpp"
#include "support/random_systems.hpp"
#include "tricell/batch.hpp"
#include "tricell/error.hpp"
#include "tricell/neighbor_list.hpp"
#include "tricell/verlet.hpp"

using tricell::Box;
using tricell::NeighborList;
using tricell::NeighborOptions;
using tricell::SearchBackend;
using tricell::testing::RandomSystem;

namespace {

#ifdef TRICELL_PROPERTY_CASES
constexpr std::uint64_t case_count = TRICELL_PROPERTY_CASES / 4;
#else
constexpr std::uint64_t case_count = 250;
#endif

// One entry of a list: i, j, S, and the bits of d and D.
struct Entry {
    std::uint32_t i, j;
    std::array<int, 3> s;
    double d;
    std::array<double, 3> v;
    bool operator==(const Entry& o) const {
        return i == o.i && j == o.j && s == o.s && std::memcmp(&d, &o.d, sizeof d) == 0 &&
               std::memcmp(v.data(), o.v.data(), sizeof v) == 0;
    }
};
std::ostream& operator<<(std::ostream& os, const Entry& e) {
    return os << "(" << e.i << ", " << e.j << ", [" << e.s[0] << " " << e.s[1] << " " << e.s[2]
              << "], d " << e.d << ")";
}

std::tuple<double, std::uint32_t, std::array<int, 3>> rank(const Entry& e) {
    return {e.d, e.j, e.s};
}

// The definition, on a full list with S, d and D.
std::vector<std::vector<Entry>> expected_nearest(const NeighborList& full, std::size_t atoms,
                                                 std::size_t k, double tolerance, bool symmetric) {
    std::vector<std::vector<Entry>> by_centre(atoms);
    for (std::size_t p = 0; p < full.size(); ++p) {
        const tricell::Shift s = full.shift(p);
        const Eigen::Vector3d v = full.vector(p);
        by_centre[full.i()[p]].push_back(Entry{
            full.i()[p], full.j()[p], {s[0], s[1], s[2]}, full.distances()[p], {v[0], v[1], v[2]}});
    }
    using Key = std::tuple<std::uint32_t, std::uint32_t, std::array<int, 3>>;
    std::set<Key> kept;
    std::map<Key, Entry> all;
    for (auto& pairs : by_centre) {
        std::sort(pairs.begin(), pairs.end(),
                  [](const Entry& l, const Entry& r) { return rank(l) < rank(r); });
        for (std::size_t t = 0; t < pairs.size(); ++t) {
            const Entry& e = pairs[t];
            all[Key{e.i, e.j, e.s}] = e;
            const bool within_k = t < k;
            const bool tied =
                pairs.size() > k && tolerance > 0 && e.d <= pairs[k - 1].d + tolerance;
            if (within_k || tied) {
                kept.insert(Key{e.i, e.j, e.s});
            }
        }
    }
    if (symmetric) {
        for (const Key& key : std::set<Key>(kept)) {
            const auto& [i, j, s] = key;
            kept.insert(Key{j, i, {-s[0], -s[1], -s[2]}});
        }
    }
    std::vector<std::vector<Entry>> out(atoms);
    for (const Key& key : kept) {
        const auto found = all.find(key);
        EXPECT_NE(found, all.end()) << "a reverse pair missing from the full list";
        if (found != all.end()) {
            out[std::get<0>(key)].push_back(found->second);
        }
    }
    for (auto& pairs : out) {
        std::sort(pairs.begin(), pairs.end(),
                  [](const Entry& l, const Entry& r) { return rank(l) < rank(r); });
    }
    return out;
}

// A perfect crystal: a conventional cubic cell (simple cubic, bcc, fcc or diamond) repeated
// 1 to 3 times, atoms on exact multiples of the fractional positions: many equal distances.
RandomSystem crystal(std::uint64_t seed) {
    std::mt19937_64 rng(seed);
    const std::vector<std::vector<Eigen::Vector3d>> bases = {
        {{0, 0, 0}},
        {{0, 0, 0}, {0.5, 0.5, 0.5}},
        {{0, 0, 0}, {0.5, 0.5, 0}, {0.5, 0, 0.5}, {0, 0.5, 0.5}},
        {{0, 0, 0},
         {0.5, 0.5, 0},
         {0.5, 0, 0.5},
         {0, 0.5, 0.5},
         {0.25, 0.25, 0.25},
         {0.75, 0.75, 0.25},
         {0.75, 0.25, 0.75},
         {0.25, 0.75, 0.75}}};
    const auto& basis = bases[seed % bases.size()];
    const int repeat = 1 + int(rng() % 3);
    const double a = 2.5 + 0.5 * double(rng() % 4);
    RandomSystem sys;
    sys.kind = "crystal";
    sys.h = a * repeat * Eigen::Matrix3d::Identity();
    sys.pbc = tricell::Periodicity::all();
    for (int x = 0; x < repeat; ++x) {
        for (int y = 0; y < repeat; ++y) {
            for (int z = 0; z < repeat; ++z) {
                for (const Eigen::Vector3d& b : basis) {
                    sys.positions.push_back(a * (b + Eigen::Vector3d(x, y, z)));
                }
            }
        }
    }
    sys.cutoff = a * (1.0 + 0.6 * double(rng() % 3));
    return sys;
}

std::vector<SearchBackend> backends() {
    return tricell::search_backends();
}

} // namespace

TEST(NearestWithin, EqualsTheDefinitionOnTheFullList_RandomSystemsAndCrystals) {
    std::size_t kept_pairs = 0, pruned_centres = 0, tolerance_cases = 0, symmetric_cases = 0,
                boundary_cases = 0;
    for (std::uint64_t seed = 0; seed < case_count; ++seed) {
        const RandomSystem sys =
            seed % 3 == 2 ? crystal(seed) : tricell::testing::random_system(seed);
        const std::size_t n = sys.positions.size();
        std::mt19937_64 rng(seed * 977 + 3);
        SCOPED_TRACE(testing::Message() << "seed " << seed << " (" << sys.kind << "), N " << n);
        NeighborOptions full_options;
        full_options.cutoff = sys.cutoff;
        full_options.quantities.vectors = true;
        full_options.backend = SearchBackend::dense;
        full_options.sorted = true; // centre 0 first
        const NeighborList full =
            tricell::compute_neighbors(sys.box(), sys.positions, full_options);

        NeighborOptions o;
        o.cutoff = sys.cutoff;
        o.max_neighbors = 1 + rng() % (rng() % 2 == 0 ? 4 : 30);
        o.tie_tolerance = rng() % 3 == 0 ? 0.0 : (rng() % 2 == 0 ? 1e-9 : 0.05 * sys.cutoff);
        o.symmetric = rng() % 2 == 0;
        o.threads = 1 + int(rng() % 4);
        o.quantities.vectors = true;
        if (sys.kind == "crystal" && o.tie_tolerance > 0 && rng() % 2 == 0) {
            // A tolerance that reaches exactly a farther distance of centre 0 (d_m - d_k is
            // exact for d_k <= d_m <= 2 d_k): the rule's boundary, d <= d_k + tolerance.
            std::vector<double> d;
            for (std::size_t p = 0; p < full.size() && full.i()[p] == 0; ++p) {
                d.push_back(full.distances()[p]);
            }
            std::sort(d.begin(), d.end());
            if (d.size() > o.max_neighbors) {
                const double kth = d[o.max_neighbors - 1];
                const auto farther = std::upper_bound(d.begin(), d.end(), kth);
                if (farther != d.end() && *farther <= 2 * kth) {
                    o.tie_tolerance = *farther - kth;
                    ++boundary_cases;
                }
            }
        }
        const auto expected =
            expected_nearest(full, n, o.max_neighbors, o.tie_tolerance, o.symmetric);
        tolerance_cases += o.tie_tolerance > 0;
        symmetric_cases += o.symmetric;
        for (std::size_t c = 0; c < n; ++c) {
            pruned_centres +=
                full.size() > 0 &&
                expected[c].size() < std::size_t(std::count(full.i().begin(), full.i().end(), c));
        }
        for (const SearchBackend backend : backends()) {
            if (backend == SearchBackend::direct && n > 40) {
                continue;
            }
            SCOPED_TRACE(tricell::backend_name(backend));
            o.backend = backend;
            const NeighborList got = tricell::compute_neighbors(sys.box(), sys.positions, o);
            ASSERT_EQ(got.offsets().size(), n + 1);
            std::size_t at = 0;
            for (std::size_t c = 0; c < n; ++c) {
                ASSERT_EQ(got.offsets()[c], at);
                for (const Entry& e : expected[c]) {
                    ASSERT_LT(at, got.size());
                    const tricell::Shift s = got.shift(at);
                    const Eigen::Vector3d v = got.vector(at);
                    const Entry g{got.i()[at],
                                  got.j()[at],
                                  {s[0], s[1], s[2]},
                                  got.distances()[at],
                                  {v[0], v[1], v[2]}};
                    ASSERT_EQ(g, e) << "entry " << at;
                    ++at;
                }
                if (!o.symmetric && o.tie_tolerance == 0) {
                    ASSERT_LE(got.offsets()[c + 1] - got.offsets()[c], o.max_neighbors);
                }
            }
            ASSERT_EQ(got.size(), at);
            kept_pairs += at;
        }
    }
    // The cases are not trivial: centres lose pairs, tolerances and the symmetric rule bite.
    EXPECT_GT(kept_pairs, 10000u);
    EXPECT_GT(pruned_centres, 500u);
    EXPECT_GT(tolerance_cases, case_count / 3);
    EXPECT_GT(symmetric_cases, case_count / 3);
    EXPECT_GT(boundary_cases, case_count / 40);
}

// Quantities not asked for stay empty (d and S are ranked on internally), a batch gives each
// structure what a call gives it alone.
TEST(NearestWithin, QuantitiesAndBatch) {
    const RandomSystem sys = crystal(6);
    NeighborOptions o;
    o.cutoff = sys.cutoff;
    o.max_neighbors = 5;
    o.quantities.shifts = false;
    o.quantities.distances = false;
    const NeighborList ij = tricell::compute_neighbors(sys.box(), sys.positions, o);
    EXPECT_TRUE(ij.shifts().empty());
    EXPECT_TRUE(ij.distances().empty());
    o.quantities = tricell::Quantities{};
    const NeighborList all = tricell::compute_neighbors(sys.box(), sys.positions, o);
    EXPECT_EQ(ij.i(), all.i());
    EXPECT_EQ(ij.j(), all.j());
    EXPECT_EQ(ij.offsets(), all.offsets());
    EXPECT_EQ(all.size(), 5 * sys.positions.size());

    std::vector<tricell::BatchStructure> structures;
    std::vector<RandomSystem> systems;
    for (std::uint64_t seed = 0; seed < 12; ++seed) {
        systems.push_back(seed % 2 == 0 ? crystal(seed) : tricell::testing::random_system(seed));
    }
    for (const RandomSystem& s : systems) {
        structures.push_back({s.box(), s.positions});
    }
    o.cutoff = 2.0;
    o.symmetric = true;
    o.tie_tolerance = 0.01;
    o.threads = 3;
    tricell::BatchList batch;
    tricell::compute_neighbors_batch(structures, o, batch);
    for (std::size_t s = 0; s < systems.size(); ++s) {
        NeighborOptions alone = o;
        alone.threads = 1;
        const NeighborList list =
            tricell::compute_neighbors(systems[s].box(), systems[s].positions, alone);
        const std::size_t first = batch.pair_offsets()[s];
        ASSERT_EQ(batch.pair_offsets()[s + 1] - first, list.size());
        for (std::size_t k = 0; k < list.size(); ++k) {
            ASSERT_EQ(batch.j()[first + k], list.j()[k]);
            ASSERT_EQ(batch.distances()[first + k], list.distances()[k]);
        }
    }
}

TEST(NearestWithin, RefusesWhatItCannotDefine) {
    const RandomSystem sys = crystal(1);
    NeighborOptions o;
    o.cutoff = sys.cutoff;
    o.max_neighbors = 4;
    o.half = true;
    EXPECT_THROW_MSG(tricell::compute_neighbors(sys.box(), sys.positions, o),
                     tricell::InvalidArgument,
                     "max_neighbors keeps the nearest pairs of each centre of a full list: half "
                     "must be false");
    o.half = false;
    o.sorted = true;
    EXPECT_THROW_MSG(tricell::compute_neighbors(sys.box(), sys.positions, o),
                     tricell::InvalidArgument,
                     "max_neighbors orders each centre's pairs by distance (d, j, S): sorted (by "
                     "j, S) cannot be asked with it");
    o.sorted = false;
    o.tie_tolerance = -0.5;
    EXPECT_THROW_MSG(tricell::compute_neighbors(sys.box(), sys.positions, o),
                     tricell::InvalidArgument, "tie_tolerance must be finite and >= 0 (got -0.5)");
    o.tie_tolerance = 0;
    o.symmetric = true;
    o.query = std::vector<std::uint32_t>{0};
    EXPECT_THROW_MSG(tricell::compute_neighbors(sys.box(), sys.positions, o),
                     tricell::InvalidArgument,
                     "symmetric needs every atom's pairs (the other end of a kept pair decides): "
                     "query cannot be asked with it");
    o.query.reset();
    o.max_neighbors = 0;
    EXPECT_THROW_MSG(tricell::compute_neighbors(sys.box(), sys.positions, o),
                     tricell::InvalidArgument,
                     "symmetric applies to the nearest pairs kept: set max_neighbors too");
    o.symmetric = false;
    o.max_neighbors = 3;
    tricell::NeighborSearch search;
    search.build(sys.box(), sys.positions, o);
    EXPECT_THROW_MSG(search.for_each_pair([](const tricell::Pair&) {}), tricell::InvalidArgument,
                     "for_each_pair() visits the whole list: max_neighbors");
    tricell::VerletOptions verlet;
    verlet.neighbors = o;
    verlet.skin = 0.1;
    EXPECT_THROW_MSG(verlet.validate(), tricell::InvalidArgument,
                     "the Verlet list keeps every pair within the cutoff: max_neighbors is for "
                     "NeighborSearch");
}

// A query's centres keep what they keep in the whole list (non-symmetric: each centre decides
// alone); the other atoms have no pairs.
TEST(NearestWithin, AQueryKeepsItsCentresPairs) {
    for (std::uint64_t seed = 0; seed < 40; ++seed) {
        const RandomSystem sys =
            seed % 2 == 0 ? crystal(seed) : tricell::testing::random_system(seed);
        const std::size_t n = sys.positions.size();
        if (n == 0) {
            continue;
        }
        SCOPED_TRACE(seed);
        NeighborOptions o;
        o.cutoff = sys.cutoff;
        o.max_neighbors = 1 + seed % 9;
        o.tie_tolerance = seed % 3 == 0 ? 0.2 : 0.0;
        const NeighborList whole = tricell::compute_neighbors(sys.box(), sys.positions, o);
        std::vector<std::uint32_t> query;
        for (std::uint32_t a = 0; a < n; a += 1 + std::uint32_t(seed % 3)) {
            query.push_back(a);
        }
        o.query = query;
        const NeighborList part = tricell::compute_neighbors(sys.box(), sys.positions, o);
        ASSERT_EQ(part.offsets().size(), n + 1);
        std::size_t at = 0;
        for (std::uint32_t a = 0; a < n; ++a) {
            const bool asked = std::find(query.begin(), query.end(), a) != query.end();
            const std::size_t count = part.offsets()[a + 1] - part.offsets()[a];
            ASSERT_EQ(count, asked ? whole.offsets()[a + 1] - whole.offsets()[a] : 0u);
            for (std::size_t t = 0; t < count; ++t, ++at) {
                const std::size_t w = whole.offsets()[a] + t;
                ASSERT_EQ(part.j()[at], whole.j()[w]);
                ASSERT_EQ(part.shift(at), whole.shift(w));
                ASSERT_EQ(part.distances()[at], whole.distances()[w]);
            }
        }
    }
}
