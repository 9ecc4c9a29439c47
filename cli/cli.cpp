#include "cli.hpp"
#include "text.hpp"

#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <utility>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <tricell/error.hpp>

namespace tricell::cli {

Arguments::Arguments(const Command& command, std::vector<std::string> args)
    : command_(command), args_(std::move(args)) {}

bool Arguments::next() {
    if (started_) {
        ++index_;
    }
    started_ = true;
    if (index_ < args_.size() && !options_ended_ && args_[index_] == "--") {
        options_ended_ = true;
        ++index_;
    }
    return index_ < args_.size();
}

bool Arguments::printed_help() {
    if (flag("--help") || flag("-h")) {
        std::fputs(command_.help().c_str(), stdout);
        return true;
    }
    return false;
}

bool Arguments::flag(const char* name) {
    const std::string& arg = current();
    if (options_ended_) {
        return false;
    }
    if (arg == name) {
        return true;
    }
    if (arg.rfind(std::string(name) + "=", 0) == 0) {
        fail(std::string(name) + " takes no value");
    }
    return false;
}

bool Arguments::option(const char* name) {
    const std::string& arg = current();
    if (options_ended_) {
        return false;
    }
    const std::string prefix = std::string(name) + "=";
    if (arg.rfind(prefix, 0) == 0) {
        value_ = arg.substr(prefix.size());
    } else if (arg == name) {
        if (index_ + 1 >= args_.size()) {
            fail(std::string(name) + " needs a value");
        }
        value_ = args_[++index_];
    } else {
        return false;
    }
    matched_ = name;
    if (value_.empty()) {
        fail(matched_ + " needs a value");
    }
    return true;
}

double Arguments::real() const {
    const char* begin = value_.c_str();
    char* end = nullptr;
    errno = 0;
    const double x = std::strtod(begin, &end);
    if (end == begin || *end != '\0' || errno == ERANGE || !std::isfinite(x)) {
        fail(matched_ + " expects a number, got '" + value_ + "'");
    }
    return x;
}

std::size_t Arguments::whole(std::size_t low, std::size_t high) const {
    const double x = real();
    if (!(x >= double(low) && x <= double(high)) || x != std::floor(x)) {
        fail(matched_ + " must be a whole number in [" + std::to_string(low) + ", " +
             std::to_string(high) + "], got '" + value_ + "'");
    }
    return std::size_t(x);
}

bool Arguments::positional() const {
    const std::string& arg = current();
    return options_ended_ || arg.empty() || arg[0] != '-' || arg == "-";
}

void Arguments::unknown() const {
    if (positional()) {
        fail("unexpected argument '" + current() + "'");
    }
    fail("unknown option '" + current() + "'");
}

void Arguments::fail(const std::string& message) const {
    const std::string name = command_.name;
    throw UsageError(name + ": " + message + " (see tricell " + name + " --help)");
}

io::Format input_format(const Arguments& arguments, const std::string& name) {
    try {
        return io::parse_format(name);
    } catch (const Error& e) {
        arguments.fail(std::string("--input-format: ") + e.what());
    }
}

std::string choices(const std::vector<std::string>& items) {
    std::string text;
    for (std::size_t k = 0; k < items.size(); ++k) {
        text += k == 0 ? "" : k + 1 == items.size() ? " or " : ", ";
        text += items[k];
    }
    return text;
}

std::string wrap(const std::string& text, std::size_t first, std::size_t indent) {
    std::string out;
    std::size_t column = first;
    std::size_t at = 0;
    while (at < text.size()) {
        std::size_t end = text.find(' ', at);
        if (end == std::string::npos) {
            end = text.size();
        }
        const std::size_t length = end - at;
        if (!out.empty() && column + 1 + length > text_width) {
            out += "\n" + std::string(indent, ' ');
            column = indent;
        } else if (!out.empty()) {
            out += ' ';
            ++column;
        }
        out.append(text, at, length);
        column += length;
        at = end + 1;
    }
    return out;
}

std::string exact(double value) {
    char text[max_real_chars];
    return std::string(text, write_real(text, value));
}

std::string brief(double value) {
    char text[32];
    std::snprintf(text, sizeof text, "%.10g", value);
    return text;
}

namespace {

std::string system_error(const std::string& what, const std::string& path) {
    return what + " " + path + " (" + std::strerror(errno) + ")";
}

} // namespace

Output::Output(const std::string& path) : path_(path) {
    if (path_.empty()) {
        stream_ = stdout;
        return;
    }
    // mkstemp in the directory of PATH, so that rename() is atomic.
    std::string pattern = path_ + ".tmp.XXXXXX";
    const int fd = ::mkstemp(pattern.data());
    if (fd < 0) {
        throw std::runtime_error(system_error("cannot create a temporary file for", path_));
    }
    temporary_ = pattern;
    const mode_t mask = ::umask(0);
    ::umask(mask);
    ::fchmod(fd, 0666 & ~mask); // mkstemp makes 0600; give the file the usual permissions
    stream_ = ::fdopen(fd, "w");
    if (stream_ == nullptr) {
        ::close(fd);
        std::remove(temporary_.c_str());
        throw std::runtime_error(system_error("cannot open a temporary file for", path_));
    }
}

Output::~Output() {
    if (!path_.empty() && !committed_) {
        if (stream_ != nullptr) {
            std::fclose(stream_);
        }
        std::remove(temporary_.c_str());
    }
}

void Output::write(const char* text, std::size_t size) {
    std::fwrite(text, 1, size, stream_);
}

void Output::commit() {
    if (path_.empty()) {
        if (std::fflush(stdout) != 0 || std::ferror(stdout) != 0) {
            throw std::runtime_error(std::string("cannot write to standard output (") +
                                     std::strerror(errno) + ")");
        }
        committed_ = true;
        return;
    }
    const bool written = std::fflush(stream_) == 0 && std::ferror(stream_) == 0;
    const int error = errno;
    const bool closed = std::fclose(stream_) == 0;
    stream_ = nullptr;
    if (!written || !closed) {
        errno = written ? errno : error;
        throw std::runtime_error(system_error("cannot write", path_));
    }
    if (std::rename(temporary_.c_str(), path_.c_str()) != 0) {
        throw std::runtime_error(system_error("cannot write", path_));
    }
    committed_ = true;
}

bool take_input(Arguments& arguments, io::ReadOptions& read_options, std::string& file) {
    if (arguments.option("--input-format")) {
        read_options.format = input_format(arguments, arguments.value());
        return true;
    }
    if (arguments.positional() && file.empty()) {
        file = arguments.current();
        return true;
    }
    return false;
}

bool take_max_pairs(Arguments& arguments, std::size_t& max_pairs) {
    if (!arguments.option("--max-pairs")) {
        return false;
    }
    const double n = arguments.real();
    if (!(n >= 0 && n <= 0x1p53) || n != std::floor(n)) {
        arguments.fail("--max-pairs must be a whole number in [0, 2^53], got '" +
                       arguments.value() + "'");
    }
    max_pairs = std::size_t(n);
    return true;
}

bool take_max_bytes(Arguments& arguments, std::size_t& max_bytes) {
    if (!arguments.option("--max-bytes")) {
        return false;
    }
    const std::string& text = arguments.value();
    std::size_t end = 0;
    double n = -1;
    try {
        n = std::stod(text, &end);
    } catch (const std::exception&) {
        end = 0;
    }
    double unit = 1;
    if (end > 0 && end + 1 == text.size()) {
        const std::string units = "KMGT";
        const std::size_t power = units.find(char(std::toupper(text[end])));
        if (power != std::string::npos) {
            unit = std::ldexp(1.0, 10 * int(power + 1));
            ++end;
        }
    }
    const double bytes = n * unit;
    if (end == 0 || end != text.size() || !(bytes >= 0 && bytes <= 0x1p63) ||
        bytes != std::floor(bytes)) {
        arguments.fail("--max-bytes must be a whole number of bytes in [0, 2^63], or a size with "
                       "K, M, G or T (powers of 1024) such as 16G, got '" +
                       text + "'");
    }
    max_bytes = std::size_t(bytes);
    return true;
}

bool take_format(Arguments& arguments, TableFormat& format) {
    if (!arguments.option("--format")) {
        return false;
    }
    const std::string& name = arguments.value();
    if (name == "tsv") {
        format = TableFormat::tsv;
    } else if (name == "csv") {
        format = TableFormat::csv;
    } else if (name == "json") {
        format = TableFormat::json;
    } else {
        arguments.fail("--format must be tsv, csv or json, got '" + name + "'");
    }
    return true;
}

bool take_threads(Arguments& arguments, int& threads) {
    if (!arguments.option("--threads")) {
        return false;
    }
    threads = int(arguments.whole(0, 1024));
    return true;
}

bool take_quiet(Arguments& arguments, bool& quiet) {
    if (!arguments.flag("--quiet")) {
        return false;
    }
    quiet = true;
    return true;
}

void require_file(const Arguments& arguments, const std::string& file) {
    if (file.empty()) {
        arguments.fail("missing FILE");
    }
}

} // namespace tricell::cli
