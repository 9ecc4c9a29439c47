// What the differential harnesses (search_fuzzer, c_api_fuzzer) check of a list, in one place:
// the list's own rules (indices in range, no (i, i, 0), zero shifts on open axes, the half
// orientation, the sorted order and offsets, max_pairs) and the comparison with the brute-force
// oracle (tests/support/brute_force.hpp).
//
// A pair whose distance is within rounding of its cutoff may be in or out: the search subtracts
// wrapped positions, the oracle the caller's; the allowance is the library's own
// (tricell::rounding_allowance, lib/verify/rounding_allowance.cpp). A failure prints one line
// and aborts, so that libFuzzer keeps the input.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include <tricell/box.hpp>
#include <tricell/error.hpp>
#include <tricell/neighbor_list.hpp>
#include <tricell/verify.hpp>

#include "support/brute_force.hpp"

namespace tricell::fuzz {

using testing::PairKey;
using testing::PairMap;

[[noreturn]] inline void broken(const std::string& what) {
    std::fprintf(stderr, "fuzzer: %s\n", what.c_str());
    std::abort();
}

/// A hash of an input's bytes (FNV-1a): a harness that checks a sample of its inputs in some way
/// picks them by it, so that a replay of an input checks the same.
inline std::uint32_t input_hash(const std::uint8_t* data, std::size_t size) {
    std::uint32_t h = 2166136261u;
    for (std::size_t k = 0; k < size; ++k) {
        h = (h ^ data[k]) * 16777619u;
    }
    return h;
}

/// Whether every input gets every check (TRICELL_FUZZ_EVERY_CHECK set, as ctest's replays of the
/// regressions and the corpus set it), not the sample input_hash() picks.
inline bool every_check() {
    static const bool every = std::getenv("TRICELL_FUZZ_EVERY_CHECK") != nullptr;
    return every;
}

/// The promise of every refusal: a message of one non-empty line.
inline void check_message(const std::string& message) {
    if (message.empty() || message.find('\n') != std::string::npos) {
        broken("error message is empty or not one line: " + message);
    }
}

/// The arrays of a stored list, from the C++ or the C API (shifts and offsets may be absent).
struct ListView {
    std::size_t size = 0;
    const std::uint32_t* i = nullptr;
    const std::uint32_t* j = nullptr;
    const std::int32_t* shifts = nullptr; // 3 per pair, or nullptr
    const std::size_t* offsets = nullptr; // offset_count entries, or nullptr
    std::size_t offset_count = 0;
};

inline ListView view(const NeighborList& list) {
    return ListView{list.size(),
                    list.i().data(),
                    list.j().data(),
                    list.shifts().size() == 3 * list.size() ? list.shifts().data() : nullptr,
                    list.offsets().empty() ? nullptr : list.offsets().data(),
                    list.offsets().size()};
}

inline bool lexicographically_positive(int a, int b, int c) {
    return a > 0 || (a == 0 && (b > 0 || (b == 0 && c > 0)));
}

/// What a list promises about its order: nothing, grouped by i with n + 1 offsets (a Verlet
/// list), or sorted by (i, j, S) with offsets.
enum class Order { any, grouped, sorted };

/// The list's own rules for n atoms, and its order.
inline void check_rules(const Box& box, std::size_t n, bool half, Order order,
                        std::size_t max_pairs, const ListView& list) {
    const bool sorted = order == Order::sorted;
    if (max_pairs != 0 && list.size > max_pairs) {
        broken("more pairs than max_pairs: " + std::to_string(list.size));
    }
    PairKey before{};
    for (std::size_t k = 0; k < list.size; ++k) {
        const std::uint32_t i = list.i[k], j = list.j[k];
        int s[3] = {0, 0, 0};
        if (list.shifts != nullptr) {
            for (int axis = 0; axis < 3; ++axis) {
                s[axis] = list.shifts[3 * k + std::size_t(axis)];
            }
        }
        if (i >= n || j >= n) {
            broken("index out of range");
        }
        if (list.shifts != nullptr && i == j && s[0] == 0 && s[1] == 0 && s[2] == 0) {
            broken("an atom paired with itself");
        }
        for (int axis = 0; axis < 3; ++axis) {
            if (!box.periodic(axis) && s[axis] != 0) {
                broken("non-zero shift along an open axis");
            }
        }
        if (half && (i > j || (list.shifts != nullptr && i == j &&
                               !lexicographically_positive(s[0], s[1], s[2])))) {
            broken("half list pair not in canonical orientation");
        }
        const PairKey here{i, j, s[0], s[1], s[2]};
        if (sorted && k > 0 && !(before < here || (list.shifts == nullptr && before == here))) {
            broken("sorted list out of order at pair " + std::to_string(k));
        }
        before = here;
    }
    if (order != Order::any) {
        if (list.offsets == nullptr || list.offset_count != n + 1 || list.offsets[0] != 0 ||
            list.offsets[n] != list.size) {
            broken("sorted list offsets have the wrong size or ends");
        }
        for (std::size_t i = 0; i < n; ++i) {
            for (std::size_t k = list.offsets[i]; k < list.offsets[i + 1]; ++k) {
                if (k >= list.size || list.i[k] != i) {
                    broken("sorted list offsets do not match i");
                }
            }
        }
    }
}

/// The rounding allowance of one pair: the library's rule (tricell::rounding_allowance), the one
/// verify() applies.
struct Tolerance {
    const Box& box;
    explicit Tolerance(const Box& b) : box(b) {}
    double operator()(const std::vector<Eigen::Vector3d>& x, const PairKey& key,
                      double cutoff) const {
        const auto& [i, j, a, b, c] = key;
        return rounding_allowance(box, x[i], x[j], Eigen::Vector3i(a, b, c), cutoff);
    }
};

inline double oracle_distance(const Box& box, const std::vector<Eigen::Vector3d>& x,
                              const PairKey& key) {
    const auto& [i, j, a, b, c] = key;
    return (x[j] - x[i] + box.matrix() * Eigen::Vector3d(a, b, c)).norm();
}

/// A list's pairs as rows sorted by key, what compare() walks: cheaper to build than a PairMap
/// (one allocation, not one a pair), which at a few thousand pairs a list was most of an input's
/// time.
using PairRows = std::vector<std::pair<PairKey, testing::PairValue>>;

/// Sorts `rows` by key; a key twice is a defect of the list `engine` made.
inline void sort_rows(PairRows& rows, const char* engine) {
    std::sort(rows.begin(), rows.end(),
              [](const auto& a, const auto& b) { return a.first < b.first; });
    for (std::size_t k = 1; k < rows.size(); ++k) {
        if (rows[k - 1].first == rows[k].first) {
            broken(std::string(engine) + ": the same pair twice in a list");
        }
    }
}

/// The oracle's pairs as sorted rows in `rows` (cleared first; a caller's buffer, reused so
/// that a large list does not cost a fresh allocation per input), straight from its loop (which
/// visits them in key order; a map would take an allocation per pair): d < cutoff_of(i, j) <=
/// `largest`, only the canonical half when `half`.
template <class CutoffOf>
void oracle_rows(const Box& box, const std::vector<Eigen::Vector3d>& x, double largest,
                 const CutoffOf& cutoff_of, bool half, PairRows& rows) {
    rows.clear();
    testing::for_each_brute_force_pair(box, x, largest, cutoff_of,
                                       [&](const PairKey& key, const testing::PairValue& value) {
                                           if (!half || testing::in_canonical_half(key)) {
                                               rows.emplace_back(key, value);
                                           }
                                       });
}

/// A stored list (shifts, distances and vectors stored) as sorted rows, in `out`.
inline void rows_of(const NeighborList& list, const char* engine, PairRows& out) {
    out.clear();
    for (std::size_t k = 0; k < list.size(); ++k) {
        const Shift s = list.shift(k);
        out.emplace_back(PairKey{list.i()[k], list.j()[k], s[0], s[1], s[2]},
                         testing::PairValue{list.distances()[k], list.vector(k)});
    }
    sort_rows(out, engine);
}

/// `found` against the oracle's `expected` (both sorted rows); cutoff_of(i, j) is the cutoff of
/// a pair.
template <class CutoffOf>
void compare(const Box& box, const std::vector<Eigen::Vector3d>& x, const CutoffOf& cutoff_of,
             const PairRows& expected, const PairRows& found, const char* engine) {
    const Tolerance tolerance(box);
    std::size_t e = 0;
    for (const auto& [key, value] : found) {
        const double cutoff = cutoff_of(std::get<0>(key), std::get<1>(key));
        for (; e < expected.size() && expected[e].first < key; ++e) {
            const auto& [missing, oracle] = expected[e];
            const double c = cutoff_of(std::get<0>(missing), std::get<1>(missing));
            if (!(std::abs(oracle.distance - c) <= tolerance(x, missing, c))) {
                broken(std::string(engine) + ": missing pair at distance " +
                       std::to_string(oracle.distance) + " for cutoff " + std::to_string(c));
            }
        }
        const double d = oracle_distance(box, x, key);
        const double tol = tolerance(x, key, cutoff);
        if (e == expected.size() || expected[e].first != key) {
            if (!(std::abs(d - cutoff) <= tol)) {
                broken(std::string(engine) + ": extra pair at distance " + std::to_string(d) +
                       " for cutoff " + std::to_string(cutoff));
            }
            continue;
        }
        if (!(std::abs(value.distance - d) <= tol) ||
            !((value.vector - expected[e].second.vector).norm() <= tol)) {
            broken(std::string(engine) + ": wrong distance or vector: " +
                   std::to_string(value.distance) + " instead of " + std::to_string(d));
        }
        ++e;
    }
    for (; e < expected.size(); ++e) {
        const auto& [missing, oracle] = expected[e];
        const double c = cutoff_of(std::get<0>(missing), std::get<1>(missing));
        if (!(std::abs(oracle.distance - c) <= tolerance(x, missing, c))) {
            broken(std::string(engine) + ": missing pair at distance " +
                   std::to_string(oracle.distance) + " for cutoff " + std::to_string(c));
        }
    }
}

/// About how many periodic images a pair can have within `cutoff` (the oracle's and the image
/// backends' loop; infinite or NaN for a cutoff that is).
inline double image_count(const Box& box, double cutoff) {
    double images = 1;
    for (int k = 0; k < 3; ++k) {
        if (box.periodic(k)) {
            images *= 2 * (cutoff / box.perpendicular_widths()[k]) + 3;
        }
    }
    return images;
}

/// Speed, not correctness: every backend's work (its stencil's offsets, the octree's reachable
/// images, the pairs it tests) grows with the periodic images within the cutoff, and for these
/// few atoms with the images times the atom pairs. A search reaching more than `max_images`, or
/// more than `max_image_pairs` images times n^2, is not made (with ~8e4 images, the slowest search
/// input took 14 s under the sanitizers on a loaded machine, and a C API input spent 15 s building
/// a stencil; with 1e4 images and no bound on their product with n^2, the tenth of the inputs with
/// the most images took two thirds of the search harness's time). One atom still gets 1e4 images
/// (20 perpendicular widths along one axis, ~10 along each of three), eight atoms 625 (~2.8
/// widths along each of three axes). A cutoff the search refuses (0, negative, NaN, infinite) is
/// fast and always made.
constexpr double max_images = 1e4;
constexpr double max_image_pairs = 4e4;

inline bool too_many_images(const Box& box, double cutoff, std::size_t n) {
    if (!(std::isfinite(cutoff) && cutoff > 0)) {
        return false;
    }
    const double images = image_count(box, cutoff);
    const double atoms = double(std::max<std::size_t>(n, 1));
    return !(images <= max_images) || !(images * atoms * atoms <= max_image_pairs);
}

/// Whether the oracle can run on these positions at this (largest) cutoff within `budget`
/// pair-image tests: finite input, fractional coordinates an int can hold (its image range),
/// and few enough images.
inline bool oracle_affordable(const Box& box, const std::vector<Eigen::Vector3d>& x, double cutoff,
                              double budget) {
    if (!(std::isfinite(cutoff) && cutoff > 0)) {
        return false;
    }
    for (const Eigen::Vector3d& r : x) {
        if (!r.allFinite() || !((box.inverse() * r).cwiseAbs().maxCoeff() < 1e8)) {
            return false;
        }
    }
    return image_count(box, cutoff) * double(x.size()) * double(x.size()) <= budget;
}

} // namespace tricell::fuzz
