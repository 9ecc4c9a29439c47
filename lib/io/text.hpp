// Private helpers shared by the readers: whole-file input, a line cursor that knows its line
// number, strict number parsing and the per-format entry points.
#pragma once

#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

#include "tricell/error.hpp"
#include "tricell/io/structure.hpp"

namespace tricell::io::detail {

/// The whole file as bytes. Throws ParseError(path, 0, ...) when it cannot be read.
std::string read_file(const std::string& path);

/// Lines of a text with their 1-based numbers; "\r\n" endings are accepted.
class Lines {
  public:
    Lines(const std::string& text, std::string name);

    const std::string& name() const { return name_; }
    bool at_end() const { return next_ >= lines_.size(); }
    /// Number of the line that next() would return (one past the last line at the end).
    std::size_t number() const { return next_ + 1; }
    /// Lines not yet returned.
    std::size_t remaining() const { return lines_.size() - next_; }
    /// The next line; throws ParseError "unexpected end of file, expected WHAT" at the end.
    std::string_view next(const char* what);

    /// Throws ParseError at line `line` with the concatenated message.
    template <class... Args> [[noreturn]] void fail(std::size_t line, Args&&... args) const {
        tricell::detail::fail_parse(name_, line, std::forward<Args>(args)...);
    }

  private:
    std::string name_;
    std::vector<std::string_view> lines_;
    std::size_t next_ = 0;
};

/// Whitespace-separated words of a line.
std::vector<std::string_view> split_words(std::string_view line);
/// The words before the first one starting with '#' or '!' (a trailing comment).
std::vector<std::string_view> data_words(std::string_view line);

/// Strict conversions: the whole token must be the number. A real must be finite.
bool parse_real(std::string_view token, double& value);
bool parse_integer(std::string_view token, long long& value);

/// True for "T", "True", "1" (any case); false for "F", "False", "0"; anything else fails.
bool parse_bool(std::string_view token, bool& value);

/// Lower-case copy (ASCII).
std::string lower(std::string_view text);

/// Shortens a token for an error message (at most ~40 characters).
std::string quote(std::string_view token);

/// A message from another library (gemmi) made fit for one line of ours: control characters
/// (a newline, a tab, a NUL read from the file) become spaces.
std::string one_line(std::string_view message);

/// Per-format readers on the text of a file called `name`.
Structure parse_cif(const std::string& text, const std::string& name, const ReadOptions& options);
Structure parse_poscar(const std::string& text, const std::string& name,
                       const ReadOptions& options);
Structure parse_xyz(const std::string& text, const std::string& name, const ReadOptions& options);

} // namespace tricell::io::detail
