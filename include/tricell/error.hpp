// Errors thrown by tricell.
//
// One hierarchy: every exception tricell throws derives from tricell::Error (itself a
// std::runtime_error), so callers can catch everything with one handler, or tell invalid
// arguments, impossible geometry and malformed files apart. Messages name the offending value
// and where it came from, e.g. "cutoff must be > 0 (got -1.5)" or
// "quartz.cif:42: _cell_angle_beta is missing".
#pragma once

#include <cstddef>
#include <sstream>
#include <stdexcept>
#include <string>
#include <utility>

#include "tricell/export.hpp"

namespace tricell {

/// Base of every exception tricell throws.
class TRICELL_API Error : public std::runtime_error {
  public:
    using std::runtime_error::runtime_error;
};

/// An argument outside its documented domain (a cutoff <= 0, a non-finite position, ...).
class TRICELL_API InvalidArgument : public Error {
  public:
    using Error::Error;
};

/// A box or configuration that cannot be handled (singular box, zero periodic vector, ...).
class TRICELL_API GeometryError : public Error {
  public:
    using Error::Error;
};

/// Malformed input file. what() reads "FILE:LINE: message" (or "FILE: message" when the line
/// is unknown, i.e. line() == 0).
class TRICELL_API ParseError : public Error {
  public:
    ParseError(std::string file, std::size_t line, const std::string& message);
    const std::string& file() const noexcept { return file_; }
    std::size_t line() const noexcept { return line_; }
    /// The message without the "FILE:LINE: " prefix.
    const std::string& message() const noexcept { return message_; }

  private:
    std::string file_;
    std::size_t line_;
    std::string message_;
};

namespace detail {

/// Concatenates the arguments with operator<< (doubles with 12 significant digits).
template <class... Args> std::string cat(Args&&... args) {
    std::ostringstream out;
    out.precision(12);
    (out << ... << std::forward<Args>(args));
    return out.str();
}

/// The one place tricell throws from: fail<InvalidArgument>("cutoff must be > 0 (got ", c, ")").
template <class E, class... Args> [[noreturn]] void fail(Args&&... args) {
    throw E(cat(std::forward<Args>(args)...));
}

/// ParseError variant: fail_parse(file, line, "what is wrong ", value).
template <class... Args>
[[noreturn]] void fail_parse(const std::string& file, std::size_t line, Args&&... args) {
    throw ParseError(file, line, cat(std::forward<Args>(args)...));
}

} // namespace detail
} // namespace tricell
