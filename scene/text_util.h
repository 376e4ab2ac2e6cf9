#pragma once
// Small text helpers shared by the hand-written parsers in scene/ (OBJ/MTL pre-scan, view files):
// whitespace tokenising with 1-based columns, strict number parsing, line splitting.
#include <charconv>
#include <cmath>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace aamap::text {

struct Token {
    std::string_view text;
    int column = 1;  // 1-based, counting bytes (a tab is one column)
};

inline bool isBlank(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f'; }

// Splits on blanks. A '#' that starts a token ends the line (comments); `comment` gets the rest.
inline std::vector<Token> tokenize(std::string_view line, std::string_view* comment = nullptr) {
    std::vector<Token> tokens;
    std::size_t i = 0;
    while (i < line.size()) {
        while (i < line.size() && isBlank(line[i])) ++i;
        if (i >= line.size()) break;
        if (line[i] == '#') {
            if (comment) *comment = line.substr(i + 1);
            break;
        }
        const std::size_t start = i;
        while (i < line.size() && !isBlank(line[i])) ++i;
        tokens.push_back({line.substr(start, i - start), static_cast<int>(start) + 1});
    }
    return tokens;
}

inline std::string_view trim(std::string_view s) {
    while (!s.empty() && isBlank(s.front())) s.remove_prefix(1);
    while (!s.empty() && isBlank(s.back())) s.remove_suffix(1);
    return s;
}

// The whole token must be a number; a leading '+' is allowed (from_chars rejects it).
// "nan"/"inf" parse, so callers check std::isfinite and say "not finite" rather than "not a number".
inline std::optional<double> parseNumber(std::string_view s) {
    if (!s.empty() && s.front() == '+') {
        s.remove_prefix(1);
        if (!s.empty() && (s.front() == '+' || s.front() == '-')) return std::nullopt;
    }
    if (s.empty()) return std::nullopt;
    double value = 0;
    const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), value);
    if (ec == std::errc::result_out_of_range) return s.front() == '-' ? -HUGE_VAL : HUGE_VAL;
    if (ec != std::errc() || end != s.data() + s.size()) return std::nullopt;
    return value;
}

inline std::optional<long long> parseInteger(std::string_view s) {
    if (!s.empty() && s.front() == '+') {
        s.remove_prefix(1);
        if (!s.empty() && s.front() == '-') return std::nullopt;
    }
    long long value = 0;
    const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), value);
    if (s.empty() || ec != std::errc() || end != s.data() + s.size()) return std::nullopt;
    return value;
}

inline std::string toLower(std::string_view s) {
    std::string out(s);
    for (char& c : out) c = static_cast<char>(c >= 'A' && c <= 'Z' ? c - 'A' + 'a' : c);
    return out;
}

// Calls fn(lineText, lineNumber) for each line; handles LF, CRLF and lone CR endings.
template <class Fn>
void forEachLine(std::string_view text, Fn&& fn) {
    int lineNumber = 1;
    std::size_t start = 0;
    while (start < text.size()) {
        std::size_t end = start;
        while (end < text.size() && text[end] != '\n' && text[end] != '\r') ++end;
        fn(text.substr(start, end - start), lineNumber++);
        if (end < text.size() && text[end] == '\r' && end + 1 < text.size() && text[end + 1] == '\n') ++end;
        start = end + 1;
    }
}

}  // namespace aamap::text
