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

/// A neighbour list larger than one of its limits: more pairs than NeighborOptions::max_pairs
/// (or a front end's own pair limit), or more memory than NeighborOptions::max_bytes (which()
/// tells them apart). Refused before anything large is allocated (from the estimate) or as soon
/// as the stored pairs pass the limit. It carries its fields so that every front end can name
/// the limit in its own terms (the command line's --max-pairs or --max-bytes, the C struct's
/// field, Python's keyword): what() names the NeighborOptions field, message_for() any other
/// name.
class TRICELL_API PairLimitError : public InvalidArgument {
  public:
    /// Which limit refused the list.
    enum class Limit { pairs, bytes };
    /// A refused pair limit. `subject` says what is too large, e.g. "cutoff 3 would give about
    /// 1.2e9 pairs for 1000 atoms (estimated from the density)"; `pairs` is that estimate, or for
    /// a list refused while it was being stored the first count past the limit (limit + 1).
    PairLimitError(std::string subject, double pairs, std::size_t limit);
    /// A refused memory limit: `subject` names the pairs and their `bytes` (the list's memory at
    /// its peak, docs/memory.md), `max_bytes` the limit.
    PairLimitError(std::string subject, double pairs, double bytes, std::size_t max_bytes);
    const std::string& subject() const noexcept { return subject_; }
    Limit which() const noexcept { return which_; }
    double pairs() const noexcept { return pairs_; }
    /// The list's memory at its peak (a memory limit; 0 for a pair limit).
    double bytes() const noexcept { return bytes_; }
    /// The limit: pairs or bytes, as which() says.
    std::size_t limit() const noexcept { return limit_; }
    /// The limit's value in words: "500000000" (pairs) or "17179869184 (16 GiB)" (bytes).
    std::string limit_text() const;
    /// "SUBJECT, more than LIMIT_TEXT; raise RAISE to allow it", e.g. message_for("--max-pairs
    /// 100", "--max-pairs"); a memory limit adds " (0 = no limit)".
    std::string message_for(const std::string& limit_text, const std::string& raise) const;
    /// The same error about `subject` instead (a caller that says where the list came from).
    PairLimitError with_subject(std::string subject) const;

  private:
    std::string subject_;
    Limit which_;
    double pairs_;
    double bytes_;
    std::size_t limit_;
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

/// Concatenates the arguments with operator<< (doubles with 12 significant digits). Out of memory
/// throws std::bad_alloc (a stream would only set its badbit and lose the rest of the text).
template <class... Args> std::string cat(Args&&... args) {
    std::ostringstream out;
    out.exceptions(std::ios::badbit);
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
