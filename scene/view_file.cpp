#include "scene/view_file.h"

#include <cmath>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include <fmt/format.h>
#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>

#include "core/error.h"
#include "scene/text_util.h"

namespace aamap {
namespace fs = std::filesystem;

namespace {

constexpr int kMaxViewFileDepth = 8;  // -vf chains

std::vector<View> loadViewFileImpl(const fs::path& file, int depth);

bool isProgramName(std::string_view s) {
    return s == "rview" || s == "rpict" || s == "rvu" || s == "rtrace" || s == "rholo";
}

class ViewLineParser {
public:
    ViewLineParser(std::string_view text, const fs::path& file, int line, int depth)
        : file_(file), line_(line), depth_(depth) {
        tokens_ = text::tokenize(text, &comment_);
    }

    View parse() {
        View v;  // Radiance's defaults, which differ from View's own
        v.position = {0, 0, 0};
        v.direction = {0, 1, 0};
        v.up = {0, 0, 1};
        v.horizontalFovDeg = 45;
        v.verticalFovDeg = 45;

        std::size_t i = 0;
        bool programLine = false;
        if (!tokens_.empty()) {
            text::Token& first = tokens_[0];
            if (first.text.starts_with("VIEW=")) {
                first.text.remove_prefix(5);
                first.column += 5;
                if (first.text.empty()) i = 1;
            } else if (isProgramName(first.text)) {
                programLine = true;
                i = 1;
            }
        }
        std::string explicitName;
        while (i < tokens_.size()) {
            const text::Token& tok = tokens_[i];
            const std::string_view opt = tok.text;
            if (!opt.starts_with("-") || text::parseNumber(opt)) {
                if (programLine) {  // an octree or other argument of rpict/rview
                    ++i;
                    continue;
                }
                fail(tok.column, fmt::format("expected a view option such as -vp, found '{}'", opt));
            }
            if (!opt.starts_with("-v")) {
                if (!programLine) fail(tok.column, fmt::format("'{}' is not a view option", opt));
                ++i;  // skip another program option and its arguments
                while (i < tokens_.size() && (!tokens_[i].text.starts_with("-") || text::parseNumber(tokens_[i].text))) ++i;
                continue;
            }
            ++i;
            if (opt.starts_with("-vt")) {
                if (opt.size() == 3) fail(tok.column, "-vt needs a view type letter (only -vtv is supported)");
                if (opt != "-vtv") fail(tok.column, fmt::format("view type {} is not supported (only -vtv)", opt));
            } else if (opt == "-vp") {
                v.position = vec3(tok, i);
            } else if (opt == "-vd") {
                v.direction = vec3(tok, i);
                dirColumn_ = tok.column;
            } else if (opt == "-vu") {
                v.up = vec3(tok, i);
                upColumn_ = tok.column;
            } else if (opt == "-vh") {
                v.horizontalFovDeg = number(tok, i);
                hColumn_ = tok.column;
            } else if (opt == "-vv") {
                v.verticalFovDeg = number(tok, i);
                vColumn_ = tok.column;
            } else if (opt == "-vs") {
                v.shiftX = number(tok, i);
            } else if (opt == "-vl") {
                v.shiftY = number(tok, i);
            } else if (opt == "-vo" || opt == "-va") {
                number(tok, i);  // clipping distances: no field in View, and rarely used
            } else if (opt == "-vn") {
                if (i >= tokens_.size()) fail(tok.column, "-vn needs a name");
                explicitName = std::string(tokens_[i++].text);
            } else if (opt == "-vf") {
                if (i >= tokens_.size()) fail(tok.column, "-vf needs a view file name");
                v = viewFromFile(tokens_[i++]);
            } else {
                fail(tok.column, fmt::format("unknown view option '{}'", opt));
            }
        }
        validate(v);
        v.name = !explicitName.empty() ? explicitName : std::string(text::trim(comment_));
        return v;
    }

private:
    [[noreturn]] void fail(int column, const std::string& problem) const {
        throw InputError(file_, line_, line_ > 0 ? column : 0, problem);
    }

    float number(const text::Token& option, std::size_t& i) {
        if (i >= tokens_.size()) fail(option.column, fmt::format("{} needs a number", option.text));
        const text::Token& tok = tokens_[i++];
        const auto value = text::parseNumber(tok.text);
        if (!value) fail(tok.column, fmt::format("{}: '{}' is not a number", option.text, tok.text));
        if (!std::isfinite(*value) || std::abs(*value) > 3.0e38) {
            fail(tok.column, fmt::format("{}: '{}' is not a finite number", option.text, tok.text));
        }
        return static_cast<float>(*value);
    }

    glm::vec3 vec3(const text::Token& option, std::size_t& i) {
        if (i + 3 > tokens_.size()) {
            fail(option.column, fmt::format("{} needs 3 numbers, found {}", option.text, tokens_.size() - i));
        }
        const float x = number(option, i), y = number(option, i), z = number(option, i);
        return {x, y, z};
    }

    View viewFromFile(const text::Token& name) {
        if (depth_ >= kMaxViewFileDepth) fail(name.column, "-vf files nest too deeply (a cycle?)");
        const fs::path path = fs::path(name.text).is_absolute() ? fs::path(name.text) : file_.parent_path() / name.text;
        try {
            return loadViewFileImpl(path, depth_ + 1).back();
        } catch (const InputError& e) {
            fail(name.column, fmt::format("in -vf file: {}", e.what()));
        }
    }

    void validate(View& v) const {
        const int anyColumn = tokens_.empty() ? 1 : tokens_[0].column;
        const float dirLength = glm::length(v.direction);
        if (!(dirLength > 0.0f)) fail(dirColumn_ ? dirColumn_ : anyColumn, "the view direction (-vd) is zero");
        const float upLength = glm::length(v.up);
        if (!(upLength > 0.0f)) fail(upColumn_ ? upColumn_ : anyColumn, "the view up vector (-vu) is zero");
        v.direction /= dirLength;
        v.up /= upLength;
        if (glm::length(glm::cross(v.direction, v.up)) < 1e-6f) {
            fail(upColumn_ ? upColumn_ : (dirColumn_ ? dirColumn_ : anyColumn),
                 "the view up vector (-vu) is parallel to the view direction (-vd); set -vu");
        }
        if (!(v.horizontalFovDeg > 0.0f && v.horizontalFovDeg < 180.0f)) {
            fail(hColumn_ ? hColumn_ : anyColumn,
                 fmt::format("-vh {} is outside (0, 180) degrees, as -vtv requires", v.horizontalFovDeg));
        }
        if (!(v.verticalFovDeg > 0.0f && v.verticalFovDeg < 180.0f)) {
            fail(vColumn_ ? vColumn_ : anyColumn,
                 fmt::format("-vv {} is outside (0, 180) degrees, as -vtv requires", v.verticalFovDeg));
        }
    }

    const fs::path& file_;
    int line_;
    int depth_;
    std::vector<text::Token> tokens_;
    std::string_view comment_;
    int dirColumn_ = 0, upColumn_ = 0, hColumn_ = 0, vColumn_ = 0;
};

std::vector<View> parseViewTextImpl(std::string_view text, const fs::path& file, int depth) {
    std::vector<View> views;
    text::forEachLine(text, [&](std::string_view line, int number) {
        const std::string_view trimmed = text::trim(line);
        if (trimmed.empty() || trimmed.front() == '#') return;
        // Other Radiance picture-header lines (FORMAT=..., EXPOSURE=...) carry no view.
        const auto firstBlank = trimmed.find_first_of(" \t");
        const std::string_view first = trimmed.substr(0, firstBlank);
        if (!first.starts_with("VIEW=") && first.find('=') != std::string_view::npos) return;
        View view = ViewLineParser(line, file, number, depth).parse();
        if (view.name.empty()) view.name = fmt::format("{}:{}", file.stem().string(), views.size());
        views.push_back(std::move(view));
    });
    return views;
}

std::vector<View> loadViewFileImpl(const fs::path& file, int depth) {
    std::error_code ec;
    if (!fs::is_regular_file(file, ec)) throw InputError(file, "view file not found");
    std::ifstream in(file, std::ios::binary);
    std::ostringstream buffer;
    buffer << in.rdbuf();
    if (!in) throw InputError(file, "cannot read view file");
    auto views = parseViewTextImpl(buffer.str(), file, depth);
    if (views.empty()) throw InputError(file, "no view in file");
    return views;
}

}  // namespace

View parseViewOptions(std::string_view text, const fs::path& file, int line) {
    return ViewLineParser(text, file, line, 0).parse();
}

std::vector<View> parseViewText(std::string_view text, const fs::path& file) {
    return parseViewTextImpl(text, file, 0);
}

std::vector<View> loadViewFile(const fs::path& file) { return loadViewFileImpl(file, 0); }

std::pair<int, int> fitResolution(const View& view, int maxWidth, int maxHeight) {
    if (maxWidth < 1 || maxHeight < 1) throw std::invalid_argument("fitResolution: resolution must be positive");
    // Radiance's normaspect() with pixel aspect 1: va = height / width of the view.
    const double va = std::tan(glm::radians(view.verticalFovDeg) * 0.5) / std::tan(glm::radians(view.horizontalFovDeg) * 0.5);
    int x = maxWidth, y = maxHeight;
    if (va * x > y) {
        x = static_cast<int>(y / va + 0.5);
    } else {
        y = static_cast<int>(x * va + 0.5);
    }
    return {std::max(x, 1), std::max(y, 1)};
}

}  // namespace aamap
