// tricell_verify: tricell's own C lists pass on random systems (full and half, every backend);
// a list with a pair dropped, an index out of range or a pair added beyond the cutoff fails with
// the words of the C++ report; bad arguments give a status and a message naming the C argument.
#include <cstdint>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "c_api_support.hpp"
#include "tricell.h"

using namespace tricell::testing;

namespace {

TEST(CVerify, OwnListsPass_EveryBackend) {
    auto search = make_search();
    auto list = make_list();
    for (std::uint64_t seed = 0; seed < 60; ++seed) {
        const RandomSystem sys = random_system(seed);
        const tricell_box box = c_box(sys);
        tricell_neighbor_options options;
        ASSERT_EQ(tricell_neighbor_options_init(&options), TRICELL_OK);
        options.cutoff = sys.cutoff;
        options.half = int(seed % 2);
        options.vectors = 1;
        options.backend = int(seed % 6);
        SCOPED_TRACE("seed " + std::to_string(seed));
        ASSERT_EQ(tricell_neighbors(search.get(), &box, xyz(sys.positions), sys.positions.size(),
                                    &options, list.get()),
                  TRICELL_OK)
            << tricell_last_error();
        tricell_pairs pairs;
        ASSERT_EQ(tricell_neighbor_list_pairs(list.get(), &pairs), TRICELL_OK);
        tricell_verify_report report;
        ASSERT_EQ(tricell_verify(&box, xyz(sys.positions), sys.positions.size(), &options, &pairs,
                                 &report),
                  TRICELL_OK)
            << tricell_last_error();
        EXPECT_EQ(report.ok, 1) << report.message;
        EXPECT_EQ(report.entries, pairs.size);
        EXPECT_STREQ(report.reference, "brute force");
        EXPECT_EQ(std::string(report.message).rfind("ok: ", 0), 0u) << report.message;
    }
}

struct Case {
    RandomSystem sys = random_system(3);
    tricell_box box;
    tricell_neighbor_options options;
    std::vector<std::uint32_t> i, j;
    std::vector<std::int32_t> s;
    std::vector<double> d;
    Case() {
        box = c_box(sys);
        tricell_neighbor_options_init(&options);
        options.cutoff = sys.cutoff;
        auto search = make_search();
        auto list = make_list();
        tricell_neighbors(search.get(), &box, xyz(sys.positions), sys.positions.size(), &options,
                          list.get());
        tricell_pairs pairs;
        tricell_neighbor_list_pairs(list.get(), &pairs);
        i.assign(pairs.i, pairs.i + pairs.size);
        j.assign(pairs.j, pairs.j + pairs.size);
        s.assign(pairs.shifts, pairs.shifts + 3 * pairs.size);
        d.assign(pairs.distances, pairs.distances + pairs.size);
    }
    tricell_status check(tricell_verify_report& report, std::size_t size) const {
        tricell_pairs pairs{};
        pairs.size = size;
        pairs.i = i.data();
        pairs.j = j.data();
        pairs.shifts = s.data();
        pairs.distances = d.data();
        return tricell_verify(&box, xyz(sys.positions), sys.positions.size(), &options, &pairs,
                              &report);
    }
};

TEST(CVerify, DefectsAreReportedInWords) {
    Case c;
    ASSERT_GT(c.i.size(), 2u);
    tricell_verify_report report;
    ASSERT_EQ(c.check(report, c.i.size()), TRICELL_OK);
    EXPECT_EQ(report.ok, 1) << report.message;

    ASSERT_EQ(c.check(report, c.i.size() - 1), TRICELL_OK); // the last pair dropped
    EXPECT_EQ(report.ok, 0);
    EXPECT_EQ(report.missing, 1u);
    EXPECT_NE(std::string(report.message).find("is missing"), std::string::npos) << report.message;

    Case range;
    range.j[1] = std::uint32_t(range.sys.positions.size());
    ASSERT_EQ(range.check(report, range.i.size()), TRICELL_OK);
    EXPECT_EQ(report.ok, 0);
    EXPECT_NE(std::string(report.message).find("is out of range for"), std::string::npos)
        << report.message;
}

TEST(CVerify, BadArgumentsGiveAStatus) {
    Case c;
    tricell_verify_report report;
    report.ok = 7;
    tricell_pairs pairs{};
    pairs.size = 1;
    EXPECT_EQ(tricell_verify(&c.box, xyz(c.sys.positions), c.sys.positions.size(), &c.options,
                             &pairs, &report),
              TRICELL_ERROR_INVALID_ARGUMENT);
    EXPECT_STREQ(tricell_last_error(), "tricell_verify: pairs->i must not be NULL");
    EXPECT_EQ(report.ok, 7);
    EXPECT_EQ(tricell_verify(&c.box, xyz(c.sys.positions), c.sys.positions.size(), &c.options,
                             &pairs, nullptr),
              TRICELL_ERROR_INVALID_ARGUMENT);
    EXPECT_STREQ(tricell_last_error(), "tricell_verify: report must not be NULL");
    std::vector<Eigen::Vector3d> x = c.sys.positions;
    x[0].x() = std::nan("");
    EXPECT_EQ(c.check(report, 0), TRICELL_OK);
    EXPECT_EQ(tricell_verify(&c.box, xyz(x), x.size(), &c.options, &pairs, &report),
              TRICELL_ERROR_INVALID_ARGUMENT);
    pairs.size = 0;
    EXPECT_EQ(tricell_verify(&c.box, xyz(x), x.size(), &c.options, &pairs, &report),
              TRICELL_ERROR_INVALID_ARGUMENT);
    EXPECT_NE(std::string(tricell_last_error()).find("position 0 is not finite"), std::string::npos)
        << tricell_last_error();
    tricell_neighbor_options bad = c.options;
    bad.half = 2;
    EXPECT_EQ(
        tricell_verify(&c.box, xyz(c.sys.positions), c.sys.positions.size(), &bad, &pairs, &report),
        TRICELL_ERROR_INVALID_ARGUMENT);
    EXPECT_NE(std::string(tricell_last_error()).find("half must be 0 or 1"), std::string::npos)
        << tricell_last_error();
}

} // namespace
