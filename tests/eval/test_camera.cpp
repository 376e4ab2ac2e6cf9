// The config's camera key and the views prepareScene picks: camera, view file, the scene's own
// views, or a framed view; and the image size a Mitsuba film gives.
#include <algorithm>
#include <filesystem>
#include <fstream>
#include <string>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>
#include <unistd.h>

#include "core/error.h"
#include "eval/config.h"
#include "eval/experiment.h"

namespace aamap {
namespace {
namespace fs = std::filesystem;

const std::string kRenders = "renders: [{name: u, strategy: uniform, rpp: 1}]\n";

InputError configError(const std::string& text) {
    try {
        parseConfig(text, "exp.yaml");
    } catch (const InputError& e) {
        return e;
    }
    ADD_FAILURE() << "no error for:\n" << text;
    return InputError("", "");
}

TEST(CameraConfig, ParsesWithDefaults) {
    const ExperimentConfig c = parseConfig("scene: builtin:cornell\ncamera: {position: [0, 1, 5], look_at: [0, 1, 0]}\n" + kRenders,
                                           "exp.yaml");
    ASSERT_TRUE(c.camera.has_value());
    EXPECT_EQ(c.camera->position, (std::array<double, 3>{0, 1, 5}));
    EXPECT_EQ(c.camera->up, (std::array<double, 3>{0, 1, 0}));
    EXPECT_EQ(c.camera->fov, 45.0);
}

TEST(CameraConfig, ErrorsNameTheLine) {
    const InputError both = configError("scene: builtin:cornell\nview: a.vf\ncamera: {position: [0, 0, 1], look_at: [0, 0, 0]}\n" + kRenders);
    EXPECT_EQ(both.line(), 3) << both.what();
    EXPECT_NE(std::string(both.what()).find("not both"), std::string::npos);
    const InputError missing = configError("scene: builtin:cornell\ncamera: {position: [0, 0, 1]}\n" + kRenders);
    EXPECT_NE(std::string(missing.what()).find("look_at"), std::string::npos) << missing.what();
    const InputError parallel = configError("scene: builtin:cornell\ncamera: {position: [0, 5, 0], look_at: [0, 0, 0]}\n" + kRenders);
    EXPECT_NE(std::string(parallel.what()).find("camera.up"), std::string::npos) << parallel.what();
    const InputError fov = configError("scene: builtin:cornell\ncamera: {position: [0, 0, 1], look_at: [0, 0, 0], fov: 0}\n" + kRenders);
    EXPECT_NE(std::string(fov.what()).find("camera.fov"), std::string::npos) << fov.what();
}

TEST(CameraConfig, EntersTheCacheKeys) {
    const std::string base = "scene: builtin:cornell\n" + kRenders;
    const ExperimentConfig none = parseConfig(base, "exp.yaml");
    const ExperimentConfig a = parseConfig(base + "camera: {position: [0, 1, 5], look_at: [0, 1, 0]}\n", "exp.yaml");
    const ExperimentConfig b = parseConfig(base + "camera: {position: [0, 1, 6], look_at: [0, 1, 0]}\n", "exp.yaml");
    EXPECT_NE(renderKey(none, none.renders[0]), renderKey(a, a.renders[0]));
    EXPECT_NE(renderKey(a, a.renders[0]), renderKey(b, b.renders[0]));
    EXPECT_NE(snapshotKey(a), snapshotKey(b));
    EXPECT_NE(a.hash(), b.hash());
}

TEST(CameraConfig, OptionTextRoundTripsThroughOverrides) {
    const CameraConfig c = parseCameraOption("{position: [1, 2, 3], look_at: [0, 0, 0], fov: 30.5}");
    const ExperimentConfig e = parseConfig("scene: builtin:cornell\n" + kRenders, "exp.yaml", cameraOverrides(c));
    ASSERT_TRUE(e.camera.has_value());
    EXPECT_EQ(e.camera->position, c.position);
    EXPECT_EQ(e.camera->fov, 30.5);
    EXPECT_THROW(parseCameraOption("{position: [1, 2]}"), InputError);
}

TEST(PrepareScene, CameraWinsOverTheScenesView) {
    ExperimentConfig c = parseConfig("scene: builtin:cornell\nimage: {width: 200, height: 100}\n"
                                     "camera: {position: [0.2, 0.3, -1], look_at: [0.2, 0.3, 0], fov: 60}\n" + kRenders,
                                     "exp.yaml");
    const PreparedScene p = prepareScene(c);
    EXPECT_EQ(p.viewLabel, "camera");
    EXPECT_NEAR(p.view.position.z, -1.0f, 1e-6f);
    EXPECT_NEAR(p.view.horizontalFovDeg, 60.0f, 1e-4f);
    EXPECT_EQ(p.width, 200);
    EXPECT_EQ(p.height, 100);
}

class Files : public ::testing::Test {
protected:
    fs::path dir = fs::temp_directory_path() / ("aamap_camera_" + std::to_string(::getpid()));
    void SetUp() override { fs::create_directories(dir); }
    void TearDown() override {
        std::error_code ec;
        fs::remove_all(dir, ec);
    }
    fs::path write(const std::string& name, const std::string& text) const {
        std::ofstream(dir / name, std::ios::binary) << text;
        return dir / name;
    }
};

TEST_F(Files, CameralessSceneGetsAFramedView) {
    write("tri.obj", "v 10 0 0\nv 12 0 0\nv 10 2 0\nf 1 2 3\n");
    const fs::path cfg = write("exp.yaml", "scene: tri.obj\n" + kRenders);
    const PreparedScene p = prepareScene(loadConfig(cfg));
    EXPECT_EQ(p.viewLabel, "framed");
    // Looking at the triangle's bounds' centre.
    const glm::vec3 toCentre = glm::normalize(glm::vec3(11, 1, 0) - p.view.position);
    EXPECT_GT(glm::dot(toCentre, p.view.direction), 0.9999f);
}

TEST_F(Files, MitsubaFilmIsTheDefaultImageSize) {
    write("scene.xml", R"(<scene version="3.0.0">
  <sensor type="perspective"><float name="fov" value="50"/>
    <film type="hdrfilm"><integer name="width" value="320"/><integer name="height" value="180"/></film>
  </sensor>
  <shape type="cube"><transform name="to_world"><translate z="5"/></transform></shape>
</scene>
)");
    const fs::path cfg = write("exp.yaml", "scene: scene.xml\n" + kRenders);
    const PreparedScene p = prepareScene(loadConfig(cfg));
    EXPECT_EQ(p.width, 320);
    EXPECT_EQ(p.height, 180);
    const PreparedScene q = prepareScene(loadConfig(cfg, {"image.width=160"}));
    EXPECT_EQ(q.width, 160);  // the config's box wins; the film's aspect ratio still fits inside
    EXPECT_EQ(q.height, 90);
    // The key says the size comes from the scene, so an explicit 512 x 512 is a different render.
    const ExperimentConfig fromScene = loadConfig(cfg), explicitSize = loadConfig(cfg, {"image.width=512"});
    EXPECT_NE(renderKey(fromScene, fromScene.renders[0]), renderKey(explicitSize, explicitSize.renders[0]));
}

TEST_F(Files, MitsubaIntegratorDecidesTheDepthsTheConfigLeavesOut) {
    write("scene.xml", R"(<scene version="3.0.0">
  <integrator type="path"><integer name="max_depth" value="65"/><integer name="rr_depth" value="9"/>
    <boolean name="hide_emitters" value="true"/></integrator>
  <sensor type="perspective"><float name="fov" value="50"/>
    <sampler type="independent"><integer name="sample_count" value="64"/></sampler>
    <film type="hdrfilm"><rfilter type="gaussian"/></film>
  </sensor>
  <shape type="cube"><transform name="to_world"><translate z="5"/></transform></shape>
</scene>
)");
    const fs::path cfg = write("exp.yaml", "scene: scene.xml\n" + kRenders);
    const ExperimentConfig silent = loadConfig(cfg);
    const PreparedScene p = prepareScene(silent);
    std::vector<std::string> notes;
    const ExperimentConfig effective = withSceneRenderSettings(silent, p.scene, notes);
    EXPECT_EQ(effective.shading.maxDepth, 65);
    EXPECT_EQ(effective.shading.rouletteDepth, 9);
    auto noted = [&](const std::string& needle) {
        return std::any_of(notes.begin(), notes.end(), [&](const std::string& n) { return n.find(needle) != n.npos; });
    };
    EXPECT_TRUE(noted("shading.max_depth 65 and shading.roulette_depth 9 from the scene file's <integrator "
                      "type=\"path\">"));
    EXPECT_TRUE(effective.shading.hideEmitters);
    EXPECT_TRUE(noted("shading.hide_emitters true from the scene file's <integrator type=\"path\">"));
    EXPECT_TRUE(noted("asks 64 samples per pixel"));
    EXPECT_TRUE(noted("reference.rpp: 64 would match the file"));  // the reference traces the renders' 1
    // The film's filter where the config names none, said so; the key follows the file.
    EXPECT_EQ(effective.image.filter.type, PixelFilterType::Gaussian);
    EXPECT_TRUE(noted("image.filter gaussian from the scene file's film"));
    const ExperimentConfig boxGiven = loadConfig(cfg, {"image.filter=box"});
    EXPECT_NE(renderKey(silent, silent.renders[0]), renderKey(boxGiven, boxGiven.renders[0]));
    notes.clear();
    EXPECT_EQ(withSceneRenderSettings(boxGiven, p.scene, notes).image.filter.type, PixelFilterType::Box);
    EXPECT_TRUE(noted("'gaussian' filter; the renders use image.filter box as the config says"));
    notes.clear();

    // The config's own values win, and only what the config leaves out is noted as applied.
    const ExperimentConfig given = loadConfig(cfg, {"shading.max_depth=7", "image.filter=gaussian"});
    notes.clear();
    const ExperimentConfig mixed = withSceneRenderSettings(given, p.scene, notes);
    EXPECT_EQ(mixed.shading.maxDepth, 7);
    EXPECT_EQ(mixed.shading.rouletteDepth, 9);
    EXPECT_TRUE(noted("shading.roulette_depth 9 from"));
    EXPECT_FALSE(noted("shading.max_depth"));
    EXPECT_FALSE(noted("filter"));

    // The key follows the file when the file decides: an explicit depth is another render.
    const ExperimentConfig explicitDepth = loadConfig(cfg, {"shading.max_depth=65"});
    EXPECT_NE(renderKey(silent, silent.renders[0]), renderKey(explicitDepth, explicitDepth.renders[0]));
    // The config's hide_emitters wins over the file's, and is another render than the file's choice.
    const ExperimentConfig shown = loadConfig(cfg, {"shading.hide_emitters=false"});
    notes.clear();
    EXPECT_FALSE(withSceneRenderSettings(shown, p.scene, notes).shading.hideEmitters);
    EXPECT_FALSE(noted("hide_emitters"));
    EXPECT_NE(renderKey(silent, silent.renders[0]), renderKey(shown, shown.renders[0]));

    // Without an integrator the config's defaults stand, unnoted.
    write("plain.xml", "<scene version=\"3.0.0\"><shape type=\"cube\"/></scene>\n");
    const ExperimentConfig plain = loadConfig(write("plain.yaml", "scene: plain.xml\n" + kRenders));
    notes.clear();
    const ExperimentConfig same = withSceneRenderSettings(plain, prepareScene(plain).scene, notes);
    EXPECT_EQ(same.shading.maxDepth, plain.shading.maxDepth);
    EXPECT_TRUE(notes.empty());
}

// What can be checked before the scene loads is checked before it loads: the scene's name or
// file, the view file and view_index in it; and the render size from a view file, so a reference
// image of another size is refused without loading the scene.
TEST_F(Files, InputsAreCheckedWithoutLoadingTheScene) {
    const auto errorOf = [&](const std::string& yaml) -> std::string {
        try {
            checkInputs(loadConfig(write("check.yaml", yaml)));
        } catch (const InputError& e) {
            EXPECT_GT(e.line(), 0) << e.what();
            return e.what();
        }
        return "";
    };
    EXPECT_NE(errorOf("scene: builtin:cornel\n" + kRenders).find("did you mean 'builtin:cornell'"), std::string::npos);
    EXPECT_NE(errorOf("scene: missing.obj\n" + kRenders).find("no such file"), std::string::npos);
    write("tri.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    EXPECT_EQ(errorOf("scene: tri.obj\n" + kRenders), "");
    EXPECT_NE(errorOf("scene: tri.obj\nview: missing.vf\n" + kRenders).find("view 'missing.vf'"), std::string::npos);
    write("one.vf", "rview -vtv -vp 0 0 5 -vd 0 0 -1 -vu 0 1 0 -vh 60 -vv 30\n");
    EXPECT_NE(errorOf("scene: tri.obj\nview: one.vf\nview_index: 3\n" + kRenders).find("out of range"), std::string::npos);
    const ExperimentConfig c = loadConfig(write("ok.yaml", "scene: tri.obj\nview: one.vf\nimage: {width: 64, height: 64}\n" + kRenders));
    const auto size = renderSizeWithoutScene(c);
    ASSERT_TRUE(size.has_value());
    EXPECT_EQ(size->first, 64);
    EXPECT_LT(size->second, 64);  // the view's 2:1 field shrinks the height
    EXPECT_FALSE(renderSizeWithoutScene(loadConfig(write("noview.yaml", "scene: tri.obj\n" + kRenders))).has_value());
    // A Mitsuba scene whose film decides the size: the view file is still checked before loading.
    write("scene.xml", "<scene version=\"3.0.0\"><shape type=\"cube\"/></scene>\n");
    EXPECT_NE(errorOf("scene: scene.xml\nview: missing.vf\n" + kRenders).find("view 'missing.vf'"), std::string::npos);
}

}  // namespace
}  // namespace aamap
