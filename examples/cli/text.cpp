#include "text.hpp"

#include <cstring>

#include "cli.hpp"

namespace tricell::cli {

TextSink::TextSink(Output& out, std::size_t capacity)
    : out_(out), buffer_(capacity < 256 ? 256 : capacity), end_(buffer_.data()),
      limit_(buffer_.data() + buffer_.size()) {}

void TextSink::put(std::string_view text) {
    if (text.size() > std::size_t(limit_ - end_)) {
        flush();
        if (text.size() > buffer_.size()) {
            out_.write(text.data(), text.size());
            return;
        }
    }
    std::memcpy(end_, text.data(), text.size());
    end_ += text.size();
}

void TextSink::flush() {
    out_.write(buffer_.data(), std::size_t(end_ - buffer_.data()));
    end_ = buffer_.data();
}

} // namespace tricell::cli
