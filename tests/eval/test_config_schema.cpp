// The schema-declared config sections (eval/config_schema.h), walked key by key: every default
// parses and is what the config's structs hold, the range ends are accepted and the values just
// outside rejected at the key's file:line, --set reaches the field, and the key is in --help and
// the docs. Each key is read back through the field its schema binds it to, so a key added to a
// schema is walked here without an edit.
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <functional>
#include <limits>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "core/error.h"
#include "eval/config.h"
#include "eval/config_schema.h"
#include "core/schema.h"
#include "passes/snapshot_params.h"
#include "tracer/shading_params.h"
#include "tests/common/read_text.h"

namespace aamap {
namespace {

struct Key {
    std::string section, dotted;
    const ParamSpec* spec;
    const ConfigSection* owner;
    // The key's value in a config, read from the field its schema binds it to.
    ParamValue field(const ExperimentConfig& c) const { return *owner->values(c).find(spec->name); }
};

std::vector<Key> allKeys() {
    std::vector<Key> keys;
    for (const ConfigSection& s : configSections())
        for (const ParamSpec& p : s.params)
            keys.push_back({s.path, s.path.empty() ? p.name : s.path + "." + p.name, &p, &s});
    return keys;
}

// Equal, a real to the precision of the field holding it (a float for the tracer's settings).
::testing::AssertionResult sameValue(const ParamValue& got, const ParamValue& expected) {
    if (got == expected) return ::testing::AssertionSuccess();
    if (std::holds_alternative<double>(got) && std::holds_alternative<double>(expected)) {
        const double a = std::get<double>(got), b = std::get<double>(expected);
        if (std::fabs(a - b) <= 1e-6 * std::fabs(b) + 1e-37) return ::testing::AssertionSuccess();
    }
    return ::testing::AssertionFailure() << toString(got) << " != " << toString(expected);
}

// A config setting `key` to `value` (YAML text), and the line the key is on.
std::string configWith(const Key& k, const std::string& value, int& line) {
    std::string text = "scene: builtin:cornell\nrenders:\n  - {name: u, strategy: aamap, rpp: 4}\n";
    line = 4;
    if (k.section.empty()) return text + fmt::format("{}: {}\n", k.spec->name, value);
    std::string indent;
    std::size_t start = 0;
    for (std::size_t dot = k.section.find('.'); ; dot = k.section.find('.', start)) {
        text += indent + k.section.substr(start, dot - start) + ":\n";
        ++line;
        indent += "  ";
        if (dot == std::string::npos) break;
        start = dot + 1;
    }
    if (k.dotted == "image.filter_stddev") {  // a cross-key rule: only the gaussian filter has one
        text += indent + "filter: gaussian\n";
        ++line;
    }
    return text + fmt::format("{}{}: {}\n", indent, k.spec->name, value);
}

std::string yamlText(const ParamValue& v) { return v.index() == 1 ? fmt::format("{}", std::get<double>(v)) : toString(v); }

std::vector<std::string> acceptedValues(const ParamSpec& p) {
    if (p.type == ParamType::Choice) return p.choices;
    if (p.type == ParamType::Bool) return {"true", "false"};
    std::vector<std::string> v;
    if (!p.openLo) v.push_back(p.type == ParamType::Int ? formatNumber(p.lo) : fmt::format("{}", p.lo));
    else v.push_back(fmt::format("{}", std::nextafter(p.lo, std::numeric_limits<double>::infinity())));
    v.push_back(p.type == ParamType::Int ? formatNumber(p.hi) : fmt::format("{}", p.hi));
    return v;
}

std::vector<std::string> rejectedValues(const ParamSpec& p) {
    if (p.type == ParamType::Choice) return {"no-such-choice"};
    if (p.type == ParamType::Bool) return {"3", "\"true\""};
    if (p.type == ParamType::Int) return {formatNumber(p.lo - 1), formatNumber(p.hi + 1)};
    const double below = p.openLo ? p.lo : std::nextafter(p.lo, -std::numeric_limits<double>::infinity());
    return {fmt::format("{}", below), fmt::format("{}", std::nextafter(p.hi, std::numeric_limits<double>::infinity()))};
}

TEST(ConfigSchema, DefaultsAreTheStructsDefaultsAndParse) {
    const ExperimentConfig handBuilt;
    for (const Key& k : allKeys()) {
        EXPECT_TRUE(sameValue(k.field(handBuilt), k.spec->defaultParam())) << k.dotted;
        int line = 0;
        const ExperimentConfig c = parseConfig(configWith(k, yamlText(k.spec->defaultParam()), line), "exp.yaml");
        EXPECT_TRUE(sameValue(k.field(c), k.spec->defaultParam())) << k.dotted;
    }
}

TEST(ConfigSchema, RangeEndsAcceptedJustOutsideRejectedAtTheKey) {
    for (const Key& k : allKeys()) {
        for (const std::string& v : acceptedValues(*k.spec)) {
            int line = 0;
            const std::string text = configWith(k, v, line);
            EXPECT_NO_THROW(parseConfig(text, "exp.yaml")) << k.dotted << " = " << v;
        }
        for (const std::string& v : rejectedValues(*k.spec)) {
            int line = 0;
            const std::string text = configWith(k, v, line);
            try {
                parseConfig(text, "exp.yaml");
                ADD_FAILURE() << k.dotted << " = " << v << " was accepted";
            } catch (const InputError& e) {
                EXPECT_EQ(e.file(), "exp.yaml") << e.what();
                EXPECT_EQ(e.line(), line) << e.what();
                EXPECT_NE(std::string(e.what()).find(k.dotted), std::string::npos) << e.what();
            }
        }
    }
}

TEST(ConfigSchema, SetReachesTheField) {
    const std::vector<std::string> settable = settableKeys();
    for (const Key& k : allKeys()) {
        EXPECT_NE(std::find(settable.begin(), settable.end(), k.dotted), settable.end()) << k.dotted;
        int line = 0;
        const std::string base = configWith(k, yamlText(k.spec->defaultParam()), line);
        for (const std::string& v : acceptedValues(*k.spec)) {
            const ExperimentConfig c = parseConfig(base, "exp.yaml", {k.dotted + "=" + v});
            std::string error;
            const ParamValue expected = k.spec->type == ParamType::Choice ? ParamValue(v)
                                        : k.spec->type == ParamType::Bool ? ParamValue(v == "true")
                                        : k.spec->type == ParamType::Int  ? ParamValue(std::stoi(v))
                                                                          : ParamValue(std::strtod(v.c_str(), nullptr));
            EXPECT_TRUE(sameValue(k.field(c), expected)) << k.dotted << " = " << v;
        }
    }
}

TEST(ConfigSchema, EveryKeyIsInTheHelpAndTheDocs) {
    const std::string help = sectionHelpLines();
    const std::string cli = test::readText(std::string(AAMAP_SOURCE_DIR) + "/docs/cli.md");
    const std::string config = test::readText(std::string(AAMAP_SOURCE_DIR) + "/docs/config.md");
    for (const ConfigSection& s : configSections()) {
        const std::string open = s.path.empty() ? "" : s.path + ": {";
        if (!open.empty()) {
            EXPECT_NE(help.find(open), std::string::npos) << s.path;
            EXPECT_NE(cli.find(open), std::string::npos) << s.path << " not in docs/cli.md";
        }
        for (const ParamSpec& p : s.params) {
            const std::string dotted = s.path.empty() ? p.name : s.path + "." + p.name;
            const std::string entry = p.type == ParamType::Choice
                                          ? fmt::format("{}: {}", p.name, fmt::join(p.choices, "|"))
                                          : fmt::format("{}: {}", p.name, toString(p.defaultParam()));
            EXPECT_NE(help.find(entry), std::string::npos) << entry;
            EXPECT_NE(cli.find(entry), std::string::npos) << entry << " not in docs/cli.md";
            EXPECT_NE(config.find("`" + dotted + "`"), std::string::npos) << dotted << " not in docs/config.md";
        }
    }
}

// A hand-built config (the structs' defaults) and the parsed one have the same cache keys, and the
// Snapshot's key holds exactly the schema's keys once the later ones are not at their defaults.
TEST(ConfigSchema, CacheKeysOfAHandBuiltConfigMatchTheParsedOne) {
    const ExperimentConfig parsed = parseConfig(
        "scene: builtin:cornell\nrenders:\n  - {name: a, strategy: aamap, rpp: 4}\n", "exp.yaml");
    ExperimentConfig hand;
    hand.file = "exp.yaml";
    hand.scene = "builtin:cornell";
    hand.renders = parsed.renders;
    hand.reference = parsed.reference;
    EXPECT_EQ(renderKeyJson(hand, hand.renders[0]), renderKeyJson(parsed, parsed.renders[0]));
    EXPECT_EQ(snapshotKey(hand), snapshotKey(parsed));
    EXPECT_EQ(hand.hash(), parsed.hash());

    // The keys hold the keys not at their default: each snapshot key enters once set, and only then.
    const auto snapshotKeyNames = [](const ExperimentConfig& c) {
        const nlohmann::json key = nlohmann::json::parse(renderKeyJson(c, c.renders[0]));
        std::vector<std::string> names;
        for (const auto& item : key.at("snapshot").items()) names.push_back(item.key());
        return names;
    };
    EXPECT_TRUE(snapshotKeyNames(hand).empty());
    const ExperimentConfig defaults = hand;
    std::vector<std::string> schema;
    for (const Schema<SnapshotSettings>::Field& f : snapshotSchema().fields()) {
        ExperimentConfig one = defaults;
        const ParamSpec& p = f.spec;
        const ParamValue other = p.type == ParamType::Bool     ? ParamValue(!std::get<bool>(p.defaultParam()))
                                 : p.type == ParamType::Choice ? ParamValue(p.choices.back())
                                 : p.type == ParamType::Int    ? ParamValue(static_cast<int>(p.defaultValue == p.hi ? p.lo : p.hi))
                                                               : ParamValue(p.defaultValue == p.hi ? p.lo : p.hi);
        f.set(one.snapshot, other);
        f.set(hand.snapshot, other);
        EXPECT_EQ(snapshotKeyNames(one), std::vector<std::string>{p.name}) << p.name;
        EXPECT_NE(snapshotKey(one), snapshotKey(parsed)) << p.name;
        schema.push_back(p.name);
    }
    std::vector<std::string> all = snapshotKeyNames(hand);
    std::sort(all.begin(), all.end());
    std::sort(schema.begin(), schema.end());
    EXPECT_EQ(all, schema);
}

}  // namespace
}  // namespace aamap

namespace aamap {
namespace {

// docs/config.md holds the table of every schema key that `aamap run --list-keys` prints, as
// tools/update_cli_docs.py copies it: type, range, default and meaning from the declaration.
TEST(ConfigSchema, DocsHoldTheGeneratedKeyTable) {
    const std::string doc = test::readText(std::string(AAMAP_SOURCE_DIR) + "/docs/config.md");
    EXPECT_NE(doc.find("<!-- keys -->\n" + configKeysMarkdown() + "<!-- /keys -->"), std::string::npos)
        << "docs/config.md's key table is stale: run tools/update_cli_docs.py";
}

// A value away from its default, for the key walks below: the other end of the range, the other
// boolean, the last choice.
ParamValue otherThanDefault(const ParamSpec& p) {
    if (p.type == ParamType::Bool) return !std::get<bool>(p.defaultParam());
    if (p.type == ParamType::Choice) return p.choices.back();
    const double v = p.defaultValue == p.hi ? p.lo : p.hi;
    return p.type == ParamType::Int ? ParamValue(static_cast<int>(v)) : ParamValue(v);
}

// Every shading key, set away from its default, reaches its field and enters the render's cache
// key under its own name (the cache's keys in cache mode), and changes it.
TEST(ConfigSchema, EveryShadingKeyEntersTheRenderKey) {
    const ExperimentConfig base = parseConfig(
        "scene: builtin:cornell\nrenders:\n  - {name: a, strategy: uniform, rpp: 4}\n", "exp.yaml");
    const auto shadingKey = [](const ExperimentConfig& c) {
        return nlohmann::json::parse(renderKeyJson(c, c.renders[0])).at("shading");
    };
    for (const Schema<ShadingSettings>::Field& f : shadingSchema().fields()) {
        ExperimentConfig c = base;
        const ParamValue v = otherThanDefault(f.spec);
        f.set(c.shading, v);
        EXPECT_TRUE(sameValue(f.get(c.shading), v)) << f.spec.name;
        EXPECT_TRUE(shadingKey(c).contains(f.spec.name)) << f.spec.name << ": " << shadingKey(c).dump();
        EXPECT_NE(renderKey(c, c.renders[0]), renderKey(base, base.renders[0])) << f.spec.name;
    }
    for (const Schema<IrradianceCacheSettings>::Field& f : shadingCacheSchema().fields()) {
        ExperimentConfig c = base;
        c.shading.mode = ShadingMode::Cache;
        ExperimentConfig tuned = c;
        f.set(tuned.shading.cache, otherThanDefault(f.spec));
        EXPECT_TRUE(shadingKey(tuned).at("cache").contains(f.spec.name)) << f.spec.name;
        EXPECT_NE(renderKey(tuned, tuned.renders[0]), renderKey(c, c.renders[0])) << f.spec.name;
        // Outside cache mode the cache is not read, and the key does not name it.
        tuned.shading.mode = ShadingMode::Direct;
        EXPECT_EQ(renderKey(tuned, tuned.renders[0]), renderKey(base, base.renders[0])) << f.spec.name;
    }
}

// The subpixel map holds its prediction against the metrics' FLIP threshold: the threshold is part
// of that Snapshot's key and of its renders' keys, and of no other map's.
TEST(ConfigSchema, FlipThresholdEntersOnlyTheSubpixelSnapshotKey) {
    const auto key = [](const std::string& map, double threshold, bool render) {
        const ExperimentConfig c = parseConfig(
            fmt::format("scene: builtin:cornell\nsnapshot: {{map: {}}}\nmetrics: {{flip_threshold: {}}}\n"
                        "renders:\n  - {{name: a, strategy: aamap, rpp: 4}}\n",
                        map, threshold),
            "exp.yaml");
        return render ? renderKey(c, c.renders[0]) : snapshotKey(c);
    };
    for (bool render : {false, true}) {
        EXPECT_NE(key("subpixel", 0.1, render), key("subpixel", 0.2, render)) << render;
        EXPECT_EQ(key("luminance", 0.1, render), key("luminance", 0.2, render)) << render;
        EXPECT_EQ(key("geometric", 0.1, render), key("geometric", 0.2, render)) << render;
    }
}

}  // namespace
}  // namespace aamap
