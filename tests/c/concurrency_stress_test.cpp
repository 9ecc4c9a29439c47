// Many threads calling the C API at once (tricell_neighbors()), each with a search and a list
// handle of its own, with 1 to 4 internal threads; and the thread-local error message
// (lib/c/boundary.cpp) of each thread staying its own while the others fail or succeed. The
// reference lists come first from serial C++ calls; every C list must equal them bit for bit.
#include <atomic>
#include <cstring>
#include <string>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

#include "c/c_api_support.hpp"
#include "support/stress_cases.hpp"

namespace {

using tricell::NeighborList;
using tricell::testing::stress_cases;

#ifdef TRICELL_STRESS_LIGHT
constexpr int callers = 6, rounds = 1;
#else
constexpr int callers = 12, rounds = 3;
#endif

tricell_box c_box_of(const tricell::testing::StressCase& s) {
    double columns[9];
    for (int r = 0; r < 3; ++r) {
        for (int c = 0; c < 3; ++c) {
            columns[3 * r + c] = s.h(r, c);
        }
    }
    const int periodic[3] = {s.pbc[0], s.pbc[1], s.pbc[2]};
    tricell_box box;
    tricell_box_from_columns(columns, periodic, &box);
    return box;
}

tricell_neighbor_options c_options(const tricell::NeighborOptions& o, int threads) {
    tricell_neighbor_options c;
    tricell_neighbor_options_init(&c);
    c.cutoff = o.cutoff;
    c.half = o.half;
    c.sorted = o.sorted;
    c.grouped = o.grouped;
    c.vectors = o.quantities.vectors;
    c.threads = threads;
    c.backend = static_cast<int>(o.backend);
    return c;
}

template <class A, class T> bool same(const A& cxx, const T* c, std::size_t n) {
    if (cxx.size() != n) {
        return false;
    }
    return n == 0 || std::memcmp(cxx.data(), c, n * sizeof(T)) == 0;
}

bool same_list(const NeighborList& ref, const tricell_pairs& p) {
    return p.size == ref.size() && same(ref.i(), p.i, p.size) && same(ref.j(), p.j, p.size) &&
           same(ref.shifts(), p.shifts, 3 * p.size) && same(ref.distances(), p.distances, p.size) &&
           (ref.vectors().empty() ? p.vectors == nullptr
                                  : same(ref.vectors(), p.vectors, 3 * p.size)) &&
           (ref.offsets().empty() ? p.offsets == nullptr
                                  : same(ref.offsets(), p.offsets, p.atoms + 1));
}

TEST(ConcurrencyStress, CApiMatchesSerialBitForBit) {
    const auto cases = stress_cases(8, 1600, 5);
    std::vector<NeighborList> reference;
    for (const auto& s : cases) {
        reference.push_back(tricell::compute_neighbors(s.box(), s.positions, s.options));
    }
    std::atomic<int> failures{0};
    std::vector<std::string> first(callers);
    std::vector<std::thread> threads;
    for (int t = 0; t < callers; ++t) {
        threads.emplace_back([&, t] {
            auto search = tricell::testing::make_search();
            auto list = tricell::testing::make_list();
            for (int r = 0; r < rounds; ++r) {
                for (std::size_t k = 0; k < cases.size(); ++k) {
                    const std::size_t c = (k + static_cast<std::size_t>(t)) % cases.size();
                    const int n_threads = 1 + (t + r + static_cast<int>(c)) % 4;
                    const tricell_box box = c_box_of(cases[c]);
                    const tricell_neighbor_options options = c_options(cases[c].options, n_threads);
                    const tricell_status status =
                        tricell_neighbors(search.get(), &box, cases[c].positions.front().data(),
                                          cases[c].positions.size(), &options, list.get());
                    tricell_pairs pairs;
                    if (status != TRICELL_OK ||
                        tricell_neighbor_list_pairs(list.get(), &pairs) != TRICELL_OK ||
                        !same_list(reference[c], pairs)) {
                        if (first[t].empty()) {
                            first[t] = "case " + std::to_string(c) + " threads " +
                                       std::to_string(n_threads) + ": " + tricell_last_error();
                        }
                        failures.fetch_add(1);
                    }
                }
            }
        });
    }
    for (auto& th : threads) {
        th.join();
    }
    for (const auto& f : first) {
        EXPECT_TRUE(f.empty()) << f;
    }
    EXPECT_EQ(failures.load(), 0);
}

TEST(ConcurrencyStress, CApiErrorMessagesStayPerThread) {
    // Even threads fail (a negative cutoff) and must read their own message; odd threads succeed
    // and must read an empty one, however the calls interleave.
    const auto cases = stress_cases(2, 400, 9);
    std::atomic<int> failures{0};
    std::vector<std::thread> threads;
    for (int t = 0; t < callers; ++t) {
        threads.emplace_back([&, t] {
            auto search = tricell::testing::make_search();
            auto list = tricell::testing::make_list();
            const auto& s = cases[static_cast<std::size_t>(t) % cases.size()];
            const tricell_box box = c_box_of(s);
            tricell_neighbor_options options = c_options(s.options, 1 + t % 3);
            if (t % 2 == 0) {
                options.cutoff = -1;
            }
            for (int r = 0; r < 20 * rounds; ++r) {
                const tricell_status status =
                    tricell_neighbors(search.get(), &box, s.positions.front().data(),
                                      s.positions.size(), &options, list.get());
                const std::string message = tricell_last_error();
                const bool ok = t % 2 == 0 ? status != TRICELL_OK && !message.empty() &&
                                                 message.find("cutoff") != std::string::npos
                                           : status == TRICELL_OK && message.empty();
                if (!ok) {
                    failures.fetch_add(1);
                }
            }
        });
    }
    for (auto& th : threads) {
        th.join();
    }
    EXPECT_EQ(failures.load(), 0);
}

} // namespace
