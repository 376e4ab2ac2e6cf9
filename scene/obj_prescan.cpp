#include "scene/obj_prescan.h"

#include <array>
#include <cmath>

#include <fmt/format.h>

#include "core/error.h"
#include "scene/text_util.h"

namespace aamap::detail {
namespace {

using text::Token;

// An index whose target may be defined later in the file; checked once the totals are known.
struct ForwardRef {
    int line, column;
    long long index;
    int kind;
};

constexpr std::array<const char*, 3> kKindNames = {"vertex", "texture coordinate", "normal"};

// Binary data where text is expected (an image renamed .obj, a truncated download): control
// bytes other than whitespace never occur in OBJ/MTL text. Reports the first one's line:col.
void rejectBinary(const std::filesystem::path& file, std::string_view text, const char* what) {
    int line = 1, column = 1;
    for (const char ch : text) {
        const auto c = static_cast<unsigned char>(ch);
        if ((c < 0x20 && c != '\t' && c != '\n' && c != '\r' && c != '\f' && c != '\v') || c == 0x7f) {
            throw InputError(file, line, column, fmt::format("binary data (byte 0x{:02x}), not {} text", c, what));
        }
        if (c == '\n') {
            ++line;
            column = 1;
        } else {
            ++column;
        }
    }
}

// Values are stored as 32-bit floats: 1e39 parses as a finite double but becomes inf.
bool finiteAsFloat(double value) {
    return std::isfinite(static_cast<float>(value));
}

class ObjScanner {
public:
    explicit ObjScanner(const std::filesystem::path& file) : file_(file) {}

    void scanLine(std::string_view line, int lineNumber) {
        line_ = lineNumber;
        const auto tokens = text::tokenize(line);
        if (tokens.empty()) return;
        const std::string_view key = tokens[0].text;
        if (key == "v") {
            numbers(tokens, 3, 7, "vertex position");
            ++result_.positions;
        } else if (key == "vt") {
            numbers(tokens, 1, 3, "texture coordinate");
            ++result_.uvs;
        } else if (key == "vn") {
            numbers(tokens, 3, 3, "vertex normal");
            ++result_.normals;
        } else if (key == "f") {
            face(tokens);
        } else if (key == "mtllib") {
            for (std::size_t i = 1; i < tokens.size(); ++i) result_.mtllibs.emplace_back(tokens[i].text);
        }
        // Everything else (g, o, s, usemtl, l, p, unknown statements) is left to tinyobjloader.
    }

    ObjPrescan finish() {
        const std::array<std::size_t, 3> totals = {result_.positions, result_.uvs, result_.normals};
        for (const ForwardRef& ref : forward_) {
            if (static_cast<std::size_t>(ref.index) > totals[ref.kind]) {
                throw InputError(file_, ref.line, ref.column,
                                 fmt::format("{} index {} is out of range (the file declares {} of them)",
                                             kKindNames[ref.kind], ref.index, totals[ref.kind]));
            }
        }
        return std::move(result_);
    }

private:
    [[noreturn]] void fail(int column, const std::string& problem) const {
        throw InputError(file_, line_, column, problem);
    }

    void numbers(const std::vector<Token>& tokens, std::size_t minCount, std::size_t maxCount, const char* what) {
        const std::size_t count = tokens.size() - 1;
        if (count < minCount) {
            fail(tokens[0].column, fmt::format("{} needs {} numbers, found {}", what, minCount, count));
        }
        if (count > maxCount) {
            fail(tokens[maxCount + 1].column, fmt::format("{} has more than {} numbers", what, maxCount));
        }
        for (std::size_t i = 1; i < tokens.size(); ++i) {
            const auto value = text::parseNumber(tokens[i].text);
            if (!value) fail(tokens[i].column, fmt::format("'{}' is not a number ({})", tokens[i].text, what));
            if (!finiteAsFloat(*value)) fail(tokens[i].column, fmt::format("{} '{}' is not finite", what, tokens[i].text));
        }
    }

    void face(const std::vector<Token>& tokens) {
        if (tokens.size() < 4) {
            fail(tokens[0].column, fmt::format("face needs at least 3 vertices, found {}", tokens.size() - 1));
        }
        if (tokens.size() > 256) {  // tinyobjloader stores vertex counts in an unsigned char
            fail(tokens[0].column, fmt::format("face has {} vertices; at most 255 are supported", tokens.size() - 1));
        }
        for (std::size_t i = 1; i < tokens.size(); ++i) faceVertex(tokens[i]);
        ++result_.faces;
    }

    // One of v, v/t, v//n, v/t/n.
    void faceVertex(const Token& token) {
        std::array<std::string_view, 3> parts{};
        std::size_t partCount = 0, start = 0;
        const std::string_view s = token.text;
        for (std::size_t i = 0; i <= s.size(); ++i) {
            if (i == s.size() || s[i] == '/') {
                if (partCount == 3) fail(token.column, fmt::format("face vertex '{}' has more than 3 indices", s));
                parts[partCount++] = s.substr(start, i - start);
                start = i + 1;
            }
        }
        const std::array<std::size_t, 3> counts = {result_.positions, result_.uvs, result_.normals};
        for (std::size_t k = 0; k < partCount; ++k) {
            if (parts[k].empty()) {
                if (k == 1 && partCount == 3) continue;  // v//n
                fail(token.column, fmt::format("face vertex '{}' has an empty {} index", s, kKindNames[k]));
            }
            const auto index = text::parseInteger(parts[k]);
            if (!index) fail(token.column, fmt::format("face vertex '{}': '{}' is not an integer", s, parts[k]));
            if (*index == 0) fail(token.column, fmt::format("face vertex '{}': index 0 is not allowed (OBJ counts from 1)", s));
            if (*index < 0) {
                if (static_cast<unsigned long long>(-*index) > counts[k]) {
                    fail(token.column, fmt::format("relative {} index {} reaches before the first {} ({} defined so far)",
                                                   kKindNames[k], *index, kKindNames[k], counts[k]));
                }
            } else if (static_cast<std::size_t>(*index) > counts[k]) {
                forward_.push_back({line_, token.column, *index, static_cast<int>(k)});
            }
        }
    }

    const std::filesystem::path& file_;
    int line_ = 0;
    ObjPrescan result_;
    std::vector<ForwardRef> forward_;
};

}  // namespace

ObjPrescan prescanObj(const std::filesystem::path& file, std::string_view text) {
    rejectBinary(file, text, "OBJ");
    ObjScanner scanner(file);
    text::forEachLine(text, [&](std::string_view line, int number) { scanner.scanLine(line, number); });
    return scanner.finish();
}

void prescanMtl(const std::filesystem::path& file, std::string_view text) {
    rejectBinary(file, text, "MTL");
    text::forEachLine(text, [&](std::string_view line, int lineNumber) {
        const auto tokens = text::tokenize(line);
        if (tokens.empty()) return;
        const std::string_view key = tokens[0].text;
        const auto fail = [&](int column, const std::string& problem) {
            throw InputError(file, lineNumber, column, problem);
        };
        const auto checkNumbers = [&](std::size_t allowedA, std::size_t allowedB) {
            std::size_t first = 1;
            if (key == "d" && tokens.size() > 1 && tokens[1].text == "-halo") first = 2;  // d -halo 0.5
            const std::size_t count = tokens.size() - first;
            if (count != allowedA && count != allowedB) {
                fail(tokens[0].column, allowedA == allowedB
                                           ? fmt::format("{} needs {} number, found {}", key, allowedA, count)
                                           : fmt::format("{} needs {} or {} numbers, found {}", key, allowedA, allowedB, count));
            }
            for (std::size_t i = first; i < tokens.size(); ++i) {
                const auto value = text::parseNumber(tokens[i].text);
                if (!value) fail(tokens[i].column, fmt::format("'{}' is not a number ({})", tokens[i].text, key));
                if (!finiteAsFloat(*value)) fail(tokens[i].column, fmt::format("{} value '{}' is not finite", key, tokens[i].text));
            }
        };
        if (key == "Ka" || key == "Kd" || key == "Ks" || key == "Ke" || key == "Kt" || key == "Tf") {
            // "spectral file" and "xyz x y z" forms are left to tinyobjloader.
            if (tokens.size() > 1 && (tokens[1].text == "spectral" || tokens[1].text == "xyz")) return;
            checkNumbers(1, 3);
        } else if (key == "Ns" || key == "Ni" || key == "d" || key == "Tr" || key == "Pr" || key == "Pm" ||
                   key == "Ps" || key == "Pc" || key == "Pcr" || key == "aniso" || key == "anisor") {
            checkNumbers(1, 1);
        } else if (key == "illum") {
            if (tokens.size() != 2) fail(tokens[0].column, "illum needs one integer");
            if (!text::parseInteger(tokens[1].text)) {
                fail(tokens[1].column, fmt::format("illum model '{}' is not an integer", tokens[1].text));
            }
        } else if (key == "newmtl" && tokens.size() < 2) {
            fail(tokens[0].column, "newmtl needs a material name");
        }
    });
}

}  // namespace aamap::detail
