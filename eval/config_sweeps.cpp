#include "eval/config_sweeps.h"

#include <algorithm>
#include <utility>
#include <vector>

#include <fmt/format.h>
#include <fmt/ranges.h>

namespace aamap::detail {
namespace {

// Settings that take one scalar each, so that a list there can only mean a sweep. The renders
// (which sweep their own way), the lights, the metrics, the report and the timing do not sweep.
const std::vector<std::string>& topLevelScalars() {
    static const std::vector<std::string> keys = {"scene", "view", "view_index", "seed", "light_file"};
    return keys;
}
const std::vector<std::string>& sweptSections() {
    static const std::vector<std::string> keys = {"image", "snapshot", "shading", "reference"};
    return keys;
}

// A mapping key's name; "" for a key that is not a scalar (`? [a, b]: 1`), which the section's
// MapReader then rejects with its position.
std::string keyName(const YAML::Node& key) { return key.IsScalar() ? key.Scalar() : std::string(); }

// The keys of a mapping a sweep may go through: the first of each name (a repeated key, which
// the reader rejects as a duplicate with its line, must not be where a variant's value is put:
// node[key] finds the first) and none holding the path separator (no setting's name does).
std::vector<std::pair<std::string, YAML::Node>> sweepableEntries(const YAML::Node& map) {
    std::vector<std::pair<std::string, YAML::Node>> entries;
    for (const auto& kv : map) {
        const std::string name = keyName(kv.first);
        if (name.empty() || name.find('.') != std::string::npos) continue;
        if (std::any_of(entries.begin(), entries.end(), [&](const auto& e) { return e.first == name; })) continue;
        entries.emplace_back(name, kv.second);
    }
    return entries;
}

void collect(const yaml::Context& ctx, const YAML::Node& node, const std::string& path,
             std::vector<ConfigSweep>& out) {
    if (node.IsMap()) {
        for (const auto& [name, value] : sweepableEntries(node)) collect(ctx, value, path + "." + name, out);
        return;
    }
    if (!node.IsSequence()) return;
    ConfigSweep sweep{path, {}};
    for (const YAML::Node& item : node) {
        const auto same = [&](const YAML::Node& v) { return v.IsScalar() && item.IsScalar() && v.Scalar() == item.Scalar(); };
        if (std::any_of(sweep.values.begin(), sweep.values.end(), same))
            ctx.fail(item, path, fmt::format("{}: the sweep lists '{}' twice", path, item.Scalar()));
        sweep.values.push_back(item);
    }
    if (sweep.values.empty()) ctx.fail(node, path, fmt::format("{}: an empty list sweeps nothing", path));
    out.push_back(std::move(sweep));
}

// The node at a dotted path of a copied document (the path exists: it was found in the original).
void setAt(YAML::Node root, const std::string& key, const YAML::Node& value) {
    std::vector<std::string> parts;
    for (std::size_t start = 0, dot; start <= key.size(); start = dot + 1) {
        dot = key.find('.', start);
        if (dot == std::string::npos) dot = key.size();
        parts.push_back(key.substr(start, dot - start));
    }
    YAML::Node node = root;
    for (std::size_t i = 0; i + 1 < parts.size(); ++i) node.reset(node[parts[i]]);
    node[parts.back()] = value;
}

}  // namespace

std::vector<ConfigSweep> findConfigSweeps(const yaml::Context& ctx, const YAML::Node& root) {
    std::vector<ConfigSweep> sweeps;
    if (!root.IsMap()) return sweeps;
    for (const auto& [key, value] : sweepableEntries(root)) {
        const bool scalarKey = std::find(topLevelScalars().begin(), topLevelScalars().end(), key) != topLevelScalars().end();
        const bool section = std::find(sweptSections().begin(), sweptSections().end(), key) != sweptSections().end();
        if (scalarKey && value.IsSequence()) collect(ctx, value, key, sweeps);
        if (section && value.IsMap())
            for (const auto& [name, inner] : sweepableEntries(value)) collect(ctx, inner, key + "." + name, sweeps);
    }
    return sweeps;
}

std::vector<std::vector<std::size_t>> takeZipGroups(const yaml::Context& ctx, YAML::Node& root,
                                                    const std::vector<ConfigSweep>& sweeps) {
    std::vector<std::vector<std::size_t>> groups;
    std::vector<bool> zipped(sweeps.size(), false);
    if (root.IsMap() && root["zip"]) {
        const YAML::Node zip = root["zip"];
        if (!zip.IsSequence()) ctx.fail(zip, "zip", "zip: expected a list of lists of swept keys ([[a.b, c.d], ...])");
        for (const YAML::Node& group : zip) {
            if (!group.IsSequence() || group.size() < 2)
                ctx.fail(group, "zip", "zip: each entry lists two or more swept keys that vary together");
            std::vector<std::size_t> members;
            for (const YAML::Node& key : group) {
                const std::string name = key.IsScalar() ? key.Scalar() : std::string();
                const auto it = std::find_if(sweeps.begin(), sweeps.end(), [&](const ConfigSweep& s) { return s.key == name; });
                if (it == sweeps.end()) {
                    std::vector<std::string> swept;
                    for (const ConfigSweep& s : sweeps) swept.push_back(s.key);
                    ctx.fail(key, "zip", fmt::format("zip: '{}' is not a swept key (swept: {})", name,
                                                     swept.empty() ? std::string("none") : fmt::format("{}", fmt::join(swept, ", "))));
                }
                const auto i = static_cast<std::size_t>(it - sweeps.begin());
                if (zipped[i]) ctx.fail(key, "zip", fmt::format("zip: '{}' is zipped twice", name));
                if (!members.empty() && sweeps[members.front()].values.size() != it->values.size())
                    ctx.fail(key, "zip",
                             fmt::format("zip: '{}' lists {} values and '{}' {}: zipped lists vary together, so their "
                                         "lengths must be equal",
                                         name, it->values.size(), sweeps[members.front()].key,
                                         sweeps[members.front()].values.size()));
                zipped[i] = true;
                members.push_back(i);
            }
            groups.push_back(std::move(members));
        }
        root.remove("zip");
    }
    for (std::size_t i = 0; i < sweeps.size(); ++i)
        if (!zipped[i]) groups.push_back({i});
    std::sort(groups.begin(), groups.end(), [](const auto& a, const auto& b) {
        return *std::min_element(a.begin(), a.end()) < *std::min_element(b.begin(), b.end());
    });
    return groups;
}

void forEachConfigVariant(const yaml::Context& ctx, YAML::Node& root, const std::vector<ConfigSweep>& sweeps,
                          const std::vector<std::vector<std::size_t>>& groups, std::size_t maxVariants,
                          const std::function<void(const YAML::Node& doc, const std::vector<std::size_t>& choice)>& variant) {
    std::size_t count = 1;
    for (const auto& group : groups) {
        const ConfigSweep& s = sweeps[group.front()];
        count *= s.values.size();
        if (count > maxVariants)
            ctx.fail(s.values.front(), s.key,
                     fmt::format("{}: the sweeps expand to more than {} variants of the experiment", s.key, maxVariants));
    }
    for (std::size_t index = 0; index < count; ++index) {
        std::vector<std::size_t> choice(sweeps.size(), 0);
        std::size_t rest = index, stride = count;
        for (const auto& group : groups) {
            stride /= sweeps[group.front()].values.size();
            for (std::size_t i : group) {
                choice[i] = rest / stride;
                setAt(root, sweeps[i].key, sweeps[i].values[rest / stride]);
            }
            rest %= stride;
        }
        variant(root, choice);
    }
}

}  // namespace aamap::detail
