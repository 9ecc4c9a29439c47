// Fast exact text for the command's tables. Reals are written in the shortest form that reads
// back to the same double (std::to_chars in general format without a precision: the fewest
// significant digits that round-trip, at most 17, "0.1" rather than "0.10000000000000001", with
// printf %g's choice of fixed or exponent notation; the plain shortest format would print
// 5e18 with all of its 19 integer digits), integers with std::to_chars, all into one large
// buffer that is reused and handed to the Output in big blocks, so a table of millions of rows
// costs a few fwrite calls and no allocation or printf parsing per number.
#pragma once

#include <charconv>
#include <cstddef>
#include <string>
#include <string_view>
#include <system_error>
#include <vector>

namespace tricell::cli {

class Output;

/// Longest text write_real() produces ("-2.2250738585072014e-308" is 24 characters).
constexpr std::size_t max_real_chars = 32;

/// Writes `value` at `at` in the shortest form that reads back exactly (nan, inf and -inf as
/// such) and returns the end. `at` must have max_real_chars of room.
inline char* write_real(char* at, double value) {
    return std::to_chars(at, at + max_real_chars, value, std::chars_format::general).ptr;
}

/// A JSON string literal of `text` (quotes, backslashes and control characters escaped).
std::string json_string(const std::string& text);

/// A text buffer in front of an Output: put() appends, and the buffer goes to the Output
/// whenever it is nearly full and on flush(). Call flush() before Output::commit().
class TextSink {
  public:
    explicit TextSink(Output& out, std::size_t capacity = std::size_t(1) << 20);
    TextSink(const TextSink&) = delete;
    TextSink& operator=(const TextSink&) = delete;

    void put(char c) {
        room(1);
        *end_++ = c;
    }
    void put(std::string_view text);
    void put_real(double value) {
        room(max_real_chars);
        end_ = write_real(end_, value);
    }
    template <class Integer> void put_integer(Integer value) {
        room(24);
        end_ = std::to_chars(end_, end_ + 24, value).ptr;
    }
    /// Hands the buffered text to the Output.
    void flush();

  private:
    void room(std::size_t n) {
        if (std::size_t(limit_ - end_) < n) {
            flush();
        }
    }

    Output& out_;
    std::vector<char> buffer_;
    char* end_;
    char* limit_;
};

} // namespace tricell::cli
