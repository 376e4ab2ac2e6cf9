#include "eval/yaml_reader.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <set>

#include <fmt/format.h>

#include "core/error.h"

namespace aamap::yaml {

SourceLocation Context::locate(const YAML::Node& node, const std::string& path) const {
    // A value that came from --set has no place in the file: name the option instead.
    for (const auto& [key, text] : overridden_)
        if (path == key || path.starts_with(key + ".")) return {"--set " + text, 0, 0};
    if (!node.IsDefined()) return {file_, 0, 0};  // Mark() throws on a missing node
    const YAML::Mark mark = node.Mark();
    if (mark.is_null() || mark.line < 0) return {file_, 0, 0};
    return {file_, mark.line + 1, mark.column + 1};
}

void Context::fail(const YAML::Node& node, const std::string& path, const std::string& problem) const {
    const SourceLocation where = locate(node, path);
    throw InputError(where.file, where.line, where.column, problem);
}

bool isPlainScalar(const YAML::Node& node) {
    // yaml-cpp tags a quoted scalar without an explicit tag "!", a plain one "?".
    return node.IsScalar() && node.Tag() != "!";
}

std::string describe(const YAML::Node& node) {
    switch (node.Type()) {
        case YAML::NodeType::Null: return "nothing (null)";
        case YAML::NodeType::Scalar:
            return isPlainScalar(node) ? fmt::format("'{}'", node.Scalar())
                                       : fmt::format("the quoted string \"{}\"", node.Scalar());
        case YAML::NodeType::Sequence: return "a list";
        case YAML::NodeType::Map: return "a mapping";
        default: return "nothing";
    }
}

std::string closest(const std::string& word, const std::vector<std::string>& candidates) {
    std::string best;
    std::size_t bestDistance = 3;
    for (const std::string& c : candidates) {
        // Levenshtein distance, one row at a time.
        std::vector<std::size_t> row(c.size() + 1);
        for (std::size_t j = 0; j <= c.size(); ++j) row[j] = j;
        for (std::size_t i = 1; i <= word.size(); ++i) {
            std::size_t diagonal = row[0];
            row[0] = i;
            for (std::size_t j = 1; j <= c.size(); ++j) {
                const std::size_t next = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (word[i - 1] != c[j - 1])});
                diagonal = row[j];
                row[j] = next;
            }
        }
        if (row[c.size()] < bestDistance) {
            bestDistance = row[c.size()];
            best = c;
        }
    }
    return best;
}

MapReader::MapReader(const Context& ctx, const YAML::Node& node, std::string path, std::vector<std::string> keys)
    : ctx_(ctx), node_(node.IsDefined() ? node : YAML::Node()), path_(std::move(path)), keys_(std::move(keys)) {
    if (!node_.IsNull() && !node_.IsMap())
        ctx_.fail(node_, path_, fmt::format("{}: expected a mapping, found {}", path_.empty() ? "config" : path_,
                                            describe(node_)));
    checkKeys();
}

bool MapReader::has(const std::string& key) const { return node_.IsMap() && node_[key].IsDefined(); }

YAML::Node MapReader::node(const std::string& key) {
    if (!node_.IsMap()) return YAML::Node(YAML::NodeType::Undefined);
    const YAML::Node& constNode = node_;  // const operator[] never inserts
    return constNode[key];
}

void MapReader::require(const std::string& key) const {
    if (!has(key)) ctx_.fail(node_, path_, fmt::format("missing required key '{}'", childPath(key)));
}

void MapReader::getInt(const std::string& key, int& out, long long lo, long long hi) {
    const YAML::Node n = node(key);
    if (!n.IsDefined()) return;
    long long v = 0;
    if (!decodePlain(n, v))
        ctx_.fail(n, childPath(key), fmt::format("{}: expected an integer, found {}", childPath(key), describe(n)));
    if (v < lo || v > hi)
        ctx_.fail(n, childPath(key), fmt::format("{}: {} is out of range [{}, {}]", childPath(key), v, lo, hi));
    out = static_cast<int>(v);
}

void MapReader::getUInt64(const std::string& key, std::uint64_t& out) {
    const YAML::Node n = node(key);
    if (!n.IsDefined()) return;
    std::uint64_t v = 0;
    // yaml-cpp would wrap "-1" round to 2^64-1; a leading minus is an error here.
    if (!decodePlain(n, v) || n.Scalar().starts_with("-"))
        ctx_.fail(n, childPath(key),
                  fmt::format("{}: expected a non-negative integer, found {}", childPath(key), describe(n)));
    out = v;
}

void MapReader::getDouble(const std::string& key, double& out, double lo, double hi, bool openLo) {
    const YAML::Node n = node(key);
    if (!n.IsDefined()) return;
    double v = 0;
    if (!decodePlain(n, v) || !std::isfinite(v))
        ctx_.fail(n, childPath(key), fmt::format("{}: expected a finite number, found {}", childPath(key), describe(n)));
    if (v < lo || v > hi || (openLo && v == lo))
        ctx_.fail(n, childPath(key), fmt::format("{}: {} is out of range {}{}, {}]", childPath(key), v,
                                                 openLo ? "(" : "[", lo, hi));
    out = v;
}

void MapReader::getString(const std::string& key, std::string& out) {
    const YAML::Node n = node(key);
    if (!n.IsDefined()) return;
    if (!n.IsScalar() || n.Scalar().empty())
        ctx_.fail(n, childPath(key), fmt::format("{}: expected a string, found {}", childPath(key), describe(n)));
    out = n.Scalar();
}

void MapReader::getVec3(const std::string& key, std::array<double, 3>& out, double lo, double hi) {
    const YAML::Node n = node(key);
    if (!n.IsDefined()) return;
    if (!n.IsSequence() || n.size() != 3)
        ctx_.fail(n, childPath(key),
                  fmt::format("{}: expected a list of 3 numbers, found {}", childPath(key), describe(n)));
    for (std::size_t i = 0; i < 3; ++i) {
        double v = 0;
        if (!decodePlain(n[i], v) || !std::isfinite(v))
            ctx_.fail(n[i], childPath(key),
                      fmt::format("{}[{}]: expected a finite number, found {}", childPath(key), i, describe(n[i])));
        if (v < lo || v > hi)
            ctx_.fail(n[i], childPath(key),
                      fmt::format("{}[{}]: {} is out of range [{}, {}]", childPath(key), i, v, lo, hi));
        out[i] = v;
    }
}

void MapReader::checkKeys() const {
    if (!node_.IsMap()) return;
    std::set<std::string> seen;
    for (auto it = node_.begin(); it != node_.end(); ++it) {
        const YAML::Node k = it->first;  // a copy: it-> returns a temporary proxy (ASan: stack-use-after-scope)
        const std::string where = path_.empty() ? "the config" : "'" + path_ + "'";
        if (!k.IsScalar())
            ctx_.fail(k, path_, fmt::format("a key in {} is {}; keys are names", where, describe(k)));
        const std::string name = k.Scalar();
        if (std::find(keys_.begin(), keys_.end(), name) == keys_.end()) {
            const std::string hint = closest(name, keys_);
            ctx_.fail(k, childPath(name),
                      fmt::format("unknown key '{}' in {}{}", name, where,
                                  hint.empty() ? fmt::format(" (known keys: {})", fmt::join(keys_, ", "))
                                               : fmt::format("; did you mean '{}'?", hint)));
        }
        if (!seen.insert(name).second) ctx_.fail(k, childPath(name), fmt::format("duplicate key '{}'", name));
    }
}

// ---- --set -------------------------------------------------------------------------------------

namespace {

std::vector<std::string> split(const std::string& s, char sep) {
    std::vector<std::string> parts;
    std::size_t start = 0;
    for (std::size_t i = 0; i <= s.size(); ++i)
        if (i == s.size() || s[i] == sep) {
            parts.push_back(s.substr(start, i - start));
            start = i + 1;
        }
    return parts;
}

bool isIndex(const std::string& s) {
    return !s.empty() && s.size() < 7 && std::all_of(s.begin(), s.end(), [](char c) { return c >= '0' && c <= '9'; });
}

bool matches(const std::vector<std::string>& parts, const std::vector<std::string>& pattern) {
    if (parts.size() != pattern.size()) return false;
    for (std::size_t i = 0; i < parts.size(); ++i)
        if (pattern[i] == "#" ? !isIndex(parts[i]) : parts[i] != pattern[i]) return false;
    return true;
}

}  // namespace

void applyOverride(YAML::Node& root, const std::string& text, const std::vector<std::string>& leaves, Context& ctx) {
    const std::filesystem::path option = "--set " + text;
    const std::size_t eq = text.find('=');
    if (eq == std::string::npos || eq == 0) throw InputError(option, "expected key.path=value");
    const std::string key = text.substr(0, eq);
    const std::vector<std::string> parts = split(key, '.');

    bool known = false, section = false;
    for (const std::string& leaf : leaves) {
        const std::vector<std::string> pattern = split(leaf, '.');
        known = known || matches(parts, pattern);
        if (pattern.size() > parts.size())
            section = section || matches(parts, std::vector(pattern.begin(), pattern.begin() + parts.size()));
    }
    if (!known) {
        if (section) throw InputError(option, fmt::format("'{}' is a section, not a single value; set one of its fields", key));
        const std::string hint = closest(key, leaves);
        throw InputError(option, fmt::format("unknown key '{}'{}", key, hint.empty() ? "" : " (did you mean '" + hint + "'?)"));
    }
    YAML::Node value;
    try {
        value = YAML::Load(text.substr(eq + 1));
    } catch (const YAML::Exception& e) {
        throw InputError(option, fmt::format("invalid YAML value: {}", e.msg));
    }

    if (!root.IsMap()) root = YAML::Node(YAML::NodeType::Map);
    YAML::Node cur = root;  // reset() rebinds; operator= would overwrite the node it refers to
    std::string path;
    for (std::size_t i = 0; i + 1 < parts.size(); ++i) {
        path += (i ? "." : "") + parts[i];
        YAML::Node next;
        if (isIndex(parts[i])) {
            const std::size_t index = std::stoul(parts[i]);
            if (!cur.IsSequence() || index >= cur.size())
                throw InputError(option, fmt::format("'{}' does not exist: the list has {} item(s)", path,
                                                     cur.IsSequence() ? cur.size() : 0));
            next.reset(cur[index]);
        } else {
            if (!cur[parts[i]] || cur[parts[i]].IsNull()) cur[parts[i]] = YAML::Node(isIndex(parts[i + 1]) ? YAML::NodeType::Sequence : YAML::NodeType::Map);
            next.reset(cur[parts[i]]);
        }
        if (!isIndex(parts[i + 1]) && !next.IsMap())
            throw InputError(option, fmt::format("'{}' in the config is {}, not a mapping", path, describe(next)));
        cur.reset(next);
    }
    cur[parts.back()] = value;
    ctx.markOverridden(key, text);
}

}  // namespace aamap::yaml
