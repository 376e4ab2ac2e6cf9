// Sweep expansion: list values in renders[] become the cartesian product, with names, series and
// cache keys; errors keep file:line:col.
#include <set>
#include <string>

#include <gtest/gtest.h>

#include "core/error.h"
#include "eval/config.h"
#include "eval/strategies.h"

namespace aamap {
namespace {

// A strategy with parameters, registered for the scope of one test (others walk the registry).
struct SpacedStrategy {
    SpacedStrategy() {
        StrategyDescriptor d;
        d.name = "spaced";
        d.doc = "test strategy";
        d.usesAamap = true;
        d.params = {intParam("spacing", 2, 64, 8, "pixels between corner rays"),
                    realParam("threshold", 0, 1e9, 0, "aamap sum that splits a block")};
        d.create = findStrategy("uniform")->create;
        registerStrategy(std::move(d));
    }
    ~SpacedStrategy() { unregisterStrategy("spaced"); }
};

ExperimentConfig parseRenders(const std::string& renders, const std::vector<std::string>& overrides = {}) {
    return parseConfig("scene: builtin:cornell\nrenders:\n" + renders, "exp.yaml", overrides);
}

TEST(Sweep, ListOfRppExpandsInOrderWithDefaultNames) {
    const ExperimentConfig c = parseRenders("  - {strategy: aamap, rpp: [1, 4, 16, 36]}\n");
    ASSERT_EQ(c.renders.size(), 4u);
    EXPECT_EQ(c.renders[0].name, "aamap1");
    EXPECT_EQ(c.renders[3].name, "aamap36");
    EXPECT_EQ(c.renders[3].rpp, 36);
    for (const RenderConfig& r : c.renders) EXPECT_EQ(r.series, "aamap");  // rpp is the table row, not the series
}

TEST(Sweep, CartesianProductOfRppAndParameters) {
    const SpacedStrategy spaced;
    const ExperimentConfig c =
        parseRenders("  - {strategy: spaced, rpp: [1, 4, 16], spacing: [8, 16], threshold: 0, series: 'Space {spacing}'}\n");
    ASSERT_EQ(c.renders.size(), 6u);
    std::set<std::string> names, keys;
    for (const RenderConfig& r : c.renders) {
        names.insert(r.name);
        keys.insert(renderKey(c, r));
    }
    EXPECT_EQ(names.size(), 6u);
    EXPECT_EQ(keys.size(), 6u);
    // rpp varies slowest, the last key fastest.
    EXPECT_EQ(c.renders[0].name, "spaced1_spacing8_threshold0");
    EXPECT_EQ(c.renders[1].name, "spaced1_spacing16_threshold0");
    EXPECT_EQ(c.renders[5].rpp, 16);
    EXPECT_EQ(c.renders[5].params.integer("spacing"), 16);
    EXPECT_EQ(c.renders[5].series, "Space 16");
    EXPECT_EQ(c.renders[2].series, "Space 8");
}

TEST(Sweep, NameTemplatesAndUnmentionedSweptKeys) {
    const SpacedStrategy spaced;
    const ExperimentConfig c = parseRenders("  - {name: 'sel{rpp}', strategy: spaced, rpp: [4, 16], spacing: [8, 16]}\n");
    ASSERT_EQ(c.renders.size(), 4u);
    EXPECT_EQ(c.renders[0].name, "sel4_spacing8");  // spacing appended: names must stay unique
    EXPECT_EQ(c.renders[0].params.real("threshold"), 0.0);  // default filled in
    const ExperimentConfig d = parseRenders("  - {name: 'u{n}x{n}', strategy: uniform, rpp: [4, 9]}\n");
    EXPECT_EQ(d.renders[1].name, "u3x3");
}

TEST(Sweep, FractionalValuesMakeSafeDefaultNames) {
    const SpacedStrategy spaced;
    const ExperimentConfig c = parseRenders("  - {strategy: spaced, rpp: 4, threshold: [0.5, 2.5e-7, 1.25e8, 1234567.5]}\n");
    ASSERT_EQ(c.renders.size(), 4u);
    EXPECT_EQ(c.renders[0].name, "spaced4_threshold0p5");
    EXPECT_EQ(c.renders[1].name, "spaced4_threshold2p5e-07");
    EXPECT_EQ(c.renders[2].name, "spaced4_threshold125000000");
    EXPECT_EQ(c.renders[3].name, "spaced4_threshold1p23457e06");
    EXPECT_EQ(c.renders[0].series, "spaced threshold=0.5");  // labels keep the number as written
}

TEST(Sweep, DefaultsAreFilledAndKeysIgnoreNames) {
    const SpacedStrategy spaced;
    const ExperimentConfig a = parseRenders("  - {name: x, strategy: spaced, rpp: 4}\n");
    const ExperimentConfig b = parseRenders("  - {name: y, series: z, strategy: spaced, rpp: 4, spacing: 8}\n");
    EXPECT_EQ(renderKey(a, a.renders[0]), renderKey(b, b.renders[0]));
    const ExperimentConfig c = parseRenders("  - {name: y, strategy: spaced, rpp: 4, spacing: 16}\n");
    EXPECT_NE(renderKey(a, a.renders[0]), renderKey(c, c.renders[0]));
    // Snapshot settings matter to aamap-driven strategies only.
    const std::string u = "  - {strategy: uniform, rpp: 4}\n";
    const ExperimentConfig u1 = parseRenders(u), u2 = parseRenders(u, {"snapshot.gain=3"});
    EXPECT_EQ(renderKey(u1, u1.renders[0]), renderKey(u2, u2.renders[0]));
    const ExperimentConfig s2 = parseRenders("  - {name: x, strategy: spaced, rpp: 4}\n", {"snapshot.gain=3"});
    EXPECT_NE(renderKey(a, a.renders[0]), renderKey(s2, s2.renders[0]));
}

TEST(Sweep, OverridesSetListsAndParameters) {
    const SpacedStrategy spaced;
    const ExperimentConfig c =
        parseRenders("  - {strategy: spaced, rpp: 4}\n", {"renders.0.rpp=[1,4]", "renders.0.spacing=[8,16,32]"});
    EXPECT_EQ(c.renders.size(), 6u);
}

TEST(Sweep, ShippedStrategiesAndChoices) {
    const ExperimentConfig c = parseRenders(
        "  - {strategy: aamap-subsample, rpp: [4, 16], spacing: [8, 16], series: 'Space {spacing}'}\n"
        "  - {strategy: supersample, rpp: 4, filter: [box, gaussian]}\n"
        "  - {strategy: aamap, rpp: 4, mapping: linear-rays}\n");
    ASSERT_EQ(c.renders.size(), 7u);
    EXPECT_EQ(c.renders[1].name, "aamap-subsample4_spacing16");
    EXPECT_EQ(c.renders[1].series, "Space 16");
    EXPECT_EQ(c.renders[5].name, "supersample4_filtergaussian");
    EXPECT_EQ(c.renders[5].params.choice("filter"), "gaussian");
    EXPECT_EQ(c.renders[4].params.integer("supersample"), 2);  // default
    EXPECT_EQ(c.renders[6].name, "aamap4_mappinglinear-rays");
    EXPECT_NE(renderKeyJson(c, c.renders[6]).find("\"mapping\":\"linear-rays\""), std::string::npos);
    EXPECT_TRUE(c.usesAamap());
    EXPECT_THROW(parseRenders("  - {strategy: supersample, rpp: 4, filter: lanczos}\n"), InputError);
}

TEST(Sweep, ErrorsPointAtTheValue) {
    const SpacedStrategy spaced;
    const auto error = [](const std::string& renders) {
        try {
            parseRenders(renders);
        } catch (const InputError& e) {
            return std::string(e.what());
        }
        return std::string("no error");
    };
    EXPECT_NE(error("  - {strategy: aamap, rpp: [1, 5]}\n").find("exp.yaml:3:"), std::string::npos);
    EXPECT_NE(error("  - {strategy: aamap, rpp: [1, 5]}\n").find("not a perfect square"), std::string::npos);
    EXPECT_NE(error("  - {strategy: aamap, rpp: []}\n").find("empty list"), std::string::npos);
    EXPECT_NE(error("  - {strategy: aamap, rpp: [4, 4]}\n").find("listed twice"), std::string::npos);
    EXPECT_NE(error("  - {strategy: uniform, rpp: 4, spacing: 8}\n").find("has no parameter 'spacing'"),
              std::string::npos);
    EXPECT_NE(error("  - {strategy: spaced, rpp: 4, spacing: 1}\n").find("out of range"), std::string::npos);
    EXPECT_NE(error("  - {strategy: spaced, rpp: 4, spacing: 8.5}\n").find("expected an integer"), std::string::npos);
    EXPECT_NE(error("  - {name: a, strategy: aamap, rpp: 4}\n  - {name: a, strategy: uniform, rpp: 4}\n").find("used twice"),
              std::string::npos);
    EXPECT_NE(error("  - {name: reference, strategy: uniform, rpp: 4}\n").find("reserved"), std::string::npos);
}

TEST(Sweep, ReferenceMetricsAndReportSections) {
    const ExperimentConfig c = parseRenders("  - {strategy: aamap, rpp: [4, 16]}\n");
    EXPECT_EQ(c.reference.type, ReferenceType::Uniform);
    EXPECT_EQ(c.reference.rpp, 16);  // the largest rpp of the renders
    EXPECT_TRUE(c.metrics.flip);
    EXPECT_FALSE(c.metrics.flipHdr);
    EXPECT_FLOAT_EQ(static_cast<float>(c.metrics.flipThreshold), 0.1f);
    EXPECT_TRUE(c.metrics.mapQuality);
    const ExperimentConfig d = parseRenders("  - {strategy: aamap, rpp: 4}\n",
                                     {"reference.rpp=64", "reference.mode=path", "metrics.flip_hdr=true",
                                      "shading.mode=cache", "report.plots=false"});
    EXPECT_EQ(d.reference.rpp, 64);
    EXPECT_EQ(d.reference.mode, ShadingMode::Path);
    EXPECT_TRUE(d.metrics.flipHdr);
    EXPECT_EQ(d.shading.mode, ShadingMode::Cache);
    EXPECT_FALSE(d.report.plots);
    EXPECT_THROW(parseRenders("  - {strategy: aamap, rpp: 4}\n", {"reference.rpp=5"}), InputError);
    EXPECT_THROW(parseRenders("  - {strategy: aamap, rpp: 4}\n", {"metrics.flip_threshold=0"}), InputError);
    EXPECT_THROW(parseRenders("  - {strategy: aamap, rpp: 4}\n", {"metrics.flip=maybe"}), InputError);
    EXPECT_THROW(parseRenders("  - {strategy: aamap, rpp: 4}\n", {"shading.mode=photon"}), InputError);
    EXPECT_THROW(parseRenders("  - {strategy: aamap, rpp: 4}\n", {"reference.type=file"}), InputError);  // needs a path
    const ExperimentConfig f = parseRenders("  - {strategy: aamap, rpp: 4}\n", {"reference.type=file", "reference.path=ref.exr"});
    EXPECT_EQ(f.reference.resolvedPath("/a/exp.yaml"), std::filesystem::path("/a/ref.exr"));
}

}  // namespace
}  // namespace aamap
