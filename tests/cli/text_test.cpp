// Exact text output of the command (cli/text.hpp): every real written reads back as the
// same double and no shorter text would, over random bit patterns (all exponents, subnormals)
// and the special values; TextSink keeps the order of everything put through any buffer size.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "cli.hpp"
#include "text.hpp"

namespace {

double from_bits(std::uint64_t bits) {
    double x;
    std::memcpy(&x, &bits, sizeof x);
    return x;
}

std::uint64_t to_bits(double x) {
    std::uint64_t bits;
    std::memcpy(&bits, &x, sizeof bits);
    return bits;
}

// Significant digits of a decimal text ("-1.25e-3" has 3).
int significant_digits(const std::string& text) {
    std::string digits;
    for (char c : text) {
        if (c == 'e') {
            break;
        }
        if (c >= '0' && c <= '9') {
            digits += c;
        }
    }
    const std::size_t first = digits.find_first_not_of('0');
    if (first == std::string::npos) {
        return 1;
    }
    const std::size_t last = digits.find_last_not_of('0');
    // Trailing zeros of an integer written without exponent are not significant either.
    return int(last - first + 1);
}

void expect_exact_and_shortest(double x) {
    const std::string text = tricell::cli::exact(x);
    SCOPED_TRACE(text);
    char* end = nullptr;
    const double back = std::strtod(text.c_str(), &end);
    ASSERT_EQ(*end, '\0');
    EXPECT_EQ(to_bits(back), to_bits(x)); // also tells -0 from +0
    const int digits = significant_digits(text);
    EXPECT_LE(digits, 17);
    if (digits > 1) {
        // No text with one digit fewer reads back as x (%.*e rounds correctly).
        char shorter[64];
        std::snprintf(shorter, sizeof shorter, "%.*e", digits - 2, x);
        EXPECT_NE(std::strtod(shorter, nullptr), x) << shorter;
    }
}

TEST(ExactText, SpecialValuesReadBackExactly) {
    const double values[] = {0.0,
                             -0.0,
                             1.0,
                             -1.0,
                             0.1,
                             1.0 / 3.0,
                             1e300,
                             -1e300,
                             1e-300,
                             1e16,
                             123456789012345680.0,
                             std::numeric_limits<double>::max(),
                             std::numeric_limits<double>::lowest(),
                             std::numeric_limits<double>::min(),        // smallest normal
                             std::numeric_limits<double>::denorm_min(), // 5e-324
                             -std::numeric_limits<double>::denorm_min(),
                             2.2250738585072009e-308, // largest subnormal
                             std::nextafter(1.0, 2.0),
                             std::nextafter(1.0, 0.0)};
    for (double x : values) {
        expect_exact_and_shortest(x);
    }
    EXPECT_EQ(tricell::cli::exact(0.1), "0.1");
    EXPECT_EQ(tricell::cli::exact(-0.0), "-0");
    EXPECT_EQ(tricell::cli::exact(1e300), "1e+300");
    EXPECT_EQ(tricell::cli::exact(5e-324), "5e-324");
    EXPECT_EQ(tricell::cli::exact(std::numeric_limits<double>::infinity()), "inf");
    EXPECT_EQ(tricell::cli::exact(-std::numeric_limits<double>::infinity()), "-inf");
    EXPECT_EQ(tricell::cli::exact(std::numeric_limits<double>::quiet_NaN()), "nan");
}

TEST(ExactText, RandomBitPatternsReadBackExactly) {
    for (std::uint64_t seed = 1; seed <= 4; ++seed) {
        SCOPED_TRACE(seed);
        std::mt19937_64 random(seed);
        for (int k = 0; k < 50000; ++k) {
            std::uint64_t bits = random();
            if (k % 4 == 1) {
                bits &= 0x800FFFFFFFFFFFFFULL; // exponent 0: subnormals (and +-0)
            }
            const double x = from_bits(bits);
            if (std::isfinite(x)) {
                expect_exact_and_shortest(x);
            }
        }
    }
}

TEST(ExactText, RandomDistancesReadBackExactly) {
    // The values a neighbour list holds: lengths and components of a few Angstrom.
    std::mt19937_64 random(15);
    std::uniform_real_distribution<double> u(-12, 12);
    for (int k = 0; k < 200000; ++k) {
        expect_exact_and_shortest(u(random));
    }
}

// Everything put through a TextSink arrives in order, whatever the buffer size, also text
// longer than the buffer.
TEST(TextSink, KeepsOrderAcrossFlushes) {
    const std::filesystem::path dir = std::filesystem::temp_directory_path();
    for (std::size_t capacity : {std::size_t(1), std::size_t(300), std::size_t(1) << 20}) {
        SCOPED_TRACE(capacity);
        const std::string path =
            (dir / ("tricell-text-test-" + std::to_string(capacity) + ".txt")).string();
        std::mt19937_64 random(capacity);
        std::string expected;
        {
            tricell::cli::Output out(path);
            tricell::cli::TextSink sink(out, capacity);
            for (int k = 0; k < 20000; ++k) {
                const double x = from_bits(random());
                const std::int64_t n = std::int64_t(random());
                const std::uint32_t u = std::uint32_t(random());
                sink.put_real(x);
                sink.put('\t');
                sink.put_integer(n);
                sink.put(',');
                sink.put_integer(u);
                expected +=
                    tricell::cli::exact(x) + "\t" + std::to_string(n) + "," + std::to_string(u);
                if (k % 1000 == 0) {
                    const std::string long_text(700, char('a' + k % 26));
                    sink.put(long_text);
                    expected += long_text;
                }
                sink.put('\n');
                expected += '\n';
            }
            sink.flush();
            out.commit();
        }
        std::ifstream in(path, std::ios::binary);
        std::ostringstream written;
        written << in.rdbuf();
        EXPECT_EQ(written.str(), expected);
        std::filesystem::remove(path);
    }
}

// write_blocks() puts every item once and in order, for any block size and number of threads.
TEST(TextSink, BlocksOnThreadsKeepTheOrder) {
    const std::filesystem::path path =
        std::filesystem::temp_directory_path() / "tricell-text-blocks.txt";
    for (const std::size_t n :
         {std::size_t(0), std::size_t(1), std::size_t(1000), std::size_t(12345)}) {
        for (const std::size_t block :
             {std::size_t(1), std::size_t(7), std::size_t(1000), std::size_t(50000)}) {
            for (const int threads : {1, 2, 3, 8}) {
                SCOPED_TRACE(std::to_string(n) + " items, blocks of " + std::to_string(block) +
                             ", " + std::to_string(threads) + " threads");
                std::vector<std::size_t> progress;
                {
                    tricell::cli::Output out(path.string());
                    tricell::cli::TextSink sink(out, 256);
                    tricell::cli::write_blocks(
                        sink, n, threads, block,
                        [](tricell::cli::TextSink& s, std::size_t begin, std::size_t end) {
                            for (std::size_t k = begin; k < end; ++k) {
                                s.put_real(double(k) / 7);
                                s.put('\n');
                            }
                        },
                        [&](std::size_t done) { progress.push_back(done); });
                    sink.flush();
                    out.commit();
                }
                std::string expected;
                for (std::size_t k = 0; k < n; ++k) {
                    expected += tricell::cli::exact(double(k) / 7) + "\n";
                }
                std::ifstream in(path, std::ios::binary);
                std::ostringstream written;
                written << in.rdbuf();
                EXPECT_EQ(written.str(), expected);
                EXPECT_TRUE(std::is_sorted(progress.begin(), progress.end()));
                if (n > 0) {
                    ASSERT_FALSE(progress.empty());
                    EXPECT_EQ(progress.back(), n);
                }
            }
        }
    }
    std::filesystem::remove(path);
}

} // namespace
