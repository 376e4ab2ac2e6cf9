#include "core/error.h"

#include <fmt/format.h>

namespace aamap {

static std::string formatLocation(const std::filesystem::path& file, int line, int column, const std::string& problem) {
    std::string where = file.string();
    if (line > 0) where += fmt::format(":{}", line);
    if (line > 0 && column > 0) where += fmt::format(":{}", column);
    return fmt::format("{}: {}", where, problem);
}

InputError::InputError(std::filesystem::path file, int line, int column, const std::string& problem)
    : std::runtime_error(formatLocation(file, line, column, problem)),
      file_(std::move(file)),
      line_(line),
      column_(column),
      problem_(problem) {}

}  // namespace aamap
