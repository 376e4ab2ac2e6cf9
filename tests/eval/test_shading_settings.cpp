// The shading section reaches the tracer: every key of shading.cache arrives in ShadingSettings,
// enters the render keys when it differs from its default, and sweeps like any other setting.
#include <string>

#include <gtest/gtest.h>

#include "core/error.h"
#include "eval/config.h"
#include "eval/strategy_settings.h"

namespace aamap {
namespace {

const std::string kBase = "scene: builtin:cornell\nshading: {mode: cache}\nrenders: [{name: u, strategy: uniform, rpp: 1}]\n";

TEST(ShadingSettings, CacheKeysReachTheTracer) {
    const ExperimentConfig c =
        parseConfig(kBase, "exp.yaml",
                    {"shading.cache.bounces=3", "shading.cache.divisions=1024", "shading.cache.supersamples=7",
                     "shading.cache.accuracy=0.05", "shading.cache.resolution=32", "shading.cache.grid_step=2",
                     "seed=9"});
    const ShadingSettings s = toShadingSettings(c, c.renders[0]);
    EXPECT_EQ(s.mode, ShadingMode::Cache);
    EXPECT_EQ(s.cache.bounces, 3);
    EXPECT_EQ(s.cache.divisions, 1024);
    EXPECT_EQ(s.cache.supersamples, 7);
    EXPECT_FLOAT_EQ(s.cache.accuracy, 0.05f);
    EXPECT_EQ(s.cache.resolution, 32);
    EXPECT_EQ(s.cache.gridStep, 2);
    EXPECT_EQ(s.cache.seed, 9u) << "the cache's random numbers follow the experiment's seed";
    // A config that sets nothing hands the tracer its own defaults (the schema reads them from
    // the struct), with the experiment's seed.
    const ExperimentConfig d = parseConfig(kBase, "exp.yaml");
    ShadingSettings expected;
    expected.mode = ShadingMode::Cache;
    expected.cache.seed = d.seed;
    EXPECT_EQ(toShadingSettings(d, d.renders[0]), expected);
}

TEST(ShadingSettings, CacheKeysChangeRenderKeysOnlyWhenNotDefault) {
    const ExperimentConfig d = parseConfig(kBase, "exp.yaml");
    const std::string base = renderKey(d, d.renders[0]);
    EXPECT_EQ(base, renderKey(parseConfig(kBase, "exp.yaml", {"shading.cache.bounces=1"}), d.renders[0]))
        << "writing the default changes nothing";
    for (const char* set : {"shading.cache.bounces=2", "shading.cache.divisions=256", "shading.cache.supersamples=0",
                            "shading.cache.accuracy=0.1", "shading.cache.resolution=0", "shading.cache.grid_step=8"}) {
        const ExperimentConfig c = parseConfig(kBase, "exp.yaml", {set});
        EXPECT_NE(renderKey(c, c.renders[0]), base) << set;
    }
}

// Only cache mode reads the cache: the renders of other modes (a path-traced reference, say)
// keep their keys, so tightening the cache re-traces nothing else.
TEST(ShadingSettings, CacheKeysLeaveOtherModesAlone) {
    for (const char* mode : {"direct", "path"}) {
        const std::string mode_ = std::string("shading.mode=") + mode;
        const ExperimentConfig d = parseConfig(kBase, "exp.yaml", {mode_});
        const ExperimentConfig c = parseConfig(kBase, "exp.yaml", {mode_, "shading.cache.bounces=3"});
        EXPECT_EQ(renderKey(d, d.renders[0]), renderKey(c, c.renders[0])) << mode;
        EXPECT_NE(d.hash(), c.hash()) << "the experiment itself still differs";
    }
}

TEST(ShadingSettings, CacheKeysAreChecked) {
    EXPECT_THROW(parseConfig(kBase, "exp.yaml", {"shading.cache.bounces=-1"}), InputError);
    EXPECT_THROW(parseConfig(kBase, "exp.yaml", {"shading.cache.accuracy=0"}), InputError);
    try {
        parseConfig("scene: builtin:cornell\nshading: {cache: {bounce: 2}}\nrenders: [{strategy: uniform, rpp: 1}]\n",
                    "exp.yaml");
        FAIL();
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("did you mean 'bounces'"), std::string::npos) << e.what();
    }
}

TEST(ShadingSettings, CacheBouncesSweep) {
    const Experiment e = parseExperiment("scene: builtin:cornell\nshading: {mode: cache, cache: {bounces: [1, 2]}}\n"
                                         "renders: [{name: u, strategy: uniform, rpp: 1}]\n",
                                         "exp.yaml");
    EXPECT_EQ(e.variants.size(), 2u);
}

}  // namespace
}  // namespace aamap
