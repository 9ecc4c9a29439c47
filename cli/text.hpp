// Fast exact text for the command's tables. Reals are written in the shortest form that reads
// back to the same double (std::to_chars in general format without a precision: the fewest
// significant digits that round-trip, at most 17, "0.1" rather than "0.10000000000000001", with
// printf %g's choice of fixed or exponent notation; the plain shortest format would print
// 5e18 with all of its 19 integer digits), integers with std::to_chars, all into one large
// buffer that is reused and handed to the Output in big blocks, so a table of millions of rows
// costs a few fwrite calls and no allocation or printf parsing per number. Formatting a real
// costs several times more than writing its bytes, so write_blocks() lets T threads format
// consecutive blocks of rows into memory while the text still reaches the Output in order:
// the output is the same for any T.
#pragma once

#include <charconv>
#include <cstddef>
#include <exception>
#include <string>
#include <string_view>
#include <system_error>
#include <thread>
#include <vector>

#include "cli.hpp"

namespace tricell::cli {

/// Longest text write_real() produces ("-2.2250738585072014e-308" is 24 characters).
constexpr std::size_t max_real_chars = 32;

/// Writes `value` at `at` in the shortest form that reads back exactly (nan, inf and -inf as
/// such) and returns the end. `at` must have max_real_chars of room.
inline char* write_real(char* at, double value) {
    return std::to_chars(at, at + max_real_chars, value, std::chars_format::general).ptr;
}

/// A JSON string literal of `text` (quotes, backslashes and control characters escaped).
std::string json_string(const std::string& text);

/// A text buffer in front of an Output (or of a string): put() appends, and the buffer goes to
/// the Output whenever it is nearly full and on flush(). Call flush() before Output::commit().
class TextSink {
  public:
    explicit TextSink(Output& out, std::size_t capacity = std::size_t(1) << 20);
    /// Collects the text in `text` (appended on flush()) instead of writing it.
    explicit TextSink(std::string& text, std::size_t capacity = std::size_t(1) << 16);
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

    Output* out_ = nullptr;
    std::string* text_ = nullptr;
    std::vector<char> buffer_;
    char* end_;
    char* limit_;
};

/// Writes what write(TextSink&) puts to `path` (standard output when empty), completely or not
/// at all (Output).
template <class Write> void write_text(const std::string& path, Write&& write) {
    Output out(path);
    TextSink sink(out);
    write(sink);
    sink.flush();
    out.commit();
}

/// Formats items [0, n) into `sink` in order: format(TextSink& s, begin, end) writes the items
/// [begin, end) into s. threads 0 means all hardware threads. With threads > 1, rounds of `threads`
/// blocks of `block` items are formatted at once, each into its own memory, and then put into
/// `sink` in order; after each round done(items so far) is called on this thread.
template <class Format, class Done>
void write_blocks(TextSink& sink, std::size_t n, int threads, std::size_t block, Format&& format,
                  Done&& done) {
    if (threads == 0) {
        threads = int(std::thread::hardware_concurrency());
    }
    if (threads <= 1 || n <= block) {
        for (std::size_t begin = 0; begin < n; begin += block) {
            const std::size_t end = n - begin < block ? n : begin + block;
            format(sink, begin, end);
            done(end);
        }
        return;
    }
    std::vector<std::string> texts(static_cast<std::size_t>(threads));
    std::vector<std::exception_ptr> errors(texts.size());
    for (std::size_t round = 0; round < n; round += block * texts.size()) {
        std::vector<std::thread> workers;
        for (std::size_t t = 0; t < texts.size(); ++t) {
            const std::size_t begin = round + t * block;
            if (begin >= n) {
                break;
            }
            const std::size_t end = n - begin < block ? n : begin + block;
            workers.emplace_back([&format, &texts, &errors, t, begin, end] {
                try { // an exception must not leave a thread (std::terminate)
                    texts[t].clear();
                    TextSink part(texts[t]);
                    format(part, begin, end);
                    part.flush();
                } catch (...) {
                    errors[t] = std::current_exception();
                }
            });
        }
        for (std::thread& worker : workers) {
            worker.join();
        }
        for (std::size_t t = 0; t < workers.size(); ++t) {
            if (errors[t]) {
                std::rethrow_exception(errors[t]);
            }
            sink.put(texts[t]);
        }
        const std::size_t formatted = round + block * texts.size();
        done(formatted < n ? formatted : n);
    }
}

} // namespace tricell::cli
