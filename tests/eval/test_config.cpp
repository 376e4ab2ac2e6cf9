// The experiment config: strict parsing with file:line:col errors, --set overrides, the canonical
// form and its hash.
#include <filesystem>
#include <fstream>
#include <string>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "core/error.h"
#include "eval/config.h"

namespace aamap {
namespace {

const std::string kMinimal = "scene: builtin:cornell\nrenders:\n  - {name: u, strategy: uniform, rpp: 4}\n";

// Parses `text` expecting an InputError, and returns it.
InputError parseError(const std::string& text, const std::vector<std::string>& overrides = {}) {
    try {
        parseConfig(text, "exp.yaml", overrides);
    } catch (const InputError& e) {
        return e;
    }
    ADD_FAILURE() << "no error for:\n" << text;
    return InputError("", "");
}

void expectAt(const InputError& e, int line, int column, const std::string& fragment) {
    EXPECT_EQ(e.file(), "exp.yaml") << e.what();
    EXPECT_EQ(e.line(), line) << e.what();
    EXPECT_EQ(e.column(), column) << e.what();
    EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
    EXPECT_EQ(std::string(e.what()).rfind(fmt::format("exp.yaml:{}:{}: ", line, column), 0), 0u) << e.what();
}

TEST(Config, MinimalGetsDefaults) {
    const ExperimentConfig c = parseConfig(kMinimal, "exp.yaml");
    EXPECT_EQ(c.scene, "builtin:cornell");
    EXPECT_FALSE(c.view.has_value());
    EXPECT_EQ(c.image.width, 512);
    EXPECT_EQ(c.image.height, 512);
    EXPECT_DOUBLE_EQ(c.snapshot.scale, 1.5);
    EXPECT_EQ(c.snapshot.areaLightSamples, 5);
    EXPECT_EQ(c.shading.areaLightSamples, 16);
    EXPECT_EQ(c.seed, 1u);
    ASSERT_EQ(c.renders.size(), 1u);
    EXPECT_EQ(c.renders[0].strata(), 2);
}

TEST(Config, FullExample) {
    const std::string text = R"(scene: builtin:cornell
view: views/front.vf
view_index: 1
lights:
  - {type: point, name: key, position: [0, 1.9, 0], intensity: [5, 5, 5]}
image: {width: 320, height: 200, exposure: 2.0}
seed: 7
threads: 3
snapshot: {scale: 2, area_light_samples: 3, blur_radius: 0, noise_floor: 0.05, gain: 4}
shading: {area_light_samples: 9}
renders:
  - {name: uniform, strategy: uniform, rpp: 36}
  - {strategy: aamap, rpp: 16}
)";
    const ExperimentConfig c = parseConfig(text, "/data/exp/exp.yaml");
    EXPECT_EQ(c.resolvedView(), std::filesystem::path("/data/exp/views/front.vf"));
    EXPECT_EQ(c.viewIndex, 1);
    ASSERT_EQ(c.lights.size(), 1u);
    EXPECT_EQ(c.lights[0].name, "key");
    EXPECT_DOUBLE_EQ(c.lights[0].position[1], 1.9);
    EXPECT_EQ(c.image.width, 320);
    EXPECT_DOUBLE_EQ(c.image.exposure, 2.0);
    EXPECT_EQ(c.seed, 7u);
    EXPECT_EQ(c.threads, 3);
    EXPECT_EQ(c.snapshot.filter.blurRadius, 0);
    EXPECT_DOUBLE_EQ(c.snapshot.filter.gain, 4.0);
    EXPECT_EQ(c.shading.areaLightSamples, 9);
    EXPECT_EQ(c.renders[1].name, "aamap16");  // default name: strategy + rpp
    EXPECT_EQ(c.viewIndexLocation.line, 3);
}

TEST(Config, ScenePathsAreRelativeToTheConfig) {
    EXPECT_EQ(parseConfig("scene: ../scenes/box.obj\nrenders: [{strategy: uniform, rpp: 1}]", "/a/b/exp.yaml")
                  .resolvedScene(),
              "/a/scenes/box.obj");
    EXPECT_EQ(parseConfig(kMinimal, "/a/b/exp.yaml").resolvedScene(), "builtin:cornell");
}

TEST(ConfigErrors, UnknownKeyNamesPositionAndSuggestion) {
    const InputError e = parseError(kMinimal + "imgae: {width: 4}\n");
    expectAt(e, 4, 1, "unknown key 'imgae'");
    EXPECT_NE(std::string(e.what()).find("did you mean 'image'"), std::string::npos) << e.what();
    expectAt(parseError(kMinimal + "image:\n  width: 4\n  heigth: 4\n"), 6, 3, "unknown key 'heigth' in 'image'");
    expectAt(parseError("scene: builtin:cornell\nrenders:\n  - {strategy: uniform, rpp: 4, spp: 2}\n"), 3, 33,
             "unknown key 'spp'");
}

TEST(ConfigErrors, WrongType) {
    expectAt(parseError(kMinimal + "image: {width: abc}\n"), 4, 16, "image.width: expected an integer");
    expectAt(parseError(kMinimal + "image: {width: 1.5}\n"), 4, 16, "expected an integer");
    expectAt(parseError(kMinimal + "image: [1, 2]\n"), 4, 8, "expected a mapping");
    // A list at a single-valued setting is a sweep (test_config_sweeps.cpp), which a single config refuses.
    expectAt(parseError(kMinimal + "snapshot: {gain: [1]}\n"), 4, 19, "snapshot.gain: a list here sweeps the setting");
    expectAt(parseError(kMinimal + "seed: -1\n"), 4, 7, "non-negative integer");
    expectAt(parseError(kMinimal + "lights:\n  - {position: [0, 1], intensity: [1, 1, 1]}\n"), 5, 16,
             "list of 3 numbers");
    expectAt(parseError("scene: builtin:cornell\nrenders: {a: 1}\n"), 2, 10, "non-empty list");
}

TEST(ConfigErrors, OutOfRange) {
    expectAt(parseError(kMinimal + "image: {width: 0}\n"), 4, 16, "0 is out of range [1, 16384]");
    expectAt(parseError(kMinimal + "image: {exposure: 0}\n"), 4, 19, "out of range (0");
    expectAt(parseError(kMinimal + "snapshot: {noise_floor: 1.5}\n"), 4, 25, "out of range");
    expectAt(parseError(kMinimal + "snapshot: {shadow_texel_pixels: 65}\n"), 4, 33, "65 is out of range [0, 64]");
    expectAt(parseError(kMinimal + "snapshot: {shadow_texel_pixels: -1}\n"), 4, 33, "out of range");
    expectAt(parseError(kMinimal + "snapshot: {scale: .nan}\n"), 4, 19, "finite");
    expectAt(parseError("scene: builtin:cornell\nrenders: [{strategy: uniform, rpp: 4096}]\n"), 2, 36, "out of range");
    expectAt(parseError(kMinimal + "shading: {light_selection: random}\n"), 4, 28,
             "shading.light_selection: unknown value 'random' (supported: contribution, power)");
    expectAt(parseError(kMinimal + "image: {filter: lanczos}\n"), 4, 17,
             "image.filter: unknown value 'lanczos' (supported: box, tent, gaussian)");
    expectAt(parseError(kMinimal + "image: {filter: tent, filter_radius: 9}\n"), 4, 38, "out of range [0, 8]");
    expectAt(parseError(kMinimal + "image: {filter: gaussian, filter_stddev: 0}\n"), 4, 42, "out of range (0");
    expectAt(parseError(kMinimal + "image: {filter: tent, filter_stddev: 0.3}\n"), 4, 38,
             "image.filter_stddev: only the gaussian filter has a stddev (image.filter is 'tent')");
    expectAt(parseError(kMinimal + "image: {filter: tent, filter_mode: splat}\n"), 4, 36,
             "image.filter_mode: unknown value 'splat' (supported: convolution, importance)");
}

TEST(ConfigErrors, RppMustBeAPerfectSquare) {
    expectAt(parseError("scene: builtin:cornell\nrenders:\n  - {strategy: aamap, rpp: 20}\n"), 3, 28,
             "20 is not a perfect square");
}

TEST(ConfigErrors, RenderNames) {
    expectAt(parseError("scene: s.obj\nrenders:\n  - {name: a, strategy: uniform, rpp: 1}\n"
                        "  - {name: a, strategy: aamap, rpp: 1}\n"),
             4, 5, "used twice");
    expectAt(parseError("scene: s.obj\nrenders:\n  - {name: ../x, strategy: uniform, rpp: 1}\n"), 3, 12,
             "not a safe file name");
    expectAt(parseError("scene: s.obj\nrenders:\n  - {name: aamap, strategy: uniform, rpp: 1}\n"), 3, 12,
             "reserved");
    expectAt(parseError("scene: s.obj\nrenders:\n  - {strategy: adaptive, rpp: 1}\n"), 3, 16, "unknown strategy");
    expectAt(parseError("scene: s.obj\nrenders:\n  - {strategy: unifrom, rpp: 1}\n"), 3, 16,
             "unknown strategy 'unifrom'; did you mean 'uniform'?");
}

TEST(ConfigErrors, MissingAndMalformed) {
    expectAt(parseError("scene: builtin:cornell\n"), 1, 1, "missing required key 'renders'");
    expectAt(parseError("scene: builtin:cornell\nrenders:\n  - {strategy: uniform}\n"), 3, 5, "'renders.0.rpp'");
    const InputError syntax = parseError("scene: builtin:cornell\nrenders: [{strategy: uniform, rpp: 4}\n");
    EXPECT_EQ(syntax.line(), 3) << syntax.what();
    EXPECT_NE(std::string(syntax.what()).find("invalid YAML"), std::string::npos);
    expectAt(parseError(""), 1, 1, "empty");
    expectAt(parseError("- a\n- b\n"), 1, 1, "expected a mapping");
    expectAt(parseError(kMinimal + "seed: 1\nseed: 2\n"), 5, 1, "duplicate key 'seed'");
}

TEST(ConfigErrors, MissingFileIsNamed) {
    try {
        loadConfig("/nonexistent/dir/exp.yaml");
        FAIL();
    } catch (const InputError& e) {
        EXPECT_EQ(e.file(), "/nonexistent/dir/exp.yaml");
        EXPECT_NE(std::string(e.what()).find("/nonexistent/dir/exp.yaml: cannot read"), std::string::npos) << e.what();
    }
}

TEST(ConfigOverrides, SetScalarsListsAndMissingSections) {
    const ExperimentConfig c = parseConfig(
        kMinimal + "image: {width: 512}\n", "exp.yaml",
        {"image.width=64", "image.height=32", "renders.0.rpp=16", "shading.area_light_samples=4", "view=a.vf",
         "seed=99", "renders.0.strategy=aamap", "snapshot.gain=2.5"});
    EXPECT_EQ(c.image.width, 64);
    EXPECT_EQ(c.image.height, 32);
    EXPECT_EQ(c.renders[0].rpp, 16);
    EXPECT_EQ(c.renders[0].strategy, "aamap");
    EXPECT_EQ(c.shading.areaLightSamples, 4);
    EXPECT_EQ(c.view, "a.vf");
    EXPECT_EQ(c.seed, 99u);
    EXPECT_DOUBLE_EQ(c.snapshot.filter.gain, 2.5);
    const ExperimentConfig lights = parseConfig(
        kMinimal + "lights: [{position: [0, 0, 0], intensity: [1, 1, 1]}]\n", "exp.yaml",
        {"lights.0.position=[1, 2, 3]", "lights.0.name=fill"});
    EXPECT_DOUBLE_EQ(lights.lights[0].position[2], 3.0);
    EXPECT_EQ(lights.lights[0].name, "fill");
}

TEST(ConfigOverrides, ErrorsNameTheOption) {
    auto expectOption = [](const InputError& e, const std::string& option, const std::string& fragment) {
        EXPECT_EQ(e.file(), "--set " + option) << e.what();
        EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
    };
    expectOption(parseError(kMinimal, {"image.widht=4"}), "image.widht=4", "unknown key 'image.widht'");
    expectOption(parseError(kMinimal, {"image.widht=4"}), "image.widht=4", "did you mean 'image.width'");
    expectOption(parseError(kMinimal, {"image=4"}), "image=4", "is a section");
    expectOption(parseError(kMinimal, {"image.width"}), "image.width", "key.path=value");
    expectOption(parseError(kMinimal, {"image.width=abc"}), "image.width=abc", "expected an integer");
    expectOption(parseError(kMinimal, {"renders.0.rpp=20"}), "renders.0.rpp=20", "not a perfect square");
    expectOption(parseError(kMinimal, {"renders.3.rpp=4"}), "renders.3.rpp=4", "1 item");
    expectOption(parseError(kMinimal, {"image.width=[1"}), "image.width=[1", "invalid YAML");
}

TEST(ConfigHash, StableUnderFormattingAndDefaults) {
    const std::string a = kMinimal;
    const std::string b = "# comment\nrenders: [ {rpp: 4, strategy: uniform, name: u} ]\nscene:   builtin:cornell\n"
                          "image: {width: 512, height: 512, exposure: 1.0}\nsnapshot: {scale: 1.5}\n";
    const ExperimentConfig ca = parseConfig(a, "x.yaml"), cb = parseConfig(b, "other/y.yaml");
    EXPECT_EQ(ca.canonicalJson(), cb.canonicalJson());
    EXPECT_EQ(ca.hash(), cb.hash());
    EXPECT_EQ(ca.hash().size(), 16u);
    // The thread count never changes an image, so it does not change the hash either.
    EXPECT_EQ(ca.hash(), parseConfig(a, "x.yaml", {"threads=5"}).hash());
    EXPECT_NE(ca.hash(), parseConfig(a, "x.yaml", {"seed=2"}).hash());
    EXPECT_NE(ca.hash(), parseConfig(a, "x.yaml", {"snapshot.noise_floor=0.03"}).hash());
    // Golden value: changing it means old results.json files no longer match their configs. A
    // config at its defaults names no schema key, so a key added to a schema leaves it as it is.
    EXPECT_EQ(ca.hashJson(),
              R"({"scene":"builtin:cornell","view":null,"lights":[],"seed":1,)"
              R"("renders":[{"name":"u","series":"uniform","strategy":"uniform","rpp":4,"params":{}}],)"
              R"("reference":{"type":"uniform","rpp":4,"mode":"","path":""}})");
    EXPECT_EQ(parseConfig(a, "x.yaml", {"snapshot.gain=2", "shading.cache.bounces=3"}).hashJson(),
              R"({"scene":"builtin:cornell","view":null,"lights":[],"seed":1,"snapshot":{"gain":2.0},)"
              R"("shading.cache":{"bounces":3},)"
              R"("renders":[{"name":"u","series":"uniform","strategy":"uniform","rpp":4,"params":{}}],)"
              R"("reference":{"type":"uniform","rpp":4,"mode":"","path":""}})");
}

TEST(ConfigFile, TheShippedDefaultParses) {
    const std::filesystem::path file = std::filesystem::path(AAMAP_SOURCE_DIR) / "configs" / "cornell.yaml";
    const ExperimentConfig c = loadConfig(file, {"image.width=64", "image.height=64"});
    EXPECT_EQ(c.scene, "builtin:cornell");
    EXPECT_EQ(c.image.width, 64);
    // standard, non-adaptive, Space 8 and Space 16 at 1, 4, 16, 36 rays per pixel, plus rpict
    // (at most one ray per pixel by definition, so once)
    ASSERT_EQ(c.renders.size(), 17u);
    EXPECT_EQ(c.renders.back().strategy, "rpict");
    EXPECT_EQ(c.renders.back().rpp, 1);
    EXPECT_EQ(c.renders[3].rpp, 36);
    EXPECT_EQ(c.renders[4].strategy, "aamap");
    EXPECT_EQ(c.renders[9].series, "Space 16");
    EXPECT_EQ(c.reference.rpp, 36);
}

// Shipped configs may sweep settings (`aamap run` expands them): every variant must parse.
TEST(ConfigFile, EveryShippedConfigParses) {
    int count = 0;
    for (const auto& e : std::filesystem::directory_iterator(std::filesystem::path(AAMAP_SOURCE_DIR) / "configs")) {
        if (e.path().extension() != ".yaml") continue;
        SCOPED_TRACE(e.path().string());
        const Experiment experiment = loadExperiment(e.path());
        ASSERT_FALSE(experiment.variants.empty());
        for (const ExperimentConfig& c : experiment.variants) {
            EXPECT_FALSE(c.renders.empty());
            if (!c.scene.starts_with("builtin:")) {  // paths relative to the config file
                EXPECT_TRUE(c.resolvedScene().find("shared/scenes") != std::string::npos) << c.resolvedScene();
            }
        }
        ++count;
    }
    EXPECT_GE(count, 4);
}

}  // namespace
}  // namespace aamap
