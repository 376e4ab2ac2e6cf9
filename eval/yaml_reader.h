#pragma once
// Strict YAML reading with positions: every problem becomes an InputError at the offending node
// (file:line:col), or at the --set option that supplied it. Unknown and duplicate keys are errors.
#include <array>
#include <cstdint>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include <yaml-cpp/yaml.h>

#include "eval/config.h"

namespace aamap::yaml {

class Context {
public:
    explicit Context(std::filesystem::path file) : file_(std::move(file)) {}

    // Records that `path` (dotted, list items by index) was set by the override `text`.
    void markOverridden(const std::string& path, const std::string& text) { overridden_[path] = text; }

    SourceLocation locate(const YAML::Node& node, const std::string& path) const;
    [[noreturn]] void fail(const YAML::Node& node, const std::string& path, const std::string& problem) const;

    const std::filesystem::path& file() const { return file_; }

private:
    std::filesystem::path file_;
    std::map<std::string, std::string> overridden_;
};

// Numbers and booleans are written plain: a quoted scalar ("4", 'true') is a string in YAML, and
// the config is parsed as strictly as it is documented.
bool isPlainScalar(const YAML::Node& node);

// Decodes a plain scalar as T (yaml-cpp's own conversion, which takes only integer literals for
// integer types: 4, not 4.0); false for a quoted scalar, a list or a mapping.
template <class T>
bool decodePlain(const YAML::Node& node, T& out) {
    return isPlainScalar(node) && YAML::convert<T>::decode(node, out);
}

// "a string", "a list", ... for error messages.
std::string describe(const YAML::Node& node);

// The closest of `candidates` to `word` (edit distance at most 2), or "".
std::string closest(const std::string& word, const std::vector<std::string>& candidates);

// Reads one mapping whose allowed keys are `keys`. The constructor rejects unknown keys (naming
// the nearest known one) and duplicates before any value is read, so a typo ("intensty") is
// reported as a typo, not as the missing key it was meant to be.
class MapReader {
public:
    // A null node (an empty section) reads as an empty mapping.
    MapReader(const Context& ctx, const YAML::Node& node, std::string path, std::vector<std::string> keys);

    bool has(const std::string& key) const;
    YAML::Node node(const std::string& key);  // claims the key; undefined if absent
    std::string childPath(const std::string& key) const { return path_.empty() ? key : path_ + "." + key; }
    const YAML::Node& self() const { return node_; }
    const std::string& path() const { return path_; }

    void getInt(const std::string& key, int& out, long long lo, long long hi);
    void getUInt64(const std::string& key, std::uint64_t& out);
    // openLo: the lower bound is excluded (exposure > 0).
    void getDouble(const std::string& key, double& out, double lo, double hi, bool openLo = false);
    void getString(const std::string& key, std::string& out);
    void getVec3(const std::string& key, std::array<double, 3>& out, double lo, double hi);
    void require(const std::string& key) const;  // fails at the mapping if key is absent

private:
    void checkKeys() const;

    const Context& ctx_;
    YAML::Node node_;
    std::string path_;
    std::vector<std::string> keys_;
};

// Applies "key.path=value" to the document. `leaves` lists the settable paths, '#' standing for
// a list index. Throws InputError naming the option for unknown paths and bad values.
void applyOverride(YAML::Node& root, const std::string& text, const std::vector<std::string>& leaves, Context& ctx);

}  // namespace aamap::yaml
