// The oracle of the Fortran test program: given the positions, box and options it used and
// the list it got through the Fortran module, checks that list against the C++ API (the same
// arrays in the same order) and the brute-force oracle. Called from Fortran through bind(c).
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <vector>

#include "support/brute_force.hpp"
#include "tricell/tricell.hpp"

using namespace tricell;
using namespace tricell::testing;

namespace {

int report(int& problems, const char* what, std::size_t k) {
    if (problems++ < 5) {
        std::fprintf(stderr, "  oracle: %s (entry %zu)\n", what, k);
    }
    return problems;
}

} // namespace

// box_columns is the Fortran box(3, 3), lattice vector k in column k; periodic holds 0 or 1.
// Every quantity is required (shifts, distances and vectors stored). With radii (n) or species
// (n) and a table of table_count entries (pairs(2, k), cutoffs(k)) the rule is variable and the
// list is compared with the C++ one only (tests/c checks those against brute force). order: 0
// as found, 1 sorted, 2 grouped. Returns the number of problems found (0: the list is right).
extern "C" int tricell_test_check_list(
    const double* positions, std::size_t n, const double* box_columns, const int* periodic,
    double cutoff, int half, int order, int backend, const double* radii,
    const std::int32_t* species, const std::int32_t* table_pairs, const double* table_cutoffs,
    std::size_t table_count, std::size_t npairs, const std::int32_t* i, const std::int32_t* j,
    const std::int32_t* shifts, const double* distances, const double* vectors) {
    int problems = 0;
    Eigen::Matrix3d rows;
    for (int k = 0; k < 3; ++k) {
        for (int c = 0; c < 3; ++c) {
            rows(k, c) = box_columns[3 * k + c];
        }
    }
    const Box box =
        Box::from_rows(rows, Periodicity{{periodic[0] == 1, periodic[1] == 1, periodic[2] == 1}});
    std::vector<Eigen::Vector3d> x(n);
    double scale = 1;
    for (std::size_t a = 0; a < n; ++a) {
        x[a] = Eigen::Vector3d(positions[3 * a], positions[3 * a + 1], positions[3 * a + 2]);
        scale = std::max(scale, x[a].cwiseAbs().maxCoeff());
    }
    const double tol = 1e-10 * scale;

    NeighborOptions options;
    options.cutoff = cutoff;
    options.half = half == 1;
    options.sorted = order == 1;
    options.grouped = order == 2;
    options.quantities.vectors = true;
    options.backend = static_cast<SearchBackend>(backend);
    if (radii != nullptr) {
        options.radii.assign(radii, radii + n);
    }
    if (species != nullptr) {
        options.species.assign(species, species + n);
        for (std::size_t k = 0; k < table_count; ++k) {
            options.species_cutoffs.push_back(
                SpeciesCutoff{table_pairs[2 * k], table_pairs[2 * k + 1], table_cutoffs[k]});
        }
    }
    const NeighborList cxx = compute_neighbors(box, x, options);
    if (cxx.size() != npairs) {
        std::fprintf(stderr, "  oracle: %zu pairs from Fortran, %zu from C++\n", npairs,
                     cxx.size());
        return 1;
    }
    for (std::size_t k = 0; k < npairs; ++k) {
        if (std::uint32_t(i[k]) != cxx.i()[k] || std::uint32_t(j[k]) != cxx.j()[k]) {
            report(problems, "i or j differs from C++", k);
        }
        for (int c = 0; c < 3; ++c) {
            if (shifts[3 * k + c] != cxx.shifts()[3 * k + c] ||
                vectors[3 * k + c] != cxx.vectors()[3 * k + c]) {
                report(problems, "S or D differs from C++", k);
            }
        }
        if (distances[k] != cxx.distances()[k]) {
            report(problems, "d differs from C++", k);
        }
    }

    if (options.variable_cutoff()) {
        return problems;
    }
    PairMap expected = brute_force_pairs(box, x, cutoff);
    if (half == 1) {
        expected = canonical_half(expected);
    }
    const PairMap actual = to_map(cxx);
    for (const auto& [key, value] : expected) {
        const auto found = actual.find(key);
        if (found == actual.end()) {
            if (std::abs(value.distance - cutoff) > tol) {
                report(problems, "a brute-force pair is missing", 0);
            }
        } else if (std::abs(found->second.distance - value.distance) > tol) {
            report(problems, "d differs from brute force", 0);
        }
    }
    for (const auto& [key, value] : actual) {
        if (expected.count(key) == 0 && std::abs(value.distance - cutoff) > tol) {
            report(problems, "a pair brute force does not have", 0);
        }
    }
    return problems;
}
