// FrameReader: a multi-frame extended XYZ file one frame at a time.
//
// The reader keeps the file open and, for each frame, reads exactly the lines the frame's first
// line announces (the atom count, the comment, that many atom lines) into one string, which the
// one XYZ parser (parse_structure, xyz.cpp) turns into a Structure; nothing of the file beyond
// the current frame is held. The parser counts lines from 1 within the frame's text, so its
// errors are rethrown with the number of lines before the frame added and "(frame K)" appended.
// A first line that is not a valid count (or a count above ReadOptions::max_atoms) is handed to
// the parser alone, which refuses it with its usual message before any atom line is read.
// Other formats hold one structure and are read whole, as read_structure() reads them.
#include "tricell/io/trajectory.hpp"

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>

#include "text.hpp"
#include "tricell/error.hpp"

namespace tricell::io {

struct FrameReader::State {
    std::string path;
    ReadOptions options; // with the format resolved
    std::ifstream file;
    std::size_t lines_before = 0; // lines of the file consumed by earlier frames
    std::size_t frames = 0;
    bool done = false;   // the end was reached
    bool failed = false; // an error was thrown; next() throws it again
    std::size_t failure_line = 0;
    std::string failure;
};

namespace {

bool blank(const std::string& line) {
    return line.find_first_not_of(" \t\r\v\f") == std::string::npos;
}

} // namespace

FrameReader::FrameReader(const std::string& path, const ReadOptions& options)
    : state_(std::make_unique<State>()) {
    options.validate();
    State& s = *state_;
    s.path = path;
    s.options = options;
    if (!s.options.format) {
        s.options.format = format_from_name(path); // before opening: a clear message first
    }
    if (*s.options.format != Format::xyz) {
        return; // read whole by the first next()
    }
    std::error_code error;
    if (std::filesystem::is_directory(path, error)) {
        tricell::detail::fail_parse(path, 0, "cannot read: is a directory, expected a file");
    }
    s.file.open(path, std::ios::binary);
    if (!s.file) {
        tricell::detail::fail_parse(path, 0, "cannot open file (", std::strerror(errno), ")");
    }
}

FrameReader::~FrameReader() = default;
FrameReader::FrameReader(FrameReader&&) noexcept = default;
FrameReader& FrameReader::operator=(FrameReader&&) noexcept = default;

std::size_t FrameReader::frames_read() const {
    return state_->frames;
}

bool FrameReader::next(Structure& frame) {
    State& s = *state_;
    if (s.failed) {
        throw ParseError(s.path, s.failure_line, s.failure);
    }
    if (s.done) {
        return false;
    }
    try {
        if (*s.options.format != Format::xyz) {
            frame = read_structure(s.path, s.options);
            s.done = true;
            ++s.frames;
            return true;
        }
        // The frame's first line; blank lines count as the end when nothing follows them.
        std::string text;
        std::string line;
        std::size_t lines = 0;
        if (!std::getline(s.file, line)) {
            s.done = true;
            if (s.frames == 0) {
                frame = parse_structure(std::string(), s.path, s.options); // "file is empty"
            }
            return false;
        }
        ++lines;
        if (blank(line)) {
            std::string rest;
            bool more = false;
            while (std::getline(s.file, rest)) {
                ++lines;
                if (!blank(rest)) {
                    more = true;
                    break;
                }
            }
            if (!more) {
                s.done = true;
                if (s.frames == 0) {
                    frame = parse_structure(std::string(), s.path, s.options); // "file is empty"
                }
                return false;
            }
            // A blank line where a frame should start, with more text after it: the parser
            // refuses the blank count line.
            text = line + '\n' + rest + '\n';
        } else {
            text = line + '\n';
            const std::vector<std::string_view> words = detail::split_words(line);
            long long count = 0;
            const bool valid = !words.empty() && detail::parse_integer(words[0], count) &&
                               count >= 0 &&
                               (s.options.max_atoms == 0 ||
                                static_cast<unsigned long long>(count) <= s.options.max_atoms);
            if (valid) {
                // The comment and the atom lines; a short file stops early and the parser says so.
                for (long long k = 0; k < count + 1 && std::getline(s.file, line); ++k) {
                    text += line;
                    text += '\n';
                    ++lines;
                }
            }
        }
        Structure parsed = parse_structure(text, s.path, s.options);
        s.lines_before += lines;
        ++s.frames;
        frame = std::move(parsed);
        return true;
    } catch (const ParseError& e) {
        s.failed = true;
        const std::size_t line = e.line() == 0 ? 0 : e.line() + s.lines_before;
        s.failure_line = line;
        s.failure = e.message() + " (frame " + std::to_string(s.frames) + ")";
        throw ParseError(e.file(), line, s.failure);
    }
}

} // namespace tricell::io
