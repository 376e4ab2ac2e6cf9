#include "core/error.h"

#include <fmt/format.h>

namespace aamap {

// The message is one line whatever the input held: a problem that quotes binary input (a token
// of garbage, a newline from a library's message) has its control bytes shown as '?'.
static std::string oneLine(std::string text) {
    for (char& c : text) {
        if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f) c = '?';
    }
    return text;
}

static std::string formatLocation(const std::filesystem::path& file, int line, int column, const std::string& problem) {
    std::string where = file.string();
    if (line > 0) where += fmt::format(":{}", line);
    if (line > 0 && column > 0) where += fmt::format(":{}", column);
    return oneLine(fmt::format("{}: {}", where, problem));
}

InputError::InputError(std::filesystem::path file, int line, int column, const std::string& problem)
    : std::runtime_error(formatLocation(file, line, column, problem)),
      file_(std::move(file)),
      line_(line),
      column_(column),
      problem_(problem) {}

}  // namespace aamap
