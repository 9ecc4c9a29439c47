#include "tricell/error.hpp"

#include <iomanip>

namespace tricell {

namespace {
std::string located(const std::string& file, std::size_t line, const std::string& message) {
    if (line == 0) {
        return file + ": " + message;
    }
    return file + ":" + std::to_string(line) + ": " + message;
}

// "17179869184 (16 GiB)": a byte count as given and in GiB (three significant digits).
std::string gib_text(std::size_t bytes) {
    return detail::cat(bytes, " (", std::setprecision(3), double(bytes) / double(1ull << 30),
                       " GiB)");
}
} // namespace

ParseError::ParseError(std::string file, std::size_t line, const std::string& message)
    : Error(located(file, line, message)), file_(std::move(file)), line_(line), message_(message) {}

PairLimitError::PairLimitError(std::string subject, double pairs, std::size_t limit)
    : InvalidArgument(subject + ", more than max_pairs = " + std::to_string(limit) +
                      "; raise NeighborOptions::max_pairs to allow it"),
      subject_(std::move(subject)), which_(Limit::pairs), pairs_(pairs), bytes_(0), limit_(limit) {}

PairLimitError::PairLimitError(std::string subject, double pairs, double bytes,
                               std::size_t max_bytes)
    : InvalidArgument(subject + ", more than max_bytes = " + gib_text(max_bytes) +
                      "; raise NeighborOptions::max_bytes to allow it (0 = no limit)"),
      subject_(std::move(subject)), which_(Limit::bytes), pairs_(pairs), bytes_(bytes),
      limit_(max_bytes) {}

std::string PairLimitError::limit_text() const {
    return which_ == Limit::bytes ? gib_text(limit_) : std::to_string(limit_);
}

std::string PairLimitError::message_for(const std::string& limit_text,
                                        const std::string& raise) const {
    return subject_ + ", more than " + limit_text + "; raise " + raise + " to allow it" +
           (which_ == Limit::bytes ? " (0 = no limit)" : "");
}

PairLimitError PairLimitError::with_subject(std::string subject) const {
    return which_ == Limit::bytes ? PairLimitError(std::move(subject), pairs_, bytes_, limit_)
                                  : PairLimitError(std::move(subject), pairs_, limit_);
}

} // namespace tricell
