// Every validation branch of the C API: the status AND the message, the message being the C++
// error's own text where the C++ API finds the problem. Also: failures write nothing (a box
// keeps its old value, a list is left empty), and a success clears the message.
#include <cmath>
#include <cstdint>
#include <cstring>
#include <functional>
#include <limits>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "c_api_support.hpp"
#include "tricell.h"
#include "tricell/tricell.hpp"

using namespace tricell::testing;

namespace {

const double not_a_number = std::numeric_limits<double>::quiet_NaN();
const double infinity = std::numeric_limits<double>::infinity();

// The what() of whatever the C++ call throws ("" if nothing).
std::string cxx_message(const std::function<void()>& call) {
    try {
        call();
    } catch (const std::exception& e) {
        return e.what();
    }
    return "";
}

const double cube_rows[9] = {4, 0, 0, 0, 4, 0, 0, 0, 4};
const int all[3] = {1, 1, 1};

tricell_box cube() {
    tricell_box box;
    EXPECT_EQ(tricell_box_from_rows(cube_rows, all, &box), TRICELL_OK);
    return box;
}

// A box the caller wrote by hand (not checked when written).
tricell_box hand_box(const double rows[9], const int periodic[3]) {
    tricell_box box;
    for (int k = 0; k < 3; ++k) {
        for (int c = 0; c < 3; ++c) {
            box.vectors[k][c] = rows[3 * k + c];
        }
        box.periodic[k] = periodic[k];
    }
    return box;
}

tricell_neighbor_options options_with_cutoff(double cutoff) {
    tricell_neighbor_options o;
    EXPECT_EQ(tricell_neighbor_options_init(&o), TRICELL_OK);
    o.cutoff = cutoff;
    return o;
}

const std::vector<Eigen::Vector3d> two_atoms = {{0.5, 0.5, 0.5}, {1.5, 0.5, 0.5}};

} // namespace

TEST(CApiValidation, Box_NullPointersAndPeriodicity) {
    tricell_box box = cube();
    const tricell_box before = box;
    const int bad[3] = {1, 2, 0};
    EXPECT_STATUS(tricell_box_from_rows(nullptr, all, &box), TRICELL_ERROR_INVALID_ARGUMENT,
                  "tricell_box_from_rows: rows must not be NULL");
    EXPECT_STATUS(tricell_box_from_rows(cube_rows, nullptr, &box), TRICELL_ERROR_INVALID_ARGUMENT,
                  "tricell_box_from_rows: periodic must not be NULL");
    EXPECT_STATUS(tricell_box_from_rows(cube_rows, all, nullptr), TRICELL_ERROR_INVALID_ARGUMENT,
                  "tricell_box_from_rows: box must not be NULL");
    EXPECT_STATUS(tricell_box_from_rows(cube_rows, bad, &box), TRICELL_ERROR_INVALID_ARGUMENT,
                  "periodic[1] must be 0 or 1 (got 2)");
    const int bad0[3] = {-1, 1, 1}, bad2[3] = {1, 1, 7};
    EXPECT_STATUS(tricell_box_from_columns(cube_rows, bad0, &box), TRICELL_ERROR_INVALID_ARGUMENT,
                  "periodic[0] must be 0 or 1 (got -1)");
    EXPECT_STATUS(tricell_box_from_parameters(4, 4, 4, 90, 90, 90, bad2, &box),
                  TRICELL_ERROR_INVALID_ARGUMENT, "periodic[2] must be 0 or 1 (got 7)");
    EXPECT_STATUS(tricell_box_from_columns(nullptr, all, &box), TRICELL_ERROR_INVALID_ARGUMENT,
                  "tricell_box_from_columns: columns must not be NULL");
    EXPECT_STATUS(tricell_box_from_columns(cube_rows, nullptr, &box),
                  TRICELL_ERROR_INVALID_ARGUMENT,
                  "tricell_box_from_columns: periodic must not be NULL");
    EXPECT_STATUS(tricell_box_from_columns(cube_rows, all, nullptr), TRICELL_ERROR_INVALID_ARGUMENT,
                  "tricell_box_from_columns: box must not be NULL");
    EXPECT_STATUS(tricell_box_from_parameters(4, 4, 4, 90, 90, 90, nullptr, &box),
                  TRICELL_ERROR_INVALID_ARGUMENT,
                  "tricell_box_from_parameters: periodic must not be NULL");
    EXPECT_STATUS(tricell_box_from_parameters(4, 4, 4, 90, 90, 90, all, nullptr),
                  TRICELL_ERROR_INVALID_ARGUMENT,
                  "tricell_box_from_parameters: box must not be NULL");
    EXPECT_EQ(std::memcmp(&box, &before, sizeof box), 0) << "a failed call wrote the box";
}

TEST(CApiValidation, Box_GeometryMessagesAreTheCxxOnes) {
    using tricell::Box;
    tricell_box box = cube();
    const tricell_box before = box;
    struct Case {
        double rows[9];
        int periodic[3];
        tricell_status status;
    };
    const Case cases[] = {
        {{4, 0, 0, 0, not_a_number, 0, 0, 0, 4},
         {1, 1, 1},
         TRICELL_ERROR_INVALID_ARGUMENT}, // non-finite
        {{4, 0, 0, 0, 4, 0, 0, 0, infinity}, {1, 1, 0}, TRICELL_ERROR_INVALID_ARGUMENT},
        {{4, 0, 0, 8, 0, 0, 0, 0, 4}, {1, 1, 1}, TRICELL_ERROR_GEOMETRY},     // singular
        {{4, 0, 0, 0, 4, 0, 4, 4, 1e-11}, {1, 1, 1}, TRICELL_ERROR_GEOMETRY}, // flat
        {{0, 0, 0, 0, 4, 0, 0, 0, 4}, {1, 1, 1}, TRICELL_ERROR_GEOMETRY},     // zero vector
    };
    for (const Case& c : cases) {
        Eigen::Matrix3d rows;
        for (int k = 0; k < 9; ++k) {
            rows(k / 3, k % 3) = c.rows[k];
        }
        const tricell::Periodicity pbc{
            {c.periodic[0] == 1, c.periodic[1] == 1, c.periodic[2] == 1}};
        const std::string from_rows = cxx_message([&] { Box::from_rows(rows, pbc); });
        const std::string from_columns =
            cxx_message([&] { Box::from_columns(rows.transpose(), pbc); });
        ASSERT_FALSE(from_rows.empty());
        double columns[9];
        for (int k = 0; k < 9; ++k) {
            columns[k] = rows.transpose()(k / 3, k % 3);
        }
        EXPECT_STATUS(tricell_box_from_rows(c.rows, c.periodic, &box), c.status, from_rows);
        EXPECT_STATUS(tricell_box_from_columns(columns, c.periodic, &box), c.status, from_columns);
        // A hand-written box with the same values fails where it is used, with the same text.
        auto search = make_search();
        auto list = make_list();
        const tricell_box hand = hand_box(c.rows, c.periodic);
        const tricell_neighbor_options o = options_with_cutoff(1);
        EXPECT_STATUS(tricell_neighbors(search.get(), &hand, xyz(two_atoms), 2, &o, list.get()),
                      c.status, from_rows);
    }
    const std::string bad_length = cxx_message([] { Box::from_parameters(-1, 4, 4, 90, 90, 90); });
    const std::string bad_angle = cxx_message([] { Box::from_parameters(4, 4, 4, 90, 190, 90); });
    const std::string bad_angles = cxx_message([] { Box::from_parameters(4, 4, 4, 10, 10, 100); });
    const std::string nan_length =
        cxx_message([] { Box::from_parameters(4, not_a_number, 4, 90, 90, 90); });
    EXPECT_STATUS(tricell_box_from_parameters(-1, 4, 4, 90, 90, 90, all, &box),
                  TRICELL_ERROR_INVALID_ARGUMENT, bad_length);
    EXPECT_STATUS(tricell_box_from_parameters(4, 4, 4, 90, 190, 90, all, &box),
                  TRICELL_ERROR_INVALID_ARGUMENT, bad_angle);
    EXPECT_STATUS(tricell_box_from_parameters(4, 4, 4, 10, 10, 100, all, &box),
                  TRICELL_ERROR_GEOMETRY, bad_angles);
    EXPECT_STATUS(tricell_box_from_parameters(4, not_a_number, 4, 90, 90, 90, all, &box),
                  TRICELL_ERROR_INVALID_ARGUMENT, nan_length);
    EXPECT_EQ(std::memcmp(&box, &before, sizeof box), 0) << "a failed call wrote the box";
    // A success clears the message.
    EXPECT_STATUS(tricell_box_from_parameters(4, 5, 6, 80, 95, 100, all, &box), TRICELL_OK, "");
}

TEST(CApiValidation, Handles_NullPointers) {
    EXPECT_STATUS(tricell_neighbor_options_init(nullptr), TRICELL_ERROR_INVALID_ARGUMENT,
                  "tricell_neighbor_options_init: options must not be NULL");
    EXPECT_STATUS(tricell_neighbor_search_create(nullptr), TRICELL_ERROR_INVALID_ARGUMENT,
                  "tricell_neighbor_search_create: search must not be NULL");
    EXPECT_STATUS(tricell_neighbor_list_create(nullptr), TRICELL_ERROR_INVALID_ARGUMENT,
                  "tricell_neighbor_list_create: list must not be NULL");
    tricell_pairs pairs;
    auto list = make_list();
    EXPECT_STATUS(tricell_neighbor_list_pairs(nullptr, &pairs), TRICELL_ERROR_INVALID_ARGUMENT,
                  "tricell_neighbor_list_pairs: list must not be NULL");
    EXPECT_STATUS(tricell_neighbor_list_pairs(list.get(), nullptr), TRICELL_ERROR_INVALID_ARGUMENT,
                  "tricell_neighbor_list_pairs: pairs must not be NULL");
    // Destroying NULL is a no-op.
    tricell_neighbor_search_destroy(nullptr);
    tricell_neighbor_list_destroy(nullptr);
    tricell_verlet_destroy(nullptr);
}

TEST(CApiValidation, Neighbors_EveryArgumentLeavesTheListEmpty) {
    auto search = make_search();
    auto list = make_list();
    const tricell_box box = cube();
    const tricell_neighbor_options good = options_with_cutoff(1.5);
    tricell_pairs pairs;

    // Fills the list, runs the failing call, and checks status, message and an empty list.
    auto check = [&](const std::function<tricell_status()>& call, tricell_status status,
                     const std::string& message) {
        ASSERT_EQ(tricell_neighbors(search.get(), &box, xyz(two_atoms), 2, &good, list.get()),
                  TRICELL_OK);
        ASSERT_EQ(tricell_neighbor_list_pairs(list.get(), &pairs), TRICELL_OK);
        ASSERT_GT(pairs.size, 0u);
        EXPECT_STATUS(call(), status, message);
        ASSERT_EQ(tricell_neighbor_list_pairs(list.get(), &pairs), TRICELL_OK);
        EXPECT_EQ(pairs.size, 0u) << message;
        EXPECT_EQ(pairs.shifts, nullptr);
        EXPECT_EQ(pairs.offsets, nullptr);
    };
    auto call_with = [&](const tricell_neighbor_options& o, const double* x, std::size_t n) {
        return [&, o, x, n] { return tricell_neighbors(search.get(), &box, x, n, &o, list.get()); };
    };

    EXPECT_STATUS(tricell_neighbors(search.get(), &box, xyz(two_atoms), 2, &good, nullptr),
                  TRICELL_ERROR_INVALID_ARGUMENT, "tricell_neighbors: list must not be NULL");
    check([&] { return tricell_neighbors(nullptr, &box, xyz(two_atoms), 2, &good, list.get()); },
          TRICELL_ERROR_INVALID_ARGUMENT, "tricell_neighbors: search must not be NULL");
    check(
        [&] {
            return tricell_neighbors(search.get(), nullptr, xyz(two_atoms), 2, &good, list.get());
        },
        TRICELL_ERROR_INVALID_ARGUMENT, "tricell_neighbors: box must not be NULL");
    check(
        [&] {
            return tricell_neighbors(search.get(), &box, xyz(two_atoms), 2, nullptr, list.get());
        },
        TRICELL_ERROR_INVALID_ARGUMENT, "tricell_neighbors: options must not be NULL");

    // Flags.
    struct Flag {
        int tricell_neighbor_options::*field;
        const char* name;
    };
    const Flag flags[] = {{&tricell_neighbor_options::half, "options.half"},
                          {&tricell_neighbor_options::sorted, "options.sorted"},
                          {&tricell_neighbor_options::shifts, "options.shifts"},
                          {&tricell_neighbor_options::distances, "options.distances"},
                          {&tricell_neighbor_options::vectors, "options.vectors"}};
    for (const Flag& flag : flags) {
        tricell_neighbor_options o = good;
        o.*flag.field = 2;
        check(call_with(o, xyz(two_atoms), 2), TRICELL_ERROR_INVALID_ARGUMENT,
              std::string(flag.name) + " must be 0 or 1 (got 2)");
        o.*flag.field = -1;
        check(call_with(o, xyz(two_atoms), 2), TRICELL_ERROR_INVALID_ARGUMENT,
              std::string(flag.name) + " must be 0 or 1 (got -1)");
    }
    const int hand_periodic[3] = {1, 1, 5};
    const tricell_box hand = hand_box(cube_rows, hand_periodic);
    check(
        [&] {
            return tricell_neighbors(search.get(), &hand, xyz(two_atoms), 2, &good, list.get());
        },
        TRICELL_ERROR_INVALID_ARGUMENT, "periodic[2] must be 0 or 1 (got 5)");

    // Values the C++ API checks: the same text as its exception.
    const tricell::Box cxx_box = tricell::Box::from_rows(Eigen::Matrix3d::Identity() * 4);
    auto cxx = [&](auto set, const std::vector<Eigen::Vector3d>& x) {
        tricell::NeighborOptions o;
        o.cutoff = 1.5;
        set(o);
        return cxx_message([&] { tricell::compute_neighbors(cxx_box, x, o); });
    };
    for (double cutoff : {0.0, -1.5, not_a_number, infinity, -infinity}) {
        SCOPED_TRACE(cutoff);
        const std::string message = cxx([&](auto& o) { o.cutoff = cutoff; }, two_atoms);
        ASSERT_FALSE(message.empty());
        check(call_with(options_with_cutoff(cutoff), xyz(two_atoms), 2),
              TRICELL_ERROR_INVALID_ARGUMENT, message);
    }
    for (int threads : {-1, 5000}) {
        tricell_neighbor_options o = good;
        o.threads = threads;
        check(call_with(o, xyz(two_atoms), 2), TRICELL_ERROR_INVALID_ARGUMENT,
              cxx([&](auto& c) { c.threads = threads; }, two_atoms));
    }
    // A refused pair limit names the C field to raise; what is too large reads as in C++.
    {
        tricell_neighbor_options o = options_with_cutoff(3.9);
        o.max_pairs = 1;
        const std::vector<Eigen::Vector3d> many(50, Eigen::Vector3d(1, 1, 1));
        tricell::NeighborOptions c;
        c.cutoff = 3.9;
        c.max_pairs = 1;
        std::string subject;
        try {
            tricell::compute_neighbors(cxx_box, many, c);
        } catch (const tricell::PairLimitError& e) {
            subject = e.subject();
        }
        ASSERT_FALSE(subject.empty());
        check(
            call_with(o, xyz(many), many.size()), TRICELL_ERROR_INVALID_ARGUMENT,
            subject +
                ", more than max_pairs = 1; raise tricell_neighbor_options.max_pairs to allow it");
    }
    // So does a refused memory limit, with the limit in bytes and GiB; 0 lifts it.
    {
        tricell_neighbor_options o = options_with_cutoff(3.9);
        EXPECT_EQ(o.max_bytes, tricell::default_max_bytes());
        o.max_bytes = 1000;
        const std::vector<Eigen::Vector3d> many(50, Eigen::Vector3d(1, 1, 1));
        tricell::NeighborOptions c;
        c.cutoff = 3.9;
        c.max_bytes = 1000;
        std::string subject;
        try {
            tricell::compute_neighbors(cxx_box, many, c);
        } catch (const tricell::PairLimitError& e) {
            subject = e.subject();
        }
        ASSERT_NE(subject.find(" bytes at its peak ("), std::string::npos) << subject;
        check(call_with(o, xyz(many), many.size()), TRICELL_ERROR_INVALID_ARGUMENT,
              subject + ", more than max_bytes = 1000 (9.31e-07 GiB); raise "
                        "tricell_neighbor_options.max_bytes to allow it (0 = no limit)");
        o.max_bytes = 0;
        EXPECT_EQ(call_with(o, xyz(many), many.size())(), TRICELL_OK) << tricell_last_error();
    }
    // Backend and variable cutoffs. Every backend of the library's table is a valid int.
    for (const tricell::SearchBackend backend : tricell::search_backends()) {
        tricell_neighbor_options o = good;
        o.backend = int(backend);
        EXPECT_EQ(call_with(o, xyz(two_atoms), 2)(), TRICELL_OK)
            << tricell::backend_name(backend) << ": " << tricell_last_error();
    }
    {
        tricell_neighbor_options o = good;
        o.backend = 9;
        check(call_with(o, xyz(two_atoms), 2), TRICELL_ERROR_INVALID_ARGUMENT,
              cxx([](auto& c) { c.backend = static_cast<tricell::SearchBackend>(9); }, two_atoms));
    }
    const double radii[2] = {0.5, 0.7};
    const double bad_radii[2] = {0.5, -1};
    const std::int32_t species[2] = {1, 2};
    const tricell_species_cutoff table[2] = {{1, 2, 1.2}, {2, 2, 0.8}};
    const tricell_species_cutoff bad_table[1] = {{1, 2, not_a_number}};
    struct Variable {
        const double* radii;
        const std::int32_t* species;
        const tricell_species_cutoff* table;
        std::size_t count;
        double cutoff;
    };
    const Variable variables[] = {
        {radii, nullptr, nullptr, 0, 1.5},   // radii and a cutoff
        {bad_radii, nullptr, nullptr, 0, 0}, // a negative radius
        {radii, species, table, 2, 0},       // radii and species cutoffs
        {nullptr, species, nullptr, 0, 0},   // species without a table
        {nullptr, species, bad_table, 1, 0}, // a bad table entry
        {nullptr, species, table, 2, 1.0},   // a table and a cutoff
    };
    for (const Variable& v : variables) {
        tricell_neighbor_options o = good;
        o.radii = v.radii;
        o.species = v.species;
        o.species_cutoffs = v.table;
        o.species_cutoff_count = v.count;
        o.cutoff = v.cutoff;
        const std::string message = cxx(
            [&](auto& c) {
                c.cutoff = v.cutoff;
                if (v.radii != nullptr) {
                    c.radii.assign(v.radii, v.radii + 2);
                }
                if (v.species != nullptr) {
                    c.species.assign(v.species, v.species + 2);
                }
                for (std::size_t k = 0; k < v.count; ++k) {
                    c.species_cutoffs.push_back({v.table[k].a, v.table[k].b, v.table[k].cutoff});
                }
            },
            two_atoms);
        ASSERT_FALSE(message.empty());
        check(call_with(o, xyz(two_atoms), 2), TRICELL_ERROR_INVALID_ARGUMENT, message);
    }
    {
        tricell_neighbor_options o = good;
        o.cutoff = 0;
        o.species = species;
        o.species_cutoff_count = 3;
        check(call_with(o, xyz(two_atoms), 2), TRICELL_ERROR_INVALID_ARGUMENT,
              "options.species_cutoffs is NULL but options.species_cutoff_count is 3");
    }
    // More atoms than the C++ API supports: refused from the count alone, nothing is read.
    {
        const std::size_t huge = std::size_t(1) << 31;
        tricell::NeighborOptions c;
        c.cutoff = 1.5;
        const std::string message = cxx_message([&] {
            tricell::compute_neighbors(cxx_box, tricell::PointsView(xyz(two_atoms), huge), c);
        });
        ASSERT_NE(message.find("positions are supported"), std::string::npos) << message;
        check(call_with(good, xyz(two_atoms), huge), TRICELL_ERROR_INVALID_ARGUMENT, message);
    }
    // Positions: NULL for N > 0, non-finite, too far away.
    check(call_with(good, nullptr, 2), TRICELL_ERROR_INVALID_ARGUMENT,
          "positions: null data for 2 points");
    for (double bad : {not_a_number, infinity, 1e300}) {
        const std::vector<Eigen::Vector3d> x = {{0, 0, 0}, {1, 1, 1}, {2, bad, 2}};
        const std::string message = cxx([](auto&) {}, x);
        ASSERT_FALSE(message.empty()) << bad;
        check(call_with(good, xyz(x), x.size()), TRICELL_ERROR_INVALID_ARGUMENT, message);
    }
}

TEST(CApiValidation, Neighbors_ZeroAtomsIsAnEmptyList) {
    auto search = make_search();
    auto list = make_list();
    const tricell_box box = cube();
    tricell_neighbor_options o = options_with_cutoff(2);
    for (int sorted : {0, 1}) {
        o.sorted = sorted;
        EXPECT_STATUS(tricell_neighbors(search.get(), &box, nullptr, 0, &o, list.get()), TRICELL_OK,
                      "");
        tricell_pairs pairs;
        ASSERT_EQ(tricell_neighbor_list_pairs(list.get(), &pairs), TRICELL_OK);
        EXPECT_EQ(pairs.size, 0u);
        EXPECT_NE(pairs.i, nullptr);
        EXPECT_NE(pairs.shifts, nullptr);
        EXPECT_NE(pairs.distances, nullptr);
        EXPECT_EQ(pairs.vectors, nullptr);
        EXPECT_EQ(pairs.atoms, 0u);
        EXPECT_EQ(pairs.offsets != nullptr, sorted == 1);
        if (pairs.offsets != nullptr) {
            EXPECT_EQ(pairs.offsets[0], 0u);
        }
    }
}

TEST(CApiValidation, Verlet_EveryBranch) {
    tricell_verlet_options good;
    EXPECT_STATUS(tricell_verlet_options_init(nullptr), TRICELL_ERROR_INVALID_ARGUMENT,
                  "tricell_verlet_options_init: options must not be NULL");
    ASSERT_EQ(tricell_verlet_options_init(&good), TRICELL_OK);
    good.neighbors.cutoff = 1.5;
    good.skin = 0.3;
    tricell_verlet* verlet = nullptr;
    EXPECT_STATUS(tricell_verlet_create(nullptr, &verlet), TRICELL_ERROR_INVALID_ARGUMENT,
                  "tricell_verlet_create: options must not be NULL");
    EXPECT_STATUS(tricell_verlet_create(&good, nullptr), TRICELL_ERROR_INVALID_ARGUMENT,
                  "tricell_verlet_create: verlet must not be NULL");

    auto cxx = [](auto set) {
        tricell::VerletOptions o;
        o.neighbors.cutoff = 1.5;
        o.skin = 0.3;
        set(o);
        return cxx_message([&] { tricell::VerletList list(o); });
    };
    static const double radius = 1.0;
    static const tricell_species_cutoff pair_cutoff = {0, 0, 1.0};
    struct Case {
        std::function<void(tricell_verlet_options&)> set_c;
        std::string message;
    };
    const Case cases[] = {
        {[](auto& o) { o.neighbors.cutoff = -1; }, cxx([](auto& o) { o.neighbors.cutoff = -1; })},
        {[](auto& o) { o.neighbors.cutoff = not_a_number; },
         cxx([](auto& o) { o.neighbors.cutoff = not_a_number; })},
        {[](auto& o) { o.skin = -0.5; }, cxx([](auto& o) { o.skin = -0.5; })},
        {[](auto& o) { o.skin = infinity; }, cxx([](auto& o) { o.skin = infinity; })},
        {[](auto& o) { o.neighbors.threads = -2; }, cxx([](auto& o) { o.neighbors.threads = -2; })},
        {[](auto& o) { o.neighbors.half = 3; }, "options.half must be 0 or 1 (got 3)"},
        {[](auto& o) { o.neighbors.vectors = 9; }, "options.vectors must be 0 or 1 (got 9)"},
        {[](auto& o) { o.neighbors.backend = 17; },
         cxx([](auto& o) { o.neighbors.backend = static_cast<tricell::SearchBackend>(17); })},
        {[](auto& o) { o.neighbors.radii = &radius; }, cxx([](auto& o) {
             o.neighbors.radii = {1.0, 1.0};
         })},
        {[](auto& o) {
             o.neighbors.species_cutoffs = &pair_cutoff;
             o.neighbors.species_cutoff_count = 1;
         },
         cxx([](auto& o) {
             o.neighbors.species_cutoffs = {{0, 0, 1.0}};
         })},
    };
    for (const Case& c : cases) {
        tricell_verlet_options o = good;
        c.set_c(o);
        ASSERT_FALSE(c.message.empty());
        EXPECT_STATUS(tricell_verlet_create(&o, &verlet), TRICELL_ERROR_INVALID_ARGUMENT,
                      c.message);
        EXPECT_EQ(verlet, nullptr) << "a failed create wrote its handle";
    }

    ASSERT_EQ(tricell_verlet_create(&good, &verlet), TRICELL_OK);
    VerletHandle handle(verlet);
    const tricell_box box = cube();
    tricell_pairs pairs;
    int rebuilt = -1;
    EXPECT_EQ(tricell_verlet_update(verlet, &box, xyz(two_atoms), 2, &rebuilt), TRICELL_OK);
    EXPECT_EQ(rebuilt, 1);
    EXPECT_STATUS(tricell_verlet_update(nullptr, &box, xyz(two_atoms), 2, &rebuilt),
                  TRICELL_ERROR_INVALID_ARGUMENT, "tricell_verlet_update: verlet must not be NULL");

    const int bad_periodic[3] = {0, 3, 1};
    const tricell_box bad_box = hand_box(cube_rows, bad_periodic);
    const std::vector<Eigen::Vector3d> not_finite = {{0, 0, 0}, {not_a_number, 1, 1}};
    const std::string not_finite_message = cxx_message([&] {
        tricell::VerletOptions o;
        o.neighbors.cutoff = 1.5;
        o.skin = 0.3;
        tricell::VerletList(o).update(tricell::Box::from_rows(Eigen::Matrix3d::Identity() * 4),
                                      not_finite);
    });
    ASSERT_FALSE(not_finite_message.empty());
    struct Failure {
        std::function<tricell_status()> call;
        std::string message;
    };
    const Failure failures[] = {
        {[&] { return tricell_verlet_update(verlet, nullptr, xyz(two_atoms), 2, &rebuilt); },
         "tricell_verlet_update: box must not be NULL"},
        {[&] { return tricell_verlet_update(verlet, &bad_box, xyz(two_atoms), 2, &rebuilt); },
         "periodic[1] must be 0 or 1 (got 3)"},
        {[&] { return tricell_verlet_update(verlet, &box, nullptr, 2, &rebuilt); },
         "positions: null data for 2 points"},
        {[&] { return tricell_verlet_update(verlet, &box, xyz(not_finite), 2, &rebuilt); },
         not_finite_message},
    };
    for (const Failure& f : failures) {
        rebuilt = -1;
        EXPECT_STATUS(f.call(), TRICELL_ERROR_INVALID_ARGUMENT, f.message);
        EXPECT_EQ(rebuilt, -1) << "a failed update wrote *rebuilt";
        ASSERT_EQ(tricell_verlet_pairs(verlet, &pairs), TRICELL_OK);
        EXPECT_EQ(pairs.size, 0u) << f.message;
        // The next update rebuilds.
        EXPECT_STATUS(tricell_verlet_update(verlet, &box, xyz(two_atoms), 2, &rebuilt), TRICELL_OK,
                      "");
        EXPECT_EQ(rebuilt, 1) << f.message;
        ASSERT_EQ(tricell_verlet_pairs(verlet, &pairs), TRICELL_OK);
        EXPECT_GT(pairs.size, 0u);
    }
    EXPECT_STATUS(tricell_verlet_update(verlet, &box, xyz(two_atoms), 2, nullptr), TRICELL_OK, "");
    EXPECT_STATUS(tricell_verlet_pairs(nullptr, &pairs), TRICELL_ERROR_INVALID_ARGUMENT,
                  "tricell_verlet_pairs: verlet must not be NULL");
    EXPECT_STATUS(tricell_verlet_pairs(verlet, nullptr), TRICELL_ERROR_INVALID_ARGUMENT,
                  "tricell_verlet_pairs: pairs must not be NULL");
}
