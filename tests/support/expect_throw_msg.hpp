// EXPECT_THROW_MSG(statement, ExceptionType, substring): the statement throws ExceptionType
// (or a subclass) and what() contains the substring. Checks the message, not only the type.
#pragma once

#include <string>

#include <gtest/gtest.h>

#define EXPECT_THROW_MSG(statement, exception_type, substring)                                     \
    do {                                                                                           \
        bool tricell_thrown_ = false;                                                              \
        try {                                                                                      \
            statement;                                                                             \
        } catch (const exception_type& e) {                                                        \
            tricell_thrown_ = true;                                                                \
            EXPECT_NE(std::string(e.what()).find(substring), std::string::npos)                    \
                << "message was: " << e.what();                                                    \
        }                                                                                          \
        EXPECT_TRUE(tricell_thrown_) << #statement " did not throw " #exception_type;              \
    } while (0)
