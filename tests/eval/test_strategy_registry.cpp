// The strategy registry against everything that describes it: every strategy's schema is sound,
// its choices round-trip through the config and the cache keys, --help and docs/config.md list
// exactly the registry's names and parameters (ranges, defaults), and the config accepts the
// defaults and rejects out-of-range values at their file:line:column.
#include <cmath>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "core/error.h"
#include "eval/config.h"
#include "eval/strategies.h"

namespace aamap {
namespace {

// A render entry in block style: the parameter's value is on line 5, column key.size() + 7.
std::string configWith(const std::string& strategy, const std::string& key, const std::string& value) {
    return fmt::format("scene: builtin:cornell\nrenders:\n  - strategy: {}\n    rpp: 4\n    {}: {}\n", strategy, key,
                       value);
}

ExperimentConfig parseWithOverrides(const std::string& text, const std::vector<std::string>& overrides = {}) {
    return parseConfig(text, "exp.yaml", overrides);
}

TEST(StrategyRegistry, SchemasAreSound) {
    ASSERT_FALSE(strategyRegistry().empty());
    EXPECT_EQ(strategyRegistry().front().name, "uniform");  // the baseline of speedups
    for (const StrategyDescriptor& s : strategyRegistry()) {
        SCOPED_TRACE(s.name);
        EXPECT_EQ(findStrategy(s.name), &s);
        EXPECT_FALSE(s.doc.empty());
        EXPECT_TRUE(static_cast<bool>(s.create));
        if (s.needsBlockSums) {
            EXPECT_TRUE(s.usesAamap) << "block sums are the map's";
        }
        for (const ParamSpec& p : s.params) {
            SCOPED_TRACE(p.name);
            EXPECT_EQ(s.param(p.name), &p) << "declared twice";
            EXPECT_FALSE(p.doc.empty());
            std::string error;
            const auto checked = p.check(p.defaultParam(), error);
            ASSERT_TRUE(checked.has_value()) << error;
            EXPECT_EQ(*checked, p.defaultParam());
            if (p.type == ParamType::Choice) {
                EXPECT_GE(p.choices.size(), 2u);
                continue;
            }
            EXPECT_LE(p.lo, p.defaultValue);
            EXPECT_LE(p.defaultValue, p.hi);
            if (p.type == ParamType::Int) {
                EXPECT_TRUE(p.lo == std::floor(p.lo) && p.hi == std::floor(p.hi) &&
                            p.defaultValue == std::floor(p.defaultValue));
            }
        }
        // Resolving nothing gives every default, in schema order.
        const StrategyParams defaults = resolveParams(s, {});
        ASSERT_EQ(defaults.entries().size(), s.params.size());
        for (std::size_t i = 0; i < s.params.size(); ++i) {
            EXPECT_EQ(defaults.entries()[i].first, s.params[i].name);
            EXPECT_EQ(defaults.entries()[i].second, s.params[i].defaultParam());
        }
    }
}

TEST(StrategyRegistry, EveryChoiceRoundTrips) {
    for (const StrategyDescriptor& s : strategyRegistry())
        for (const ParamSpec& p : s.params) {
            if (p.type != ParamType::Choice) continue;
            for (const std::string& choice : p.choices) {
                SCOPED_TRACE(s.name + "." + p.name + "=" + choice);
                const StrategyParams resolved = resolveParams(s, StrategyParams{{p.name, choice}});
                EXPECT_EQ(resolved.choice(p.name), choice);
                const ExperimentConfig c = parseWithOverrides(configWith(s.name, p.name, choice));
                EXPECT_EQ(c.renders[0].params.choice(p.name), choice);
                EXPECT_NE(renderKeyJson(c, c.renders[0]).find(fmt::format("\"{}\":\"{}\"", p.name, choice)),
                          std::string::npos);
            }
            std::string error;
            EXPECT_FALSE(p.check(std::string("no-such-choice"), error).has_value());
            EXPECT_NE(error.find(p.choices.front()), std::string::npos) << error;
        }
}

// The cache keys write numbers as doubles and choices by name, so existing caches stay valid.
TEST(StrategyRegistry, RenderKeysKeepTheirParameterFormat) {
    const ExperimentConfig c = parseWithOverrides("scene: builtin:cornell\nrenders:\n  - {strategy: aamap-subsample, rpp: 4}\n"
                                     "  - {strategy: supersample, rpp: 4, filter: gaussian}\n");
    EXPECT_NE(renderKeyJson(c, c.renders[0]).find(R"("params":{"spacing":8.0,"threshold":0.0,"gradient_tolerance":2.0,"mapping":"paper"})"),
              std::string::npos)
        << renderKeyJson(c, c.renders[0]);
    EXPECT_NE(renderKeyJson(c, c.renders[1])
                  .find(R"("params":{"supersample":2.0,"filter":"gaussian","filter_radius":0.6})"),
              std::string::npos)
        << renderKeyJson(c, c.renders[1]);
}

TEST(StrategyRegistry, ConfigAcceptsDefaultsAndRejectsOutOfRangeAtTheValue) {
    for (const StrategyDescriptor& s : strategyRegistry())
        for (const ParamSpec& p : s.params) {
            SCOPED_TRACE(s.name + "." + p.name);
            const std::string fallback = toString(p.defaultParam());
            const ExperimentConfig c = parseWithOverrides(configWith(s.name, p.name, fallback));
            EXPECT_EQ(*c.renders[0].params.find(p.name), p.defaultParam());
            // The same render without the key: the default fills in, with the same cache key.
            const ExperimentConfig bare = parseWithOverrides(fmt::format("scene: builtin:cornell\nrenders:\n  - strategy: {}\n"
                                                            "    rpp: 4\n", s.name));
            EXPECT_EQ(renderKeyJson(bare, bare.renders[0]), renderKeyJson(c, c.renders[0]));

            std::vector<std::string> bad;
            if (p.type == ParamType::Choice) bad.push_back("no-such-choice");
            if (p.type != ParamType::Choice && std::isfinite(p.lo)) bad.push_back(formatNumber(p.lo - 1));
            if (p.type != ParamType::Choice && std::isfinite(p.hi)) bad.push_back(formatNumber(p.hi + 1));
            ASSERT_FALSE(bad.empty());
            for (const std::string& value : bad) {
                SCOPED_TRACE(value);
                try {
                    parseWithOverrides(configWith(s.name, p.name, value));
                    ADD_FAILURE() << "accepted";
                } catch (const InputError& e) {
                    EXPECT_EQ(e.file(), "exp.yaml");
                    EXPECT_EQ(e.line(), 5) << e.what();
                    EXPECT_EQ(e.column(), static_cast<int>(p.name.size()) + 7) << e.what();
                    const std::string what = e.what();
                    const std::string where = fmt::format("exp.yaml:5:{}: renders.0.{}: ", p.name.size() + 7, p.name);
                    EXPECT_EQ(what.rfind(where, 0), 0u) << what;
                    EXPECT_NE(what.find(p.type == ParamType::Choice ? p.choices.front() : p.rangeText()),
                              std::string::npos)
                        << what;
                }
                // --set goes through the same schema.
                const std::string set = fmt::format("renders.0.{}={}", p.name, value);
                EXPECT_THROW(parseWithOverrides(configWith(s.name, p.name, fallback), {set}), InputError);
                // And so does the tracer's own check.
                EXPECT_THROW(resolveParams(s, StrategyParams{{p.name, p.type == ParamType::Choice
                                                                          ? ParamValue(value)
                                                                          : ParamValue(std::stod(value))}}),
                             std::invalid_argument);
            }
        }
}

TEST(StrategyRegistry, HelpListsEveryStrategyWithItsRangesAndDefaults) {
    std::istringstream lines(strategyHelpLines());
    std::vector<std::string> names;
    for (std::string line; std::getline(lines, line);) {
        std::istringstream words(line);
        std::string name;
        words >> name;
        names.push_back(name);
        const StrategyDescriptor* s = findStrategy(name);
        ASSERT_NE(s, nullptr) << line;
        EXPECT_EQ(line.find("[aamap]") != std::string::npos, s->usesAamap) << line;
        if (s->params.empty()) {
            EXPECT_NE(line.find("no parameters"), std::string::npos) << line;
        }
        for (const ParamSpec& p : s->params) {
            const std::string expected =
                p.type == ParamType::Choice
                    ? fmt::format("{} {} ({})", p.name, fmt::join(p.choices, "/"), p.choices.front())
                    : fmt::format("{} {} in [{}, {}] ({})", p.name, p.type == ParamType::Int ? "int" : "real", p.lo,
                                  p.hi, formatNumber(p.defaultValue));
            EXPECT_NE(line.find(expected), std::string::npos) << line << "\n  lacks: " << expected;
        }
    }
    EXPECT_EQ(names, strategyNames());
}

std::string sourceFile(const std::string& path) {
    std::ifstream in(std::string(AAMAP_SOURCE_DIR) + "/" + path);
    EXPECT_TRUE(in.good()) << path << " not found under " << AAMAP_SOURCE_DIR;
    std::stringstream text;
    text << in.rdbuf();
    return text.str();
}

TEST(StrategyRegistry, CliDocsQuoteTheHelpLines) {
    EXPECT_NE(sourceFile("docs/cli.md").find(strategyHelpLines()), std::string::npos)
        << "docs/cli.md: the strategy lines of `aamap run --help` are\n"
        << strategyHelpLines();
}

// The rows of docs/config.md's strategy table: | `name` | yes/no | parameters | what it does |.
struct DocRow {
    std::string name, usesAamap, params;
};

std::vector<std::string> cells(const std::string& row) {
    std::vector<std::string> out;
    std::size_t at = 1;
    for (std::size_t bar; (bar = row.find(" | ", at)) != std::string::npos; at = bar + 3)
        out.push_back(row.substr(at == 1 ? 2 : at, bar - (at == 1 ? 2 : at)));
    out.push_back(row.substr(at, row.size() - at - 2));
    return out;
}

std::vector<DocRow> docRows() {
    std::istringstream in(sourceFile("docs/config.md"));
    std::vector<DocRow> rows;
    bool inSection = false;
    for (std::string line; std::getline(in, line);) {
        if (line.starts_with("### ")) inSection = line == "### Strategies and their parameters";
        if (!inSection || !line.starts_with("| `") || line.starts_with("| `strategy` |")) continue;  // not the header
        const std::vector<std::string> c = cells(line);
        EXPECT_EQ(c.size(), 4u) << line;
        if (c.size() < 3) continue;
        rows.push_back({c[0].substr(1, c[0].size() - 2), c[1], c[2]});
    }
    return rows;
}

TEST(StrategyRegistry, DocsTableListsExactlyTheRegistry) {
    const std::vector<DocRow> rows = docRows();
    std::vector<std::string> names;
    for (const DocRow& r : rows) names.push_back(r.name);
    EXPECT_EQ(names, strategyNames()) << "docs/config.md, \"Strategies and their parameters\"";
    for (const DocRow& r : rows) {
        const StrategyDescriptor* s = findStrategy(r.name);
        if (s == nullptr) continue;
        SCOPED_TRACE(r.name);
        EXPECT_EQ(r.usesAamap, s->usesAamap ? "yes" : "no");
        EXPECT_EQ(r.params, strategyParamsText(*s, true));
    }
}

// docs/tracer.md's table of rules has a row per strategy too.
TEST(StrategyRegistry, TracerDocsHaveARulePerStrategy) {
    std::istringstream in(sourceFile("docs/tracer.md"));
    std::vector<std::string> names;
    bool inSection = false;
    for (std::string line; std::getline(in, line);) {
        if (line.starts_with("## ")) inSection = line.starts_with("## Sampling strategies");
        if (inSection && line.starts_with("| `")) names.push_back(line.substr(3, line.find('`', 3) - 3));
    }
    EXPECT_EQ(names, strategyNames()) << "docs/tracer.md, \"Sampling strategies\"";
}

}  // namespace
}  // namespace aamap
