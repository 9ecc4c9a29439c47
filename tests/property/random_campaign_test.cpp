// The random campaign: seeded random systems of up to 10^5 atoms (uniform, clustered, slabs,
// droplets; mild, skewed, strongly skewed and left-handed cells; every periodicity; atoms on
// faces, coincident, or hundreds of boxes outside; cutoffs from tiny to several boxes; per-atom
// radii and species tables; full and half, plain, grouped and sorted lists; 1 to 8 threads and
// random tuning knobs) from tests/support/random_systems.hpp. For each system and options every
// backend of the registry (search_backends()) gives the same list as the dense one: the same
// (i, j, S) multiset with bit-identical d and D, compared as sorted lists. Systems of up to a few
// hundred atoms are checked against the brute-force oracle (tests/support/brute_force.hpp) as
// well, and sorted and grouped lists against their order and offsets.
//
// The test suite runs fixed seeds and bounded counts (fewer and smaller systems in the sanitizer
// build). The environment replays or extends a run: TRICELL_CAMPAIGN_SEED (the campaign's seed),
// TRICELL_CAMPAIGN_FIRST (the first system index) and TRICELL_CAMPAIGN_SYSTEMS (how many);
// scripts/random-campaign.sh runs the Mixed test with fresh seeds. Every failure names the seed
// and system index, and each test prints the systems, pairs compared and oracle-checked systems.
#include <algorithm>
#include <array>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <iostream>
#include <random>
#include <string>
#include <tuple>
#include <vector>

#include <gtest/gtest.h>

#include "support/brute_force.hpp"
#include "support/random_systems.hpp"
#include "tricell/neighbor_list.hpp"

using tricell::NeighborList;
using tricell::NeighborOptions;
using tricell::SearchBackend;
using tricell::testing::CampaignSystem;
using tricell::testing::PairMap;

namespace {

// The sanitizer build (TRICELL_CAMPAIGN_SANITIZED from tests/CMakeLists.txt) runs fewer and
// smaller systems.
#ifdef TRICELL_CAMPAIGN_SANITIZED
constexpr std::uint64_t small_count = 120, medium_count = 8, large_count = 1, mixed_count = 12;
constexpr std::size_t large_min = 20000, large_max = 30000, direct_limit = 300;
#else
constexpr std::uint64_t small_count = 200, medium_count = 20, large_count = 2, mixed_count = 20;
constexpr std::size_t large_min = 80000, large_max = 100000, direct_limit = 1000;
#endif
constexpr std::size_t oracle_limit = 400;

std::uint64_t from_environment(const char* name, std::uint64_t fallback) {
    const char* text = std::getenv(name);
    return text != nullptr && *text != '\0' ? std::strtoull(text, nullptr, 0) : fallback;
}

// The seed of system `index` of a campaign (splitmix64), so that one system replays alone.
std::uint64_t system_seed(std::uint64_t campaign, std::uint64_t index) {
    std::uint64_t z = campaign + 0x9e3779b97f4a7c15ULL * (index + 1);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    return z ^ (z >> 31);
}

struct Totals {
    std::uint64_t systems = 0;
    std::uint64_t pairs = 0; // pairs compared, over every backend against the dense one
    std::uint64_t oracle = 0;
};

// One entry of a list with its bits: equal entries are equal bit for bit.
using Entry = std::tuple<std::uint32_t, std::uint32_t, std::int32_t, std::int32_t, std::int32_t,
                         std::uint64_t, std::uint64_t, std::uint64_t, std::uint64_t>;

std::uint64_t bits(double x) {
    std::uint64_t b;
    std::memcpy(&b, &x, sizeof b);
    return b;
}

std::vector<Entry> sorted_entries(const NeighborList& list) {
    std::vector<Entry> out(list.size());
    for (std::size_t k = 0; k < list.size(); ++k) {
        const std::int32_t* s = list.shifts().data() + 3 * k;
        const double* v = list.vectors().data() + 3 * k;
        out[k] = Entry{list.i()[k], list.j()[k], s[0],      s[1], s[2], bits(list.distances()[k]),
                       bits(v[0]),  bits(v[1]),  bits(v[2])};
    }
    std::sort(out.begin(), out.end());
    return out;
}

std::string describe(const Entry& e) {
    return testing::PrintToString(std::get<0>(e)) + " -> " +
           testing::PrintToString(std::get<1>(e)) + " S=(" + std::to_string(std::get<2>(e)) + "," +
           std::to_string(std::get<3>(e)) + "," + std::to_string(std::get<4>(e)) + ")";
}

// The order and offsets a sorted or grouped list promises.
void check_layout(const NeighborList& list, const NeighborOptions& o, std::size_t atoms) {
    if (!o.with_offsets()) {
        EXPECT_TRUE(list.offsets().empty());
        return;
    }
    ASSERT_EQ(list.offsets().size(), atoms + 1);
    ASSERT_EQ(list.offsets().front(), 0u);
    ASSERT_EQ(list.offsets().back(), list.size());
    for (std::size_t a = 0; a < atoms; ++a) {
        for (std::size_t k = list.offsets()[a]; k < list.offsets()[a + 1]; ++k) {
            ASSERT_EQ(list.i()[k], a) << "pair " << k;
        }
    }
    if (o.sorted) {
        for (std::size_t k = 1; k < list.size(); ++k) {
            const auto key = [&](std::size_t p) {
                const Eigen::Vector3i s = list.shift(p);
                return std::make_tuple(list.i()[p], list.j()[p], s[0], s[1], s[2]);
            };
            ASSERT_LT(key(k - 1), key(k)) << "sorted list out of order at pair " << k;
        }
    }
}

// The list against the oracle: the same (i, j, S) with d and D within `tol`; an entry may be
// missing from one side only when its d is within `tol` of its cutoff (rounding decides it).
template <class CutoffOf>
void check_oracle(const PairMap& expected, const PairMap& actual, double tol,
                  const CutoffOf& cutoff_of) {
    int reported = 0;
    auto near_cutoff = [&](const tricell::testing::PairKey& key, double d) {
        return std::abs(d - cutoff_of(std::get<0>(key), std::get<1>(key))) <= tol;
    };
    for (const auto& [key, value] : expected) {
        const auto found = actual.find(key);
        if (found == actual.end()) {
            if (!near_cutoff(key, value.distance) && reported++ < 5) {
                ADD_FAILURE() << "oracle pair missing: i=" << std::get<0>(key)
                              << " j=" << std::get<1>(key) << " S=(" << std::get<2>(key) << ","
                              << std::get<3>(key) << "," << std::get<4>(key)
                              << ") d=" << value.distance;
            }
        } else if ((std::abs(found->second.distance - value.distance) > tol ||
                    (found->second.vector - value.vector).norm() > tol) &&
                   reported++ < 5) {
            ADD_FAILURE() << "distance differs from the oracle: " << found->second.distance
                          << " vs " << value.distance;
        }
    }
    for (const auto& [key, value] : actual) {
        if (expected.count(key) == 0 && !near_cutoff(key, value.distance) && reported++ < 5) {
            ADD_FAILURE() << "pair not in the oracle: i=" << std::get<0>(key)
                          << " j=" << std::get<1>(key) << " S=(" << std::get<2>(key) << ","
                          << std::get<3>(key) << "," << std::get<4>(key)
                          << ") d=" << value.distance;
        }
    }
}

// One set of options for a system: the cutoff rule, the list's form, threads and knobs.
struct Variant {
    NeighborOptions options;
    std::string name;
    std::vector<std::array<double, 3>> table; // species table as (a, b, cutoff), for the oracle
};

Variant random_variant(std::mt19937_64& rng, const CampaignSystem& sys) {
    auto integer = [&](int lo, int hi) { return std::uniform_int_distribution<int>(lo, hi)(rng); };
    std::uniform_real_distribution<double> unit(0, 1);
    Variant v;
    NeighborOptions& o = v.options;
    o.quantities.vectors = true;
    const std::size_t n = sys.positions.size();
    const int rule = integer(0, 5);
    if (rule == 0) {
        v.name = "radii";
        o.radii.resize(n);
        for (double& r : o.radii) {
            r = integer(0, 9) == 0 ? 0.0 : (0.2 + 0.4 * unit(rng)) * sys.cutoff;
        }
    } else if (rule == 1) {
        v.name = "species";
        o.species.resize(n);
        for (auto& s : o.species) {
            s = std::int32_t(integer(0, 2));
        }
        // (0, 2) and (2, 2) are missing from the table: such pairs never count.
        for (const auto& [a, b] : {std::pair<int, int>{0, 0}, {0, 1}, {1, 1}, {1, 2}}) {
            const double c = (0.4 + 0.8 * unit(rng)) * sys.cutoff;
            o.species_cutoffs.push_back({a, b, c});
            v.table.push_back({double(a), double(b), c});
        }
    } else {
        v.name = "cutoff";
        o.cutoff = sys.cutoff;
    }
    o.half = integer(0, 1) == 1;
    const int form = integer(0, 2);
    o.sorted = form == 1;
    o.grouped = form == 2;
    o.threads = integer(1, 8);
    o.cells_per_cutoff = 1 + integer(0, 2);
    if (n <= 2000 && integer(0, 5) == 0) {
        o.max_cells = std::size_t(integer(1, 64)); // the dense grid's cap bites (quadratic)
    }
    if (integer(0, 3) == 0) {
        // collisions everywhere (a lookup walks cells / slots: small systems only)
        o.hash_table_size = std::size_t(n <= 2000 ? integer(1, 7) : integer(int(n / 64), int(n)));
    }
    if (integer(0, 1) == 0) {
        o.leaf_size = std::size_t(integer(n <= 2000 ? 1 : 8, 32));
    }
    o.reduce_cell = integer(0, 4) != 0;
    v.name += o.half ? ", half" : ", full";
    v.name += o.sorted ? ", sorted" : o.grouped ? ", grouped" : "";
    v.name += ", " + std::to_string(o.threads) + " threads";
    return v;
}

void check_variants(const CampaignSystem& sys, std::uint64_t seed, Totals& totals);

void check_system(const char* test, std::uint64_t campaign, std::uint64_t index,
                  const CampaignSystem& sys, Totals& totals) {
    SCOPED_TRACE(testing::Message()
                 << "campaign seed " << campaign << ", system " << index << " (" << sys.kind << ", "
                 << sys.positions.size() << " atoms, cutoff " << sys.cutoff
                 << "); replay with TRICELL_CAMPAIGN_SEED=" << campaign
                 << " TRICELL_CAMPAIGN_FIRST=" << index
                 << " TRICELL_CAMPAIGN_SYSTEMS=1 --gtest_filter=RandomCampaign." << test);
    try {
        check_variants(sys, system_seed(campaign, index), totals);
    } catch (const std::exception& e) { // reported here, with the trace that replays it
        ADD_FAILURE() << "threw: " << e.what();
    }
}

// Every backend against the dense one under a few random variants of the options.
void check_variants(const CampaignSystem& sys, std::uint64_t seed, Totals& totals) {
    const std::size_t n = sys.positions.size();
    std::mt19937_64 rng(seed ^ 0x5eed);
    const int variants = n <= oracle_limit ? 3 : n <= 20000 ? 2 : 1;
    const tricell::Box box = sys.box();
    double scale = 1;
    for (const auto& x : sys.positions) {
        scale = std::max(scale, x.cwiseAbs().maxCoeff());
    }
    for (int k = 0; k < variants; ++k) {
        const Variant v = random_variant(rng, sys);
        SCOPED_TRACE("options: " + v.name);
        NeighborOptions o = v.options;
        o.backend = SearchBackend::dense;
        const NeighborList reference = tricell::compute_neighbors(box, sys.positions, o);
        check_layout(reference, o, n);
        const std::vector<Entry> expected = sorted_entries(reference);
        for (const SearchBackend backend : tricell::search_backends()) {
            if (backend == SearchBackend::dense ||
                (backend == SearchBackend::direct && n > direct_limit)) {
                continue;
            }
            SCOPED_TRACE(std::string("backend ") + tricell::backend_name(backend));
            o.backend = backend;
            const NeighborList list = tricell::compute_neighbors(box, sys.positions, o);
            check_layout(list, o, n);
            const std::vector<Entry> actual = sorted_entries(list);
            totals.pairs += actual.size();
            if (actual != expected) {
                const auto diff =
                    std::mismatch(expected.begin(), expected.end(), actual.begin(), actual.end());
                ADD_FAILURE() << "differs from dense: " << actual.size() << " pairs vs "
                              << expected.size() << "; first difference: dense "
                              << (diff.first == expected.end() ? "(end)" : describe(*diff.first))
                              << ", this "
                              << (diff.second == actual.end() ? "(end)" : describe(*diff.second));
                return;
            }
        }
        if (n <= oracle_limit) {
            const auto cutoff_of = [&](std::uint32_t i, std::uint32_t j) {
                if (!o.radii.empty()) {
                    return o.radii[i] + o.radii[j];
                }
                if (!o.species.empty()) {
                    const double a = std::min(o.species[i], o.species[j]);
                    const double b = std::max(o.species[i], o.species[j]);
                    for (const auto& row : v.table) {
                        if (row[0] == a && row[1] == b) {
                            return row[2];
                        }
                    }
                    return 0.0;
                }
                return o.cutoff;
            };
            double largest = o.cutoff;
            for (const double r : o.radii) {
                largest = std::max(largest, 2 * r);
            }
            for (const auto& row : v.table) {
                largest = std::max(largest, row[2]);
            }
            PairMap oracle = tricell::testing::brute_force_pairs(box, sys.positions,
                                                                 largest * (1 + 1e-9), cutoff_of);
            if (o.half) {
                oracle = tricell::testing::canonical_half(oracle);
            }
            check_oracle(oracle, tricell::testing::to_map(reference), 1e-10 * scale, cutoff_of);
        }
        if (testing::Test::HasFailure()) {
            return;
        }
    }
    totals.systems += 1;
    totals.oracle += n <= oracle_limit ? 1 : 0;
}

// Runs systems [first, first + count) of the campaign `seed` (each overridable from the
// environment), making each with `make(system seed, index)`, and prints the totals.
template <class Make>
void run_campaign(const char* test, std::uint64_t seed, std::uint64_t count, const Make& make) {
    seed = from_environment("TRICELL_CAMPAIGN_SEED", seed);
    const std::uint64_t first = from_environment("TRICELL_CAMPAIGN_FIRST", 0);
    count = from_environment("TRICELL_CAMPAIGN_SYSTEMS", count);
    Totals totals;
    for (std::uint64_t index = first; index < first + count; ++index) {
        const CampaignSystem sys = make(system_seed(seed, index), index);
        check_system(test, seed, index, sys, totals);
        if (testing::Test::HasFailure()) {
            break;
        }
    }
    std::cout << "[campaign] " << test << ": seed " << seed << ", systems " << totals.systems
              << ", pairs compared " << totals.pairs << ", oracle-checked systems " << totals.oracle
              << std::endl;
}

} // namespace

TEST(RandomCampaign, SmallSystems) {
    run_campaign("SmallSystems", 20261203, small_count, [](std::uint64_t s, std::uint64_t) {
        return tricell::testing::random_campaign_system(s, oracle_limit);
    });
}

TEST(RandomCampaign, MediumSystems) {
    run_campaign("MediumSystems", 77003, medium_count, [](std::uint64_t s, std::uint64_t) {
        return tricell::testing::random_campaign_system(s, 10000, oracle_limit + 1);
    });
}

TEST(RandomCampaign, LargeSystems) {
    run_campaign("LargeSystems", 100000, large_count, [](std::uint64_t s, std::uint64_t) {
        return tricell::testing::random_campaign_system(s, large_max, large_min);
    });
}

// Sizes drawn per system: mostly small (oracle-checked), some up to 10^4, a few up to the
// large size. What scripts/random-campaign.sh runs with fresh seeds.
TEST(RandomCampaign, Mixed) {
    run_campaign("Mixed", 424242, mixed_count, [](std::uint64_t s, std::uint64_t) {
        const std::uint64_t size_class = s % 20;
        const std::size_t most = size_class < 14   ? oracle_limit
                                 : size_class < 19 ? 10000
                                                   : large_max;
        return tricell::testing::random_campaign_system(s, most);
    });
}
