// Progress on stderr for long runs (a large table written to a file, an RDF over many frames):
// "tricell: LABEL 1234/5678 (21%)" rewritten in place with '\r', at most about five times a
// second, and cleared at the end. Only when stderr is a terminal and --quiet was not given, so
// that logs, pipes and tests never see it.
#pragma once

#include <chrono>
#include <cstddef>
#include <string>

namespace tricell::cli {

class Progress {
  public:
    /// `total` 0 means unknown (counts without a percentage). Shown only when `enabled` and
    /// stderr is a terminal.
    Progress(std::string label, std::size_t total, bool enabled);
    ~Progress();
    Progress(const Progress&) = delete;
    Progress& operator=(const Progress&) = delete;

    /// `done` items so far (call it per frame or per block of rows: it looks at the clock).
    void step(std::size_t done) {
        if (shown_) {
            draw(done);
        }
    }
    /// Draws "tricell: LABEL ..." now, for one long call that cannot report steps.
    void show();
    /// Clears the line.
    void finish();

  private:
    void draw(std::size_t done);

    std::string label_;
    std::size_t total_;
    bool shown_;
    bool drawn_ = false;
    std::chrono::steady_clock::time_point last_;
};

/// Whether standard output is a terminal (progress would then mix with the output).
bool stdout_is_terminal();

} // namespace tricell::cli
