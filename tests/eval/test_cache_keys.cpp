// The render cache keys are complete: every input that changes a traced image changes the key of
// that render (else a rerun would silently reuse an image of other settings). One test per input,
// generated from the table below; inputs that live in files (a light file) are changed in place,
// under the same path; a file of the same contents under another name is another input too
// (the key cannot know the two are the same scene).
#include <fstream>
#include <functional>
#include <ostream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "core/image_io.h"
#include "eval/config.h"
#include "eval/render_cache.h"
#include "tests/common/temp_dir.h"

namespace aamap {
namespace {

struct KeyInput {
    std::string name;                     // the test's name
    const char* config;                   // the config before the change
    std::vector<std::string> overrides;   // --set options that change the input, or
    std::function<void(const test::TempDir&)> editFiles;  // an edit of the files the config names
};

const char* kLightFileConfig = R"(scene: builtin:cornell
light_file: lights.yaml
lights:
  - {type: quad, position: [0, 1.9, 0], normal: [0, -1, 0], size: [0.4, 0.4], radiance: [5, 5, 5]}
image: {width: 64, height: 48, exposure: 1.0}
renders:
  - {strategy: uniform, rpp: 4}
  - {strategy: aamap, rpp: 4}
  - {strategy: variance, rpp: 16}
)";

// Scene and view from files, for the inputs that are file contents.
const char* kFileConfig = R"(scene: room.obj
view: a.vf
renders:
  - {strategy: uniform, rpp: 4}
  - {strategy: aamap, rpp: 4}
)";

// A camera written in the config.
const char* kCameraConfig = R"(scene: builtin:cornell
camera: {position: [0, 1, 3.9], look_at: [0, 1, 0]}
renders:
  - {strategy: uniform, rpp: 4}
  - {strategy: aamap, rpp: 4}
)";

// A sky from an environment map.
const char* kSkyConfig = R"(scene: builtin:cornell
lights:
  - {type: environment, map: sky.exr}
renders:
  - {strategy: uniform, rpp: 4}
  - {strategy: aamap, rpp: 4}
)";

ImageRGB skyImage(float brightness) {
    ImageRGB sky(8, 4);
    for (int y = 0; y < 4; ++y)
        for (int x = 0; x < 8; ++x) sky.at(x, y) = glm::vec3(brightness * (1.0f + static_cast<float>(x + y)));
    return sky;
}

const char* kRoom = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";

const char* kLights = "- {type: point, position: [0, 1.5, 0], intensity: [2, 2, 2]}\n";

// kLightFileConfig with a Gaussian pixel filter (the one filter with a stddev).
const std::string& gaussianConfig() {
    static const std::string config = [] {
        std::string c = kLightFileConfig;
        const std::string image = "exposure: 1.0}";
        c.replace(c.find(image), image.size(), "exposure: 1.0, filter: gaussian}");
        return c;
    }();
    return config;
}

std::vector<KeyInput> inputs() {
    std::vector<KeyInput> v;
    const auto set = [&](std::string name, std::string override) {
        v.push_back({std::move(name), kLightFileConfig, {std::move(override)}, {}});
    };
    set("Seed", "seed=2");
    set("ShadingAreaLightSamples", "shading.area_light_samples=4");
    set("ShadingMode", "shading.mode=path");
    set("ShadingMaxDepth", "shading.max_depth=2");
    set("ShadingRussianRoulette", "shading.russian_roulette=false");
    set("ShadingRouletteDepth", "shading.roulette_depth=3");
    set("ShadingHideEmitters", "shading.hide_emitters=true");
    set("ShadingMaxSpecularDepth", "shading.max_specular_depth=1");
    set("ShadingLightSelection", "shading.light_selection=power");
    set("ShadingLightSampling", "shading.light_sampling=area");
    set("ImageWidth", "image.width=65");
    set("ImageHeight", "image.height=47");
    set("ImageExposure", "image.exposure=1.5");
    set("ImageFilter", "image.filter=tent");
    set("ImageFilterRadius", "image.filter_radius=1");
    v.push_back({"ImageFilterStddev", gaussianConfig().c_str(), {"image.filter_stddev=0.3"}, {}});
    v.push_back({"ImageFilterMode", gaussianConfig().c_str(), {"image.filter_mode=importance"}, {}});
    set("LightPosition", "lights.0.position=[0, 1.8, 0]");
    set("LightRadiance", "lights.0.radiance=[5, 5, 4]");
    set("LightSize", "lights.0.size=[0.4, 0.3]");
    set("LightNormal", "lights.0.normal=[0, -1, 0.1]");
    set("Scene", "scene=builtin:spheres-plane");
    v.push_back({"CameraPosition", kCameraConfig, {"camera.position=[0, 1.1, 3.9]"}, {}});
    v.push_back({"CameraLookAt", kCameraConfig, {"camera.look_at=[0.1, 1, 0]"}, {}});
    v.push_back({"CameraUp", kCameraConfig, {"camera.up=[0.1, 1, 0]"}, {}});
    v.push_back({"CameraFov", kCameraConfig, {"camera.fov=44"}, {}});
    v.push_back({"ViewFileName", kFileConfig, {"view=b.vf"}, {}});
    v.push_back({"ViewIndex", kFileConfig, {"view_index=1"}, {}});
    v.push_back({"ViewFileContent", kFileConfig, {}, [](const test::TempDir& d) {
                     d.write("a.vf", "rview -vtv -vp 0 1 3.5 -vd 0 0 -1 -vu 0 1 0 -vh 41 -vv 40\n");
                 }});
    v.push_back({"SceneFileName", kFileConfig, {"scene=other.obj"}, {}});
    v.push_back({"SceneFileContent", kFileConfig, {}, [](const test::TempDir& d) {
                     d.write("room.obj", "v 0 0 0\nv 1 0 0\nv 0 1.5 0\nf 1 2 3\n");
                 }});
    v.push_back({"LightFileContent", kLightFileConfig, {}, [](const test::TempDir& d) {
                     d.write("lights.yaml", "- {type: point, position: [0, 1.5, 0], intensity: [2, 2, 2.5]}\n");
                 }});
    v.push_back({"LightFileLightAdded", kLightFileConfig, {}, [](const test::TempDir& d) {
                     d.write("lights.yaml", std::string(kLights) + "- {type: point, position: [1, 1, 0], intensity: [1, 1, 1]}\n");
                 }});
    v.push_back({"ViewFile", kLightFileConfig, {"view=a.vf"}, {}});
    v.push_back({"EnvironmentMapName", kSkyConfig, {"lights.0.map=other_sky.exr"}, {}});
    v.push_back({"EnvironmentMapContent", kSkyConfig, {}, [](const test::TempDir& d) {
                     writeExr(d.path() / "sky.exr", skyImage(0.6f));
                 }});
    return v;
}

void PrintTo(const KeyInput& input, std::ostream* os) { *os << input.name; }

class CacheKeyInputs : public ::testing::TestWithParam<KeyInput> {
protected:
    void SetUp() override {
        dir_.write("lights.yaml", kLights);
        dir_.write("a.vf", "rview -vtv -vp 0 1 3.5 -vd 0 0 -1 -vu 0 1 0 -vh 40 -vv 40\n"
                           "rview -vtv -vp 0 1 3.6 -vd 0 0 -1 -vu 0 1 0 -vh 40 -vv 40\n");
        dir_.write("b.vf", "rview -vtv -vp 0 1 3.5 -vd 0 0 -1 -vu 0 1 0 -vh 40 -vv 40\n");
        dir_.write("room.obj", kRoom);
        dir_.write("other.obj", kRoom);
        writeExr(dir_.path() / "sky.exr", skyImage(0.5f));
        writeExr(dir_.path() / "other_sky.exr", skyImage(0.5f));
    }
    ExperimentConfig parse(const std::vector<std::string>& overrides = {}) const {
        return parseConfig(GetParam().config, dir_.path() / "exp.yaml", overrides);
    }
    test::TempDir dir_;
};

TEST_P(CacheKeyInputs, ChangesTheKeyOfEveryRenderItAffects) {
    const KeyInput& input = GetParam();
    // The keys of a first run, then the edit, then the keys a rerun computes.
    const ExperimentConfig before = parse();
    std::vector<std::string> keysBefore;
    for (const RenderConfig& r : before.renders) keysBefore.push_back(renderKey(before, r));
    const std::string snapshotBefore = snapshotKey(before);
    if (input.editFiles) input.editFiles(dir_);
    const ExperimentConfig after = parse(input.overrides);
    ASSERT_EQ(before.renders.size(), after.renders.size());
    for (std::size_t r = 0; r < before.renders.size(); ++r)
        EXPECT_NE(keysBefore[r], renderKey(after, after.renders[r]))
            << input.name << " does not reach the key of render " << before.renders[r].name;
    // Every input here changes what the Snapshot sees too, except the seed, shading and the pixel
    // filter (the Snapshot has its own area-light samples, no random numbers and no filter).
    const bool snapshotInput = !input.name.starts_with("Seed") && !input.name.starts_with("Shading") &&
                               !input.name.starts_with("ImageFilter");
    EXPECT_EQ(snapshotBefore != snapshotKey(after), snapshotInput) << input.name;
}

INSTANTIATE_TEST_SUITE_P(CacheKeys, CacheKeyInputs, ::testing::ValuesIn(inputs()),
                         [](const ::testing::TestParamInfo<KeyInput>& info) { return info.param.name; });

// And what never changes an image never changes a key: names, series, threads, metrics, report.
TEST(CacheKeys, LabelsThreadsAndMetricsLeaveEveryKeyAlone) {
    test::TempDir dir;
    dir.write("lights.yaml", kLights);
    const auto parse = [&](const std::vector<std::string>& o) { return parseConfig(kLightFileConfig, dir.path() / "exp.yaml", o); };
    const ExperimentConfig before = parse({});
    for (const char* o : {"renders.0.name=first", "renders.1.series=Map", "threads=2", "metrics.flip=false",
                                 "metrics.flip_threshold=0.2", "metrics.ppd=30", "metrics.mse_threshold=0.001",
                                 "report.plots=false", "timing.repeats=3", "reference.rpp=64"}) {
        const ExperimentConfig after = parse({o});
        for (std::size_t r = 0; r < before.renders.size(); ++r)
            EXPECT_EQ(renderKey(before, before.renders[r]), renderKey(after, after.renders[r])) << o;
        EXPECT_EQ(snapshotKey(before), snapshotKey(after)) << o;
    }
}

// The files a config names enter the keys by where they are, not by how the config was reached:
// an absolute path, a relative one from another working directory, or one through "..", give the
// same keys, so a run resumed from elsewhere finds its cache.
TEST(CacheKeys, TheConfigsPathAndTheWorkingDirectoryLeaveEveryKeyAlone) {
    test::TempDir dir;
    dir.write("scenes/room.obj", kRoom);
    dir.write("scenes/a.vf", "rview -vtv -vp 0 1 3.5 -vd 0 0 -1 -vu 0 1 0 -vh 40 -vv 40\n");
    writeExr(dir.path() / "scenes" / "sky.exr", skyImage(0.5f));
    const std::string config = "scene: ../scenes/room.obj\nview: ../scenes/a.vf\n"
                               "lights:\n  - {type: environment, map: ../scenes/sky.exr}\n"
                               "renders:\n  - {strategy: uniform, rpp: 4}\n  - {strategy: aamap, rpp: 4}\n";
    std::filesystem::create_directories(dir.path() / "configs" / "more");
    const auto keys = [&](const std::filesystem::path& file) {
        const ExperimentConfig c = parseConfig(config, file, {});
        std::vector<std::string> k{snapshotKey(c)};
        for (const RenderConfig& r : c.renders) k.push_back(renderKey(c, r));
        return k;
    };
    const std::vector<std::string> absolute = keys(dir.path() / "configs" / "exp.yaml");
    EXPECT_EQ(absolute, keys(dir.path() / "configs" / "more" / ".." / "exp.yaml"));
    const std::filesystem::path cwd = std::filesystem::current_path();
    std::filesystem::current_path(dir.path());
    const std::vector<std::string> relative = keys("configs/exp.yaml");
    std::filesystem::current_path(dir.path() / "configs");
    const std::vector<std::string> here = keys("exp.yaml");
    std::filesystem::current_path(cwd);
    EXPECT_EQ(absolute, relative);
    EXPECT_EQ(absolute, here);
}

// A folder under a key's name is an entry only once its record.json is there (the record is
// written last): a folder without one, left by hand or by a crash, is traced again, not reused.
TEST(RenderCache, AFolderWithoutItsRecordIsNoEntry) {
    test::TempDir dir;
    RenderCache cache(dir.path() / "cache");
    std::filesystem::create_directories(cache.entry("0123456789abcdef"));
    EXPECT_FALSE(cache.has("0123456789abcdef"));
    cache.commit("0123456789abcdef", [](const std::filesystem::path& tmp) {
        std::ofstream(tmp / "record.json") << "{}\n";
    });
    EXPECT_TRUE(cache.has("0123456789abcdef"));
}

}  // namespace
}  // namespace aamap
