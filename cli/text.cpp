#include "text.hpp"

#include <cstdio>
#include <cstring>

#include "cli.hpp"

namespace tricell::cli {

TextSink::TextSink(Output& out, std::size_t capacity)
    : out_(&out), buffer_(capacity < 256 ? 256 : capacity), end_(buffer_.data()),
      limit_(buffer_.data() + buffer_.size()) {}

TextSink::TextSink(std::string& text, std::size_t capacity)
    : text_(&text), buffer_(capacity < 256 ? 256 : capacity), end_(buffer_.data()),
      limit_(buffer_.data() + buffer_.size()) {}

void TextSink::put(std::string_view text) {
    if (text.size() > std::size_t(limit_ - end_)) {
        flush();
        if (text.size() > buffer_.size()) {
            if (out_ != nullptr) {
                out_->write(text.data(), text.size());
            } else {
                text_->append(text);
            }
            return;
        }
    }
    std::memcpy(end_, text.data(), text.size());
    end_ += text.size();
}

std::string json_string(const std::string& text) {
    std::string out = "\"";
    for (char c : text) {
        if (c == '"' || c == '\\') {
            out += '\\';
            out += c;
        } else if (static_cast<unsigned char>(c) < 0x20) {
            char escaped[8];
            std::snprintf(escaped, sizeof escaped, "\\u%04x", c);
            out += escaped;
        } else {
            out += c;
        }
    }
    return out + "\"";
}

void TextSink::flush() {
    const std::size_t size = std::size_t(end_ - buffer_.data());
    if (out_ != nullptr) {
        out_->write(buffer_.data(), size);
    } else {
        text_->append(buffer_.data(), size);
    }
    end_ = buffer_.data();
}

} // namespace tricell::cli
