#include "tricell/error.hpp"

namespace tricell {

namespace {
std::string located(const std::string& file, std::size_t line, const std::string& message) {
    if (line == 0) {
        return file + ": " + message;
    }
    return file + ":" + std::to_string(line) + ": " + message;
}
} // namespace

ParseError::ParseError(std::string file, std::size_t line, const std::string& message)
    : Error(located(file, line, message)), file_(std::move(file)), line_(line), message_(message) {}

PairLimitError::PairLimitError(std::string subject, double pairs, std::size_t limit)
    : InvalidArgument(subject + ", more than max_pairs = " + std::to_string(limit) +
                      "; raise NeighborOptions::max_pairs to allow it"),
      subject_(std::move(subject)), pairs_(pairs), limit_(limit) {}

std::string PairLimitError::message_for(const std::string& limit_text,
                                        const std::string& raise) const {
    return subject_ + ", more than " + limit_text + "; raise " + raise + " to allow it";
}

} // namespace tricell
