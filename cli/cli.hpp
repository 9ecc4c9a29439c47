// Shared pieces of the `tricell` command: usage errors, a small argument cursor, reading the
// input structure, real-number formatting and an output that is written completely or not at all.
#pragma once

#include <cstdio>
#include <stdexcept>
#include <string>
#include <vector>

#include <tricell/io/structure.hpp>

namespace tricell::cli {

/// A malformed command line; main() prints it and exits with status 2.
class UsageError : public std::runtime_error {
  public:
    using std::runtime_error::runtime_error;
};

/// The exit status of `neighbors --verify` when the list fails its check.
constexpr int verify_failed = 3;

class Arguments;

/// One line of the usage text (tricell --help): "NAME ARGS" and what it does, in one sentence
/// that the usage text wraps.
struct UsageLine {
    const char* args;    // "FILE --cutoff R"
    const char* summary; // "all pairs closer than R, with image shifts and vectors"
};

/// A subcommand: a row of the table in dispatch.cpp, from which the usage text, the dispatch
/// and the "unknown command" error come.
struct Command {
    const char* name;                 // "neighbors"
    const char* alias;                // another spelling run() accepts ("neighbours"), or nullptr
    std::vector<UsageLine> usage;     // its lines in the usage text, at least one
    std::string (*help)();            // the text of 'tricell NAME --help'
    int (*run)(Arguments& arguments); // the handler
};

/// Walks the arguments of a subcommand. Options take their value as the next argument or after
/// '=' ("--cutoff 3" or "--cutoff=3"); "--" ends the options.
class Arguments {
  public:
    /// The arguments of `command` (its name starts every failure; its help is printed_help()'s).
    Arguments(const Command& command, std::vector<std::string> args);

    /// Moves to the next argument; false at the end.
    bool next();
    /// The current argument is --help or -h: prints the command's help to standard output and
    /// returns true (the handler then returns 0).
    bool printed_help();
    /// The current argument is the flag `name` ("--half").
    bool flag(const char* name);
    /// The current argument is the option `name`; its value is then value().
    bool option(const char* name);
    /// Value of the option just matched.
    const std::string& value() const { return value_; }
    /// Value of the option just matched, as a finite real.
    double real() const;
    /// Value of the option just matched, as a whole number in [low, high] (UsageError
    /// "--name must be a whole number in [low, high], got 'value'" otherwise).
    std::size_t whole(std::size_t low, std::size_t high) const;
    /// The current argument is a positional one (not starting with '-', or after "--").
    bool positional() const;
    const std::string& current() const { return args_[index_]; }
    /// Throws UsageError for the current argument.
    [[noreturn]] void unknown() const;
    /// Throws UsageError with "COMMAND: message (see tricell COMMAND --help)".
    [[noreturn]] void fail(const std::string& message) const;

  private:
    const Command& command_;
    std::vector<std::string> args_;
    std::size_t index_ = 0;
    bool started_ = false;
    bool options_ended_ = false;
    std::string value_;
    std::string matched_;
};

/// Parses "cif", "xyz", "poscar", ... for --input-format (UsageError otherwise).
io::Format input_format(const Arguments& arguments, const std::string& name);

/// The arguments every command shares: consumes the current argument if it is
/// --input-format F or the (first) positional FILE, and says whether it did.
bool take_input(Arguments& arguments, io::ReadOptions& read_options, std::string& file);
/// --max-pairs N (a whole number, 0 = no limit): consumes it into max_pairs and says whether
/// it did. The library refuses a larger list before allocating it.
bool take_max_pairs(Arguments& arguments, std::size_t& max_pairs);
/// --max-bytes N (bytes, or with a suffix K, M, G or T for powers of 1024; 0 = no limit):
/// consumes it into max_bytes and says whether it did. The library refuses a list whose memory
/// would pass it before allocating it.
bool take_max_bytes(Arguments& arguments, std::size_t& max_bytes);
/// The text formats of the tables (--format).
enum class TableFormat { tsv, csv, json };
/// --format tsv|csv|json: consumes it into format and says whether it did.
bool take_format(Arguments& arguments, TableFormat& format);

/// --threads T (0 = all hardware threads, at most 1024): consumes it and says whether it did.
bool take_threads(Arguments& arguments, int& threads);
/// --quiet: consumes it into quiet and says whether it did.
bool take_quiet(Arguments& arguments, bool& quiet);

/// UsageError "missing FILE" when no FILE was given.
void require_file(const Arguments& arguments, const std::string& file);

/// "a, b or c" (for lists of choices in messages and help texts).
std::string choices(const std::vector<std::string>& items);
/// Width of the help and usage texts that wrap().
constexpr std::size_t text_width = 96;
/// `text` broken into lines at spaces so that no line passes text_width, the first line taken
/// to start at column `first` and every further one indented by `indent` spaces; no final
/// newline.
std::string wrap(const std::string& text, std::size_t first, std::size_t indent);

/// The shortest text that reads back as the same double (write_real in text.hpp).
std::string exact(double value);
/// %.10g: for people.
std::string brief(double value);

/// Where a command writes: standard output, or the file PATH written through a temporary file
/// in the same directory that is renamed over PATH by commit(). Until then PATH is untouched;
/// if the command fails first, the destructor removes the temporary file.
class Output {
  public:
    explicit Output(const std::string& path);
    ~Output();
    Output(const Output&) = delete;
    Output& operator=(const Output&) = delete;

    std::FILE* stream() const { return stream_; }
    void write(const std::string& text) { write(text.data(), text.size()); }
    void write(const char* text, std::size_t size);
    /// Flushes and, for a file, closes and renames it into place. Throws std::runtime_error.
    void commit();

  private:
    std::string path_;
    std::string temporary_;
    std::FILE* stream_ = nullptr;
    bool committed_ = false;
};

/// The whole command: args as after the program name ("neighbors", "x.cif", "--cutoff", "3").
/// Prints errors as one line on stderr and returns the exit status (see dispatch.cpp).
int run(const std::vector<std::string>& args);

} // namespace tricell::cli
