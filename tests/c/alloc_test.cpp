// std::bad_alloc at every allocation of a C API call becomes TRICELL_ERROR_OUT_OF_MEMORY with
// the message "out of memory", leaves the list empty, and the next call works. The failures
// are injected by replacing the global operator new of this test program (which the shared
// C library's code and the C++ runtime then call): once armed, the k-th allocation throws.
#include <atomic>
#include <cstdlib>
#include <new>
#include <string>

#include <gtest/gtest.h>

#include "c_api_support.hpp"
#include "tricell.h"

namespace {
std::atomic<long> allocations_left{-1}; // -1: never fail
} // namespace

void* operator new(std::size_t size) {
    if (allocations_left.load() >= 0 && allocations_left.fetch_sub(1) == 0) {
        throw std::bad_alloc();
    }
    if (void* p = std::malloc(size == 0 ? 1 : size)) {
        return p;
    }
    throw std::bad_alloc();
}
void* operator new[](std::size_t size) {
    return operator new(size);
}
void operator delete(void* p) noexcept {
    std::free(p);
}
void operator delete[](void* p) noexcept {
    std::free(p);
}
void operator delete(void* p, std::size_t) noexcept {
    std::free(p);
}
void operator delete[](void* p, std::size_t) noexcept {
    std::free(p);
}

using namespace tricell::testing;

namespace {

// Runs call() with the k-th allocation failing, for k = 0, 1, ... until a run succeeds.
// Every failing run must report out of memory; check() then runs with allocation working.
template <class Call, class Check> int fail_each_allocation(Call&& call, Check&& check) {
    for (long k = 0; k < 100000; ++k) {
        allocations_left.store(k);
        const tricell_status status = call();
        allocations_left.store(-1);
        if (status == TRICELL_OK) {
            return int(k);
        }
        EXPECT_EQ(status, TRICELL_ERROR_OUT_OF_MEMORY) << "allocation " << k;
        EXPECT_EQ(std::string(tricell_last_error()), "out of memory") << "allocation " << k;
        check();
    }
    ADD_FAILURE() << "never succeeded";
    return -1;
}

} // namespace

TEST(CApiOutOfMemory, EveryAllocationOfASearch) {
    const RandomSystem sys = random_system(6); // triclinic, 7 mixed
    for (int threads : {1, 2}) {
        for (int sorted : {0, 1}) {
            SCOPED_TRACE(threads);
            SCOPED_TRACE(sorted);
            tricell_neighbor_search* search = nullptr;
            tricell_neighbor_list* list = nullptr;
            fail_each_allocation([&] { return tricell_neighbor_search_create(&search); }, [] {});
            fail_each_allocation([&] { return tricell_neighbor_list_create(&list); }, [] {});
            SearchHandle search_handle(search);
            ListHandle list_handle(list);
            const tricell_box box = c_box(sys);
            tricell_neighbor_options o;
            tricell_neighbor_options_init(&o);
            o.cutoff = sys.cutoff;
            o.vectors = 1;
            o.sorted = sorted;
            o.threads = threads;
            const int points = fail_each_allocation(
                [&] {
                    return tricell_neighbors(search, &box, xyz(sys.positions), sys.positions.size(),
                                             &o, list);
                },
                [&] {
                    tricell_pairs pairs;
                    ASSERT_EQ(tricell_neighbor_list_pairs(list, &pairs), TRICELL_OK);
                    EXPECT_EQ(pairs.size, 0u);
                });
            EXPECT_GT(points, 3); // the search did allocate, and each allocation was failed
            tricell_pairs pairs;
            ASSERT_EQ(tricell_neighbor_list_pairs(list, &pairs), TRICELL_OK);
            expect_same_pairs(brute_force_pairs(sys.box(), sys.positions, sys.cutoff),
                              to_map(pairs), sys.cutoff, tolerance(sys));
        }
    }
}

TEST(CApiOutOfMemory, EveryAllocationOfAVerletList) {
    const RandomSystem sys = random_system(0);
    tricell_verlet_options o;
    tricell_verlet_options_init(&o);
    o.neighbors.cutoff = sys.cutoff;
    o.neighbors.vectors = 1;
    o.skin = 0.2;
    tricell_verlet* verlet = nullptr;
    fail_each_allocation([&] { return tricell_verlet_create(&o, &verlet); }, [] {});
    VerletHandle handle(verlet);
    const tricell_box box = c_box(sys);
    const int points = fail_each_allocation(
        [&] {
            return tricell_verlet_update(verlet, &box, xyz(sys.positions), sys.positions.size(),
                                         nullptr);
        },
        [&] {
            tricell_pairs pairs;
            ASSERT_EQ(tricell_verlet_pairs(verlet, &pairs), TRICELL_OK);
            EXPECT_EQ(pairs.size, 0u);
        });
    EXPECT_GT(points, 3);
    tricell_pairs pairs;
    ASSERT_EQ(tricell_verlet_pairs(verlet, &pairs), TRICELL_OK);
    expect_same_pairs(brute_force_pairs(sys.box(), sys.positions, sys.cutoff), to_map(pairs),
                      sys.cutoff, tolerance(sys));
}
