// DOC_CHECK(condition, what): the check of a page example's harness (tests/docs). Unlike assert
// it stays in optimised builds; a failure names the page's claim and ends the program with 1.
#pragma once

#include <cstdio>
#include <cstdlib>

#define DOC_CHECK(condition, what)                                                                 \
    do {                                                                                           \
        if (!(condition)) {                                                                        \
            std::fprintf(stderr, "%s:%d: the page's example does not do what it says: %s\n",       \
                         __FILE__, __LINE__, what);                                                \
            std::exit(1);                                                                          \
        }                                                                                          \
    } while (false)
