// Loads every public scene in ../shared/scenes (labelled "shared"; skips when it is absent).
#include <cmath>
#include <filesystem>
#include <map>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include "scene/builtin_scenes.h"
#include "scene/gltf_loader.h"
#include "scene/lights.h"
#include "scene/load_scene.h"
#include "scene/mitsuba_loader.h"
#include "scene/obj_loader.h"
#include "scene/view_file.h"

namespace aamap {
namespace {
namespace fs = std::filesystem;

const fs::path kScenes = AAMAP_SHARED_SCENES_DIR;

std::vector<fs::path> filesWithExtension(const std::vector<std::string>& extensions) {
    std::vector<fs::path> files;
    for (const auto& entry : fs::recursive_directory_iterator(kScenes)) {
        const std::string ext = entry.path().extension().string();
        for (const auto& wanted : extensions) {
            if (entry.is_regular_file() && ext == wanted) files.push_back(entry.path());
        }
    }
    std::sort(files.begin(), files.end());
    return files;
}

void expectSaneMesh(const Scene& s) {
    const TriangleMesh& m = s.mesh;
    ASSERT_GT(m.triangles.size(), 0u);
    ASSERT_LT(m.triangles.size(), 10'000'000u);
    ASSERT_EQ(m.normals.size(), m.positions.size());
    ASSERT_TRUE(m.uvs.empty() || m.uvs.size() == m.positions.size());
    ASSERT_EQ(m.materialIds.size(), m.triangles.size());
    ASSERT_EQ(m.objectIds.size(), m.triangles.size());
    for (std::size_t i = 0; i < m.positions.size(); ++i) {
        const glm::vec3 p = m.positions[i], n = m.normals[i];
        ASSERT_TRUE(std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z)) << "vertex " << i;
        ASSERT_NEAR(glm::length(n), 1.0f, 1e-3f) << "normal " << i;
    }
    for (const glm::uvec3& t : m.triangles) {
        ASSERT_LT(std::max({t.x, t.y, t.z}), m.positions.size());
    }
    for (std::uint32_t id : m.materialIds) ASSERT_LT(id, s.materials.size());
    for (const Material& mat : s.materials) {
        ASSERT_TRUE(mat.diffuseTexture < static_cast<int>(s.textures.size()));
    }
    for (const Texture& t : s.textures) {
        ASSERT_EQ(t.rgba.size(), static_cast<std::size_t>(t.width) * t.height * 4);
    }
    for (const AreaLight& l : s.areaLights) EXPECT_GT(l.area, 0.0f) << l.name;
}

TEST(SharedScenes, EveryObjLoads) {
    if (!fs::is_directory(kScenes)) GTEST_SKIP() << kScenes << " is absent";
    // Triangle counts from ../shared/scenes/README.md (after triangulating quads and polygons).
    const std::map<std::string, std::size_t> expected = {
        {"CornellBox-Original.obj", 36}, {"CornellBox-Mirror.obj", 36},
        {"staircase2_merged.obj", 31087}, {"conference.obj", 331179}};
    const auto files = filesWithExtension({".obj"});
    ASSERT_FALSE(files.empty());
    for (const fs::path& file : files) {
        SCOPED_TRACE(file.string());
        ObjLoadReport report;
        const Scene s = loadObj(file, &report);
        expectSaneMesh(s);
        if (const auto it = expected.find(file.filename().string()); it != expected.end()) {
            EXPECT_EQ(s.mesh.triangles.size() + report.degenerateTriangles, it->second);
        }
        // Each McGuire box has one quad emitter, except the Glossy ones: their MTL has no "light"
        // material, so the quad is a plain default surface there.
        const std::string name = file.filename().string();
        if (name.starts_with("CornellBox-")) {
            EXPECT_EQ(s.areaLights.size(), name.starts_with("CornellBox-Glossy") ? 0u : 1u);
        }
        if (file.filename() == "staircase2_merged.obj") {
            EXPECT_EQ(s.areaLights.size(), 13u);
            EXPECT_EQ(s.textures.size(), 3u);
        }
        if (file.filename() == "spider.obj") {
            EXPECT_GE(s.textures.size(), 4u);  // ".\name.jpg" paths
        }
    }
}

TEST(SharedScenes, CornellMirrorHasAMirrorMaterial) {
    if (!fs::is_directory(kScenes)) GTEST_SKIP() << kScenes << " is absent";
    const Scene s = loadObj(kScenes / "cornell-mcguire" / "CornellBox-Mirror.obj");
    bool mirror = false;
    for (const Material& m : s.materials) mirror = mirror || m.kind == MaterialKind::Mirror;
    EXPECT_TRUE(mirror);
    // The light quad faces down into the box.
    const AreaLight& light = s.areaLights.at(0);
    for (const PointLight& p : approximateAreaLight(s, light, 5)) EXPECT_LT(p.normal.y, -0.99f);
}

TEST(SharedScenes, EveryGltfLoads) {
    if (!fs::is_directory(kScenes)) GTEST_SKIP() << kScenes << " is absent";
    // Triangle counts from ../shared/scenes/README.md; 11,160 of 2CylinderEngine's 121,496 have
    // zero area and are dropped.
    const std::map<std::string, std::size_t> expected = {
        {"BoxTextured.gltf", 12}, {"BoxTextured.glb", 12}, {"2CylinderEngine.glb", 121496 - 11160}, {"oaktree.gltf", 5302}};
    const auto files = filesWithExtension({".gltf", ".glb"});
    ASSERT_FALSE(files.empty());
    for (const fs::path& file : files) {
        SCOPED_TRACE(file.string());
        const Scene s = loadGltf(file);
        expectSaneMesh(s);
        if (const auto it = expected.find(file.filename().string()); it != expected.end()) {
            EXPECT_EQ(s.mesh.triangles.size(), it->second);
        }
        if (file.filename().string().starts_with("BoxTextured")) {
            EXPECT_EQ(s.textures.size(), 1u);
        }
        if (file.filename() == "Cameras.gltf") {
            EXPECT_EQ(s.views.size(), 1u);  // the orthographic camera is skipped
        }
    }
}

TEST(SharedScenes, EveryViewFileParses) {
    if (!fs::is_directory(kScenes)) GTEST_SKIP() << kScenes << " is absent";
    const auto files = filesWithExtension({".vf"});
    ASSERT_FALSE(files.empty());
    for (const fs::path& file : files) {
        SCOPED_TRACE(file.string());
        const auto views = loadViewFile(file);
        EXPECT_GE(views.size(), 1u);
    }
}

TEST(SharedScenes, ModernHallThroughLoadSceneGetsItsView) {
    if (!fs::is_directory(kScenes)) GTEST_SKIP() << kScenes << " is absent";
    const Scene s = loadScene((kScenes / "modern-hall" / "staircase2_merged.obj").string());
    ASSERT_EQ(s.views.size(), 1u);
    EXPECT_NEAR(s.views[0].horizontalFovDeg, 70.0f, 1e-4f);
}

// Mitsuba 0.5 (Bitterli's staircase2): meshes, textures, 13 area lights, the sensor and its film.
TEST(SharedScenes, ModernHallMitsubaXmlLoads) {
    const fs::path file = kScenes / "modern-hall" / "scene.xml";
    if (!fs::is_regular_file(file)) GTEST_SKIP() << file << " is absent";
    MitsubaLoadReport report;
    const Scene s = loadMitsuba(file, &report);
    expectSaneMesh(s);
    EXPECT_EQ(s.areaLights.size(), 13u);
    EXPECT_GE(s.textures.size(), 3u);  // wood, tiles, wallpaper
    ASSERT_EQ(s.views.size(), 1u);
    EXPECT_NEAR(s.views[0].horizontalFovDeg, 70.0f, 1e-3f);
    EXPECT_EQ(s.imageWidth, 1280);
    EXPECT_EQ(s.imageHeight, 720);
    EXPECT_TRUE(std::any_of(s.materials.begin(), s.materials.end(),
                            [](const Material& m) { return m.kind == MaterialKind::Glass; }));
    // The same staircase as the OBJ conversion next to it, so the same place and size.
    const Bounds obj = sceneBounds(loadObj(kScenes / "modern-hall" / "staircase2_merged.obj"));
    const Bounds xml = sceneBounds(s);
    for (int a = 0; a < 3; ++a) {
        EXPECT_NEAR(xml.lo[a], obj.lo[a], 0.05f) << "axis " << a;
        EXPECT_NEAR(xml.hi[a], obj.hi[a], 0.05f) << "axis " << a;
    }
}

// Mitsuba 2/3 (snake_case names, a lookat sensor, millimetres, spectra): the built-in Cornell
// box in millimetres, with the same camera and near the same albedos.
TEST(SharedScenes, MitsubaCornellBoxMatchesTheBuiltinOne) {
    const fs::path file = kScenes / "mitsuba-cbox" / "scene.xml";
    if (!fs::is_regular_file(file)) GTEST_SKIP() << file << " is absent";
    const Scene m = loadMitsuba(file);
    const Scene b = builtinScene("cornell");
    expectSaneMesh(m);
    const Bounds bm = sceneBounds(m), bb = sceneBounds(b);
    for (int a = 0; a < 3; ++a) {
        EXPECT_NEAR(bm.lo[a] / 1000.0f, bb.lo[a], 0.003f) << "axis " << a;
        EXPECT_NEAR(bm.hi[a] / 1000.0f, bb.hi[a], 0.003f) << "axis " << a;
    }
    ASSERT_EQ(m.views.size(), 1u);
    ASSERT_FALSE(b.views.empty());
    EXPECT_NEAR(glm::length(m.views[0].position / 1000.0f - b.views[0].position), 0.0f, 1e-4f);
    EXPECT_GT(glm::dot(m.views[0].direction, b.views[0].direction), 0.99999f);
    EXPECT_NEAR(m.views[0].horizontalFovDeg, b.views[0].horizontalFovDeg, 0.01f);
    EXPECT_NEAR(m.views[0].verticalFovDeg, b.views[0].verticalFovDeg, 0.01f);
    ASSERT_EQ(m.areaLights.size(), 1u);
    ASSERT_EQ(b.areaLights.size(), 1u);
    EXPECT_NEAR(m.areaLights[0].area / 1e6f, b.areaLights[0].area, 0.01f * b.areaLights[0].area);
    // The walls' measured spectra: the white is grey at the built-in albedo; the red and green
    // walls keep their hue (the dominant channel 4x, for green 2x, the others). Their saturated
    // channel differs from the built-in RGB values, which come from another conversion.
    std::map<std::string, glm::vec3> kd;
    for (const Material& mat : m.materials) kd[mat.name] = mat.kd;
    ASSERT_TRUE(kd.count("white") && kd.count("red") && kd.count("green"));
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(kd["white"][c], 0.74f, 0.02f) << "white channel " << c;
    EXPECT_GT(kd["red"].r, 4.0f * std::max(kd["red"].g, kd["red"].b));
    EXPECT_GT(kd["green"].g, 2.0f * std::max(kd["green"].r, kd["green"].b));
}

}  // namespace
}  // namespace aamap
