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

} // namespace tricell
