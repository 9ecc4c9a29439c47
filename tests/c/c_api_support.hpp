// Helpers for the C API tests: C handles with RAII, a C list as a PairMap, and the comparison
// with the brute-force oracle (a pair may be missing on one side only when its distance is
// within rounding of the cutoff).
#pragma once

#include <algorithm>
#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "support/brute_force.hpp"
#include "support/random_systems.hpp"
#include "tricell.h"

namespace tricell::testing {

struct SearchDeleter {
    void operator()(tricell_neighbor_search* p) const { tricell_neighbor_search_destroy(p); }
};
struct ListDeleter {
    void operator()(tricell_neighbor_list* p) const { tricell_neighbor_list_destroy(p); }
};
struct VerletDeleter {
    void operator()(tricell_verlet* p) const { tricell_verlet_destroy(p); }
};
using SearchHandle = std::unique_ptr<tricell_neighbor_search, SearchDeleter>;
using ListHandle = std::unique_ptr<tricell_neighbor_list, ListDeleter>;
using VerletHandle = std::unique_ptr<tricell_verlet, VerletDeleter>;

inline SearchHandle make_search() {
    tricell_neighbor_search* p = nullptr;
    EXPECT_EQ(tricell_neighbor_search_create(&p), TRICELL_OK);
    return SearchHandle(p);
}
inline ListHandle make_list() {
    tricell_neighbor_list* p = nullptr;
    EXPECT_EQ(tricell_neighbor_list_create(&p), TRICELL_OK);
    return ListHandle(p);
}

/// The C box of a random system (through the C API's column constructor).
inline tricell_box c_box(const RandomSystem& sys) {
    double columns[9];
    for (int r = 0; r < 3; ++r) {
        for (int c = 0; c < 3; ++c) {
            columns[3 * r + c] = sys.h(r, c);
        }
    }
    const int periodic[3] = {sys.pbc[0], sys.pbc[1], sys.pbc[2]};
    tricell_box box;
    EXPECT_EQ(tricell_box_from_columns(columns, periodic, &box), TRICELL_OK)
        << tricell_last_error();
    return box;
}

inline const double* xyz(const std::vector<Eigen::Vector3d>& x) {
    return x.empty() ? nullptr : x.front().data();
}

/// A C pair view as a PairMap (needs shifts, distances and vectors).
inline PairMap to_map(const tricell_pairs& p) {
    PairMap out;
    for (std::size_t k = 0; k < p.size; ++k) {
        out[PairKey{p.i[k], p.j[k], p.shifts[3 * k], p.shifts[3 * k + 1], p.shifts[3 * k + 2]}] =
            PairValue{p.distances[k], Eigen::Vector3d(p.vectors[3 * k], p.vectors[3 * k + 1],
                                                      p.vectors[3 * k + 2])};
    }
    return out;
}

inline double tolerance(const RandomSystem& sys) {
    double scale = 1;
    for (const auto& x : sys.positions) {
        scale = std::max(scale, x.cwiseAbs().maxCoeff());
    }
    return 1e-10 * scale;
}

inline void expect_same_pairs(const PairMap& expected, const PairMap& actual, double cutoff,
                              double tol) {
    int reported = 0;
    auto near_cutoff = [&](double d) { return std::abs(d - cutoff) <= tol; };
    for (const auto& [key, value] : expected) {
        const auto found = actual.find(key);
        if (found == actual.end()) {
            if (!near_cutoff(value.distance) && reported++ < 5) {
                ADD_FAILURE() << "missing pair i=" << std::get<0>(key) << " j=" << std::get<1>(key)
                              << " d=" << value.distance;
            }
        } else if (std::abs(found->second.distance - value.distance) > tol ||
                   (found->second.vector - value.vector).norm() > tol) {
            if (reported++ < 5) {
                ADD_FAILURE() << "d or D differs: " << found->second.distance << " vs "
                              << value.distance;
            }
        }
    }
    for (const auto& [key, value] : actual) {
        if (expected.count(key) == 0 && !near_cutoff(value.distance) && reported++ < 5) {
            ADD_FAILURE() << "extra pair i=" << std::get<0>(key) << " j=" << std::get<1>(key)
                          << " d=" << value.distance;
        }
    }
}

/// The first `n` entries of a C array equal a C++ array (and the sizes agree).
template <class A, class B> void expect_same_array(const A& cxx, const B* c, std::size_t n) {
    ASSERT_EQ(cxx.size(), n);
    for (std::size_t k = 0; k < n; ++k) {
        if (cxx[k] != c[k]) {
            ADD_FAILURE() << "entry " << k << " differs: " << cxx[k] << " vs " << c[k];
            return;
        }
    }
}

} // namespace tricell::testing

/// A C call returns `status` and leaves `message` as this thread's message.
#define EXPECT_STATUS(call, status, message)                                                       \
    do {                                                                                           \
        EXPECT_EQ((call), (status));                                                               \
        EXPECT_EQ(std::string(tricell_last_error()), std::string(message));                        \
    } while (0)
