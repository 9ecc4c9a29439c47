#include "progress.hpp"

#include <cstdio>

#include <unistd.h>

namespace tricell::cli {

Progress::Progress(std::string label, std::size_t total, bool enabled)
    : label_(std::move(label)), total_(total), shown_(enabled && ::isatty(STDERR_FILENO) == 1),
      last_(std::chrono::steady_clock::now()) {}

Progress::~Progress() {
    finish();
}

void Progress::draw(std::size_t done) {
    const auto now = std::chrono::steady_clock::now();
    if (now - last_ < std::chrono::milliseconds(200)) {
        return;
    }
    last_ = now;
    if (total_ > 0) {
        std::fprintf(stderr, "\rtricell: %s %zu/%zu (%.0f%%)  ", label_.c_str(), done, total_,
                     100.0 * double(done) / double(total_));
    } else {
        std::fprintf(stderr, "\rtricell: %s %zu  ", label_.c_str(), done);
    }
    std::fflush(stderr);
    drawn_ = true;
}

void Progress::show() {
    if (shown_) {
        std::fprintf(stderr, "\rtricell: %s ...  ", label_.c_str());
        std::fflush(stderr);
        drawn_ = true;
    }
}

void Progress::finish() {
    if (drawn_) {
        std::fputs("\r\033[K", stderr);
        std::fflush(stderr);
        drawn_ = false;
    }
    shown_ = false;
}

bool stdout_is_terminal() {
    return ::isatty(STDOUT_FILENO) == 1;
}

} // namespace tricell::cli
