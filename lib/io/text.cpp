#include "text.hpp"

#include <cctype>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace tricell::io::detail {

std::string read_file(const std::string& path) {
    std::error_code error;
    if (std::filesystem::is_directory(path, error)) {
        tricell::detail::fail_parse(path, 0, "cannot read: is a directory, expected a file");
    }
    std::ifstream file(path, std::ios::binary);
    if (!file) {
        tricell::detail::fail_parse(path, 0, "cannot open file (", std::strerror(errno), ")");
    }
    std::ostringstream content;
    content << file.rdbuf();
    if (file.bad()) {
        tricell::detail::fail_parse(path, 0, "cannot read file (", std::strerror(errno), ")");
    }
    return content.str();
}

Lines::Lines(const std::string& text, std::string name) : name_(std::move(name)) {
    std::size_t start = 0;
    while (start < text.size()) {
        std::size_t end = text.find('\n', start);
        if (end == std::string::npos) {
            end = text.size();
        }
        std::string_view line(text.data() + start, end - start);
        if (!line.empty() && line.back() == '\r') {
            line.remove_suffix(1);
        }
        lines_.push_back(line);
        start = end + 1;
    }
}

std::string_view Lines::next(const char* what) {
    if (at_end()) {
        fail(number(), "unexpected end of file, expected ", what);
    }
    return lines_[next_++];
}

std::vector<std::string_view> split_words(std::string_view line) {
    std::vector<std::string_view> words;
    std::size_t k = 0;
    while (k < line.size()) {
        while (k < line.size() && std::isspace(static_cast<unsigned char>(line[k]))) {
            ++k;
        }
        const std::size_t start = k;
        while (k < line.size() && !std::isspace(static_cast<unsigned char>(line[k]))) {
            ++k;
        }
        if (k > start) {
            words.push_back(line.substr(start, k - start));
        }
    }
    return words;
}

std::vector<std::string_view> data_words(std::string_view line) {
    std::vector<std::string_view> words = split_words(line);
    for (std::size_t k = 0; k < words.size(); ++k) {
        if (words[k].front() == '#' || words[k].front() == '!') {
            words.resize(k);
            break;
        }
    }
    return words;
}

bool parse_real(std::string_view token, double& value) {
    if (!token.empty() && token.front() == '+') {
        token.remove_prefix(1);
    }
    if (token.empty() || token.front() == '+') {
        return false;
    }
    const char* end = token.data() + token.size();
    const auto result = std::from_chars(token.data(), end, value);
    return result.ec == std::errc() && result.ptr == end && std::isfinite(value);
}

bool parse_integer(std::string_view token, long long& value) {
    if (!token.empty() && token.front() == '+') {
        token.remove_prefix(1);
    }
    if (token.empty() || token.front() == '+') {
        return false;
    }
    const char* end = token.data() + token.size();
    const auto result = std::from_chars(token.data(), end, value);
    return result.ec == std::errc() && result.ptr == end;
}

bool parse_bool(std::string_view token, bool& value) {
    const std::string word = lower(token);
    if (word == "t" || word == "true" || word == "1") {
        value = true;
        return true;
    }
    if (word == "f" || word == "false" || word == "0") {
        value = false;
        return true;
    }
    return false;
}

std::string lower(std::string_view text) {
    std::string out(text);
    for (char& c : out) {
        c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    }
    return out;
}

std::string quote(std::string_view token) {
    constexpr std::size_t max_length = 40;
    std::string out = "'";
    if (token.size() > max_length) {
        out.append(token.substr(0, max_length - 3));
        out += "...";
    } else {
        out.append(token);
    }
    for (char& c : out) {
        if (static_cast<unsigned char>(c) < 0x20) {
            c = ' '; // keep messages on one line
        }
    }
    return out + "'";
}

std::string one_line(std::string_view message) {
    std::string out(message);
    for (char& c : out) {
        if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f) {
            c = ' ';
        }
    }
    return out;
}

} // namespace tricell::io::detail
