#include <gtest/gtest.h>

#include "tricell/error.hpp"

TEST(Error, ParseErrorNamesFileAndLine) {
    const tricell::ParseError e("quartz.cif", 42, "_cell_angle_beta is missing");
    EXPECT_STREQ(e.what(), "quartz.cif:42: _cell_angle_beta is missing");
    EXPECT_EQ(e.file(), "quartz.cif");
    EXPECT_EQ(e.line(), 42u);
    EXPECT_EQ(e.message(), "_cell_angle_beta is missing");
}

TEST(Error, ParseErrorWithoutLineOmitsIt) {
    const tricell::ParseError e("empty.xyz", 0, "file is empty");
    EXPECT_STREQ(e.what(), "empty.xyz: file is empty");
}

TEST(Error, FailThrowsTheRequestedTypeWithFormattedMessage) {
    try {
        tricell::detail::fail<tricell::InvalidArgument>("cutoff must be > 0 (got ", -1.5, ")");
        FAIL() << "fail() returned";
    } catch (const tricell::InvalidArgument& e) {
        EXPECT_STREQ(e.what(), "cutoff must be > 0 (got -1.5)");
    }
}

TEST(Error, AllErrorsDeriveFromError) {
    EXPECT_THROW(throw tricell::GeometryError("x"), tricell::Error);
    EXPECT_THROW(throw tricell::ParseError("f", 1, "x"), tricell::Error);
    EXPECT_THROW(throw tricell::InvalidArgument("x"), std::runtime_error);
}
