// The light schema's one parser (eval/light_list.h): light files and the config's inline list,
// with every problem reported at file:line:col.
#include <filesystem>
#include <fstream>
#include <string>

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include "core/error.h"
#include "eval/config.h"
#include "eval/light_list.h"

namespace aamap {
namespace {

class LightFile : public ::testing::Test {
protected:
    void SetUp() override {
        dir_ = std::filesystem::temp_directory_path() /
               fmt::format("aamap_lights_{}_{}", ::getpid(), ::testing::UnitTest::GetInstance()->current_test_info()->name());
        std::filesystem::remove_all(dir_);
        std::filesystem::create_directories(dir_);
    }
    void TearDown() override {
        std::error_code ec;
        std::filesystem::remove_all(dir_, ec);
    }
    std::filesystem::path write(const std::string& name, const std::string& text) const {
        const auto path = dir_ / name;
        std::filesystem::create_directories(path.parent_path());
        std::ofstream(path, std::ios::binary) << text;
        return path;
    }
    // Loads `text` as a light file, expecting an InputError at line:col mentioning `fragment`.
    void expectError(const std::string& text, int line, int col, const std::string& fragment) const {
        const auto path = write("bad.yaml", text);
        try {
            loadLightFile(path);
            ADD_FAILURE() << "no error for:\n" << text;
        } catch (const InputError& e) {
            EXPECT_EQ(e.file(), path) << e.what();
            EXPECT_EQ(e.line(), line) << e.what();
            EXPECT_EQ(e.column(), col) << e.what();
            EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
            EXPECT_EQ(std::string(e.what()).rfind(fmt::format("{}:{}:{}: ", path.string(), line, col), 0), 0u) << e.what();
        }
    }
    std::filesystem::path dir_;
};

const char* const kAllTypes = R"(# one of each
- {type: point, name: bulb, position: [0, 2, 0], intensity: [1, 2, 3]}
- {position: [1, 2, 3], power: [10, 10, 10], normal: [0, -1, 0]}
- type: spot
  name: stage
  position: [0, 3, 0]
  direction: [0, -1, 0.5]
  inner_angle: 15
  outer_angle: 25.5
  intensity: [100, 90, 80]
- {type: quad, name: panel, position: [0, 2.9, 0], normal: [0, -1, 0], up: [0, 0, 1], size: [0.5, 0.25],
   radiance: [5, 5, 5]}
- {type: disk, name: downlight, position: [1, 2.9, 1], normal: [0, -1, 0], radius: 0.1, segments: 12,
   power: [30, 30, 30]}
)";

TEST_F(LightFile, ReadsEveryTypeWithDefaults) {
    const auto lights = loadLightFile(write("lights.yaml", kAllTypes));
    ASSERT_EQ(lights.size(), 5u);
    EXPECT_EQ(lights[0].type, LightType::Point);
    EXPECT_EQ(lights[0].name, "bulb");
    EXPECT_EQ(lights[0].unit, EmissionUnit::Intensity);
    EXPECT_EQ(lights[0].emission, (std::array<double, 3>{1, 2, 3}));
    EXPECT_EQ(lights[1].type, LightType::Point);  // the default type
    EXPECT_EQ(lights[1].name, "light1");          // the default name: its index
    EXPECT_EQ(lights[1].unit, EmissionUnit::Power);
    EXPECT_EQ(lights[1].normal[1], -1.0);
    EXPECT_EQ(lights[2].type, LightType::Spot);
    EXPECT_EQ(lights[2].direction, (std::array<double, 3>{0, -1, 0.5}));
    EXPECT_EQ(lights[2].innerAngle, 15.0);
    EXPECT_EQ(lights[2].outerAngle, 25.5);
    EXPECT_EQ(lights[3].type, LightType::Quad);
    EXPECT_EQ(lights[3].size, (std::array<double, 2>{0.5, 0.25}));
    EXPECT_EQ(lights[3].unit, EmissionUnit::Radiance);
    EXPECT_EQ(lights[4].type, LightType::Disk);
    EXPECT_EQ(lights[4].radius, 0.1);
    EXPECT_EQ(lights[4].segments, 12);
    EXPECT_EQ(lights[4].unit, EmissionUnit::Power);
    // Canonical JSON: a point light given by intensity keeps the keys configs always had.
    EXPECT_EQ(lightJson(lights[0]).dump(),
              R"({"type":"point","name":"bulb","position":[0.0,2.0,0.0],"intensity":[1.0,2.0,3.0],"normal":[0.0,0.0,0.0]})");
    EXPECT_TRUE(loadLightFile(write("empty.yaml", "[]\n")).empty());
}

TEST_F(LightFile, ErrorsNameFileLineAndColumn) {
    expectError("- {type: tube, position: [0, 0, 0]}\n", 1, 10,
                "unknown light type 'tube' (supported: point, spot, quad, disk, directional, environment)");
    expectError("- {position: [0, 0, 0], intensity: [1, 1, 1]}\n- {type: spot, position: [0, 0, 0], intensity: [1, 1, 1],\n"
                "   direction: [0, -1, 0], radius: 2}\n",
                3, 27, "unknown key 'radius' in 'lights.1'");
    expectError("- {intensity: [1, 1, 1]}\n", 1, 3, "missing required key 'lights.0.position'");
    expectError("- {position: [0, 0, 0]}\n", 1, 3, "give exactly one of 'intensity' and 'power' for a point light");
    expectError("- {position: [0, 0, 0], intensity: [1, 1, 1], power: [1, 1, 1]}\n", 1, 54, "exactly one of");
    expectError("- {type: quad, position: [0, 0, 0], intensity: [1, 1, 1], normal: [0, 1, 0], size: [1, 1]}\n", 1, 48,
                "a quad light is given by exactly one of 'radiance' and 'power', not 'intensity'");
    expectError("- {position: [0, 0, 0], intensty: [1, 1, 1]}\n", 1, 25, "did you mean 'intensity'?");
    expectError("- {type: spot, position: [0, 0, 0], intensity: [1, 1, 1], direction: [0, -1, 0],\n"
                "   inner_angle: 30, outer_angle: 20}\n",
                2, 17, "lights.0.inner_angle: 30 degrees is wider than outer_angle (20 degrees)");
    expectError("- {type: spot, position: [0, 0, 0], intensity: [1, 1, 1], direction: [0, 0, 0]}\n", 1, 70,
                "lights.0.direction: must not be the zero vector");
    expectError("- {type: disk, position: [0, 0, 0], radiance: [1, 1, 1], normal: [0, 1, 0], radius: -1}\n", 1, 85,
                "lights.0.radius: -1 is out of range (0");
    expectError("- {type: quad, position: [0, 0, 0], radiance: [1, 1, 1], normal: [0, 1, 0], size: [1, 0]}\n", 1, 87,
                "lights.0.size[1]: expected a positive number");
    expectError("- {position: [0, 0, 0], intensity: [1, -1, 1]}\n", 1, 40, "lights.0.intensity[1]: -1 is out of range");
    expectError("lights: []\n", 1, 1, "a light file is a YAML list of lights");
    expectError("- {position: [0, 0, 0]\n", 2, 1, "invalid YAML");
    expectError("- 3\n", 1, 3, "lights.0: expected a mapping (a light)");
}

// The lights at infinity: a directional light (direction and irradiance, no position) and an
// environment (a constant radiance, or a map named relative to the light file with its scale,
// rotation and up).
TEST_F(LightFile, ReadsDirectionalAndEnvironmentLights) {
    write("maps/sky.exr", "not parsed here: only its name and presence are checked");
    const auto lights = loadLightFile(write("lights.yaml",
                                            "- {type: directional, name: sun, direction: [0.2, -1, 0.1], irradiance: [3, 2, 1]}\n"
                                            "- {type: environment, name: sky, map: maps/sky.exr, scale: 2.5, rotation: -30,\n"
                                            "   up: [0, 0, 1]}\n"));
    ASSERT_EQ(lights.size(), 2u);
    EXPECT_EQ(lights[0].type, LightType::Directional);
    EXPECT_EQ(lights[0].direction, (std::array<double, 3>{0.2, -1, 0.1}));
    EXPECT_EQ(lights[0].unit, EmissionUnit::Irradiance);
    EXPECT_EQ(lights[0].emission, (std::array<double, 3>{3, 2, 1}));
    EXPECT_EQ(lights[1].type, LightType::Environment);
    EXPECT_EQ(std::filesystem::path(lights[1].map), dir_ / "maps/sky.exr");
    EXPECT_EQ(lights[1].scale, 2.5);
    EXPECT_EQ(lights[1].rotation, -30.0);
    EXPECT_EQ(lights[1].up, (std::array<double, 3>{0, 0, 1}));
    EXPECT_EQ(lightJson(lights[0]).dump(),
              R"({"type":"directional","name":"sun","direction":[0.2,-1.0,0.1],"irradiance":[3.0,2.0,1.0]})");
    const auto constant = loadLightFile(write("sky.yaml", "- {type: environment, radiance: [0.1, 0.2, 0.3]}\n"));
    ASSERT_EQ(constant.size(), 1u);
    EXPECT_EQ(constant[0].name, "light0");
    EXPECT_TRUE(constant[0].map.empty());
    EXPECT_EQ(constant[0].unit, EmissionUnit::Radiance);
    EXPECT_EQ(constant[0].emission, (std::array<double, 3>{0.1, 0.2, 0.3}));
    EXPECT_EQ(lightJson(constant[0]).dump(), R"({"type":"environment","name":"light0","radiance":[0.1,0.2,0.3]})");
}

TEST_F(LightFile, DirectionalAndEnvironmentErrorsNameFileLineAndColumn) {
    write("sky.png", "8-bit");
    expectError("- {type: directonal, direction: [0, -1, 0], irradiance: [1, 1, 1]}\n", 1, 10,
                "unknown light type 'directonal'; did you mean 'directional'?");
    expectError("- {type: directional, direction: [0, -1, 0], irradiance: [1, 1, 1], directoin: [0, 1, 0]}\n", 1, 69,
                "unknown key 'directoin' in 'lights.0'; did you mean 'direction'?");
    expectError("- {type: directional, irradiance: [1, 1, 1]}\n", 1, 3, "missing required key 'lights.0.direction'");
    expectError("- {type: directional, direction: [0, 0, 0], irradiance: [1, 1, 1]}\n", 1, 34,
                "lights.0.direction: must not be the zero vector");
    expectError("- {type: directional, position: [0, 1, 0], direction: [0, -1, 0], irradiance: [1, 1, 1]}\n", 1, 23,
                "unknown key 'position' in 'lights.0'");
    expectError("- {type: directional, direction: [0, -1, 0], irradiance: [1, 1, 1], power: [1, 1, 1]}\n", 1, 69,
                "unknown key 'power'");
    expectError("- {type: environment}\n", 1, 3, "give exactly one of 'radiance' (a constant sky) and 'map'");
    expectError("- {type: environment, radiance: [1, 1, 1], map: sky.exr}\n", 1, 49, "give exactly one of 'radiance'");
    expectError("- {type: environment, map: nowhere.hdr}\n", 1, 28, "lights.0.map: environment map '");
    expectError("- {type: environment, map: sky.png}\n", 1, 28,
                "lights.0.map: 'sky.png' is not an EXR or Radiance HDR image (8-bit images hold no radiance)");
    expectError("- {type: environment, radiance: [1, 1, 1], scale: 2}\n", 1, 51,
                "lights.0.scale: only an environment with a 'map' has a scale");
    expectError("- {type: environment, radiance: [1, -1, 1]}\n", 1, 37, "lights.0.radiance[1]: -1 is out of range");
    write("sky.hdr", "");
    expectError("- {type: environment, map: sky.hdr, rotation: 400}\n", 1, 47, "lights.0.rotation: 400 is out of range");
    expectError("- {type: environment, map: sky.hdr, up: [0, 0, 0]}\n", 1, 41, "lights.0.up: must not be the zero vector");
    expectError("- {type: environment, map: sky.hdr, scael: 2}\n", 1, 37, "did you mean 'scale'?");
    expectError("- {type: environment, radiance: [1, 1, 1]}\n- {type: environment, map: sky.hdr}\n", 2, 3,
                "lights.1: a second environment (the first is lights.0); a scene has at most one");
}

TEST_F(LightFile, ConfigMergesTheLightFileWithTheInlineList) {
    write("lights/room.yaml", kAllTypes);
    const auto config = write("exp.yaml", "scene: builtin:cornell\nlight_file: lights/room.yaml\n"
                                          "lights: [{name: extra, position: [0, 1, 0], intensity: [1, 1, 1]}]\n"
                                          "renders: [{strategy: uniform, rpp: 1}]\n");
    const ExperimentConfig c = loadConfig(config);
    ASSERT_EQ(c.lights.size(), 6u);  // the file's, then the inline one
    EXPECT_EQ(c.lights[0].name, "bulb");
    EXPECT_EQ(c.lights[5].name, "extra");
    EXPECT_EQ(*c.resolvedLightFile(), (dir_ / "lights/room.yaml").lexically_normal());
    EXPECT_NE(c.canonicalJson().find(R"("light_file":"lights/room.yaml")"), std::string::npos);
    EXPECT_NE(c.canonicalJson().find(R"("type":"disk")"), std::string::npos);

    // The same schema inline, and --set reaches the new keys.
    const ExperimentConfig inl = parseConfig(
        "scene: builtin:cornell\nrenders: [{strategy: uniform, rpp: 1}]\n"
        "lights: [{type: spot, position: [0, 1, 0], intensity: [1, 1, 1], direction: [0, -1, 0]}]\n",
        "exp.yaml", {"lights.0.outer_angle=60", "lights.0.inner_angle=5"});
    ASSERT_EQ(inl.lights.size(), 1u);
    EXPECT_EQ(inl.lights[0].outerAngle, 60.0);
    EXPECT_EQ(inl.lights[0].innerAngle, 5.0);
}

TEST_F(LightFile, ConfigErrorsPointIntoTheLightFileOrAtTheKey) {
    write("bad.yaml", "- {position: [0, 0, 0], intensity: [1, 1]}\n");
    const auto config = write("exp.yaml", "scene: builtin:cornell\nlight_file: bad.yaml\nrenders: [{strategy: uniform, rpp: 1}]\n");
    try {
        loadConfig(config);
        ADD_FAILURE() << "no error";
    } catch (const InputError& e) {
        EXPECT_EQ(e.file(), dir_ / "bad.yaml") << e.what();
        EXPECT_EQ(e.line(), 1) << e.what();
        EXPECT_EQ(e.column(), 36) << e.what();
    }
    const auto missing = write("missing.yaml", "scene: builtin:cornell\nlight_file: nowhere.yaml\nrenders: [{strategy: uniform, rpp: 1}]\n");
    try {
        loadConfig(missing);
        ADD_FAILURE() << "no error";
    } catch (const InputError& e) {
        EXPECT_EQ(e.file(), missing) << e.what();
        EXPECT_EQ(e.line(), 2) << e.what();
        EXPECT_EQ(e.column(), 13) << e.what();
        EXPECT_NE(std::string(e.what()).find("light_file 'nowhere.yaml': "), std::string::npos) << e.what();
    }
    // An inline light with a key of another type: the config's own file:line:col.
    try {
        parseConfig("scene: builtin:cornell\nrenders: [{strategy: uniform, rpp: 1}]\n"
                    "lights:\n  - {position: [0, 1, 0], intensity: [1, 1, 1], size: [1, 1]}\n",
                    "exp.yaml");
        ADD_FAILURE() << "no error";
    } catch (const InputError& e) {
        EXPECT_EQ(e.file(), "exp.yaml");
        EXPECT_EQ(e.line(), 4);
        EXPECT_EQ(e.column(), 49);
        EXPECT_NE(std::string(e.what()).find("unknown key 'size' in 'lights.0'"), std::string::npos) << e.what();
    }
}

}  // namespace
}  // namespace aamap
