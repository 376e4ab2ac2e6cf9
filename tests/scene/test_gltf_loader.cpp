#include <cstring>

#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>
#include <gtest/gtest.h>
#include <stb_image_write.h>

#include "core/error.h"
#include "scene/gltf_loader.h"
#include "scene/lights.h"
#include "mutate.h"
#include "tests/common/base64.h"
#include "tests/common/temp_dir.h"

namespace aamap {
namespace {

template <class T>
void append(std::string& buffer, std::initializer_list<T> values) {
    for (T v : values) buffer.append(reinterpret_cast<const char*>(&v), sizeof(T));
}

std::string replaceAll(std::string s, const std::string& from, const std::string& to) {
    for (std::size_t p = 0; (p = s.find(from, p)) != std::string::npos; p += to.size()) s.replace(p, from.size(), to);
    return s;
}

// A unit quad (indexed, with normals and UVs) under a translated node, a mirrored emissive
// triangle as its child, a camera, a point light, and four kinds of material.
std::string testGltf() {
    std::string buf;
    append<float>(buf, {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0});   // 0: quad positions (48 bytes)
    append<float>(buf, {0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1});   // 48: normals
    append<float>(buf, {0, 0, 1, 0, 1, 1, 0, 1});               // 96: uvs (32 bytes)
    append<std::uint16_t>(buf, {0, 1, 2, 0, 2, 3});             // 128: indices (12 bytes)
    append<float>(buf, {0, 0, 0, 1, 0, 0, 0, 1, 0});            // 140: triangle (36 bytes)
    std::string json = R"({
  "asset": {"version": "2.0"},
  "extensionsUsed": ["KHR_lights_punctual", "KHR_materials_emissive_strength", "KHR_materials_transmission", "KHR_materials_ior"],
  "scene": 0,
  "scenes": [{"nodes": [0, 2, 3]}],
  "nodes": [
    {"name": "floor", "mesh": 0, "translation": [0, 1, 0], "children": [1]},
    {"name": "lamp", "mesh": 1, "scale": [-1, 1, 1]},
    {"name": "eye", "camera": 0, "translation": [0, 0, 5]},
    {"name": "bulb", "translation": [1, 2, 3], "extensions": {"KHR_lights_punctual": {"light": 0}}}
  ],
  "extensions": {"KHR_lights_punctual": {"lights": [{"type": "point", "color": [1, 0.5, 0.25], "intensity": 4}]}},
  "cameras": [{"type": "perspective", "perspective": {"yfov": 0.5, "aspectRatio": 2.0, "znear": 0.1}}],
  "meshes": [
    {"name": "quad", "primitives": [{"attributes": {"POSITION": 0, "NORMAL": 1, "TEXCOORD_0": 2}, "indices": 3, "material": 0}]},
    {"name": "tri", "primitives": [{"attributes": {"POSITION": 4}, "material": 1},
                                   {"attributes": {"POSITION": 4}, "material": 2},
                                   {"attributes": {"POSITION": 4}, "material": 3}]}
  ],
  "materials": [
    {"name": "textured", "pbrMetallicRoughness": {"baseColorFactor": [0.5, 0.5, 0.5, 1], "metallicFactor": 0, "baseColorTexture": {"index": 0}}},
    {"name": "glow", "emissiveFactor": [1, 2, 3], "extensions": {"KHR_materials_emissive_strength": {"emissiveStrength": 2}}},
    {"name": "chrome", "pbrMetallicRoughness": {"metallicFactor": 1, "roughnessFactor": 0}},
    {"name": "water", "extensions": {"KHR_materials_transmission": {"transmissionFactor": 1}, "KHR_materials_ior": {"ior": 1.33}}}
  ],
  "textures": [{"source": 0}],
  "images": [{"uri": "Tex.PNG"}],
  "buffers": [{"byteLength": 176, "uri": "data:application/octet-stream;base64,@DATA@"}],
  "bufferViews": [
    {"buffer": 0, "byteOffset": 0, "byteLength": 128},
    {"buffer": 0, "byteOffset": 128, "byteLength": 12},
    {"buffer": 0, "byteOffset": 140, "byteLength": 36}
  ],
  "accessors": [
    {"bufferView": 0, "byteOffset": 0, "componentType": 5126, "count": 4, "type": "VEC3", "min": [0, 0, 0], "max": [1, 1, 0]},
    {"bufferView": 0, "byteOffset": 48, "componentType": 5126, "count": 4, "type": "VEC3"},
    {"bufferView": 0, "byteOffset": 96, "componentType": 5126, "count": 4, "type": "VEC2"},
    {"bufferView": 1, "byteOffset": 0, "componentType": 5123, "count": 6, "type": "SCALAR"},
    {"bufferView": 2, "byteOffset": 0, "componentType": 5126, "count": 3, "type": "VEC3", "min": [0, 0, 0], "max": [1, 1, 0]}
  ]
})";
    return replaceAll(json, "@DATA@", base64(buf));
}

TEST(GltfLoader, GeometryTransformsMaterialsCamerasAndLights) {
    test::TempDir dir;
    const unsigned char pixel[] = {128, 128, 128, 255};
    ASSERT_NE(stbi_write_png((dir.path() / "tex.png").string().c_str(), 1, 1, 4, pixel, 4), 0);  // case differs
    const Scene s = loadGltf(dir.write("model.gltf", testGltf()));
    EXPECT_EQ(s.name, "model");
    ASSERT_EQ(s.mesh.triangles.size(), 2u + 3u);
    ASSERT_EQ(s.mesh.uvs.size(), s.mesh.positions.size());
    // The quad is lifted by its node's translation.
    for (std::uint32_t t = 0; t < 2; ++t) {
        for (int k = 0; k < 3; ++k) EXPECT_GE(s.mesh.positions[s.mesh.triangles[t][k]].y, 1.0f);
        EXPECT_EQ(s.mesh.objectIds[t], 0u);
    }
    // The child triangle is mirrored in x but still faces +z, and its flat normal agrees.
    const glm::uvec3 lamp = s.mesh.triangles[2];
    EXPECT_GT(triangleNormal(s.mesh, 2).z, 0.99f);
    EXPECT_GT(s.mesh.normals[lamp.x].z, 0.99f);
    EXPECT_EQ(s.mesh.objectIds[2], 1u);
    EXPECT_LE(s.mesh.positions[lamp.y].x, 0.0f);

    ASSERT_EQ(s.materials.size(), 4u);
    EXPECT_EQ(s.materials[0].diffuseTexture, 0);
    ASSERT_EQ(s.textures.size(), 1u);
    EXPECT_NEAR(s.textures[0].rgba[0], 0.2158605f, 1e-5f);
    EXPECT_EQ(s.materials[0].kd, glm::vec3(0.5f));
    EXPECT_EQ(s.materials[1].ke, glm::vec3(2, 4, 6));
    EXPECT_EQ(s.materials[2].kind, MaterialKind::Mirror);
    EXPECT_EQ(s.materials[3].kind, MaterialKind::Glass);
    EXPECT_FLOAT_EQ(s.materials[3].ior, 1.33f);

    ASSERT_EQ(s.areaLights.size(), 1u);
    EXPECT_EQ(s.areaLights[0].name, "lamp/glow");
    EXPECT_FLOAT_EQ(s.areaLights[0].area, 0.5f);

    ASSERT_EQ(s.views.size(), 1u);
    EXPECT_EQ(s.views[0].name, "eye");
    EXPECT_NEAR(s.views[0].position.z, 5.0f, 1e-6f);
    EXPECT_NEAR(s.views[0].direction.z, -1.0f, 1e-6f);
    EXPECT_NEAR(s.views[0].verticalFovDeg, glm::degrees(0.5f), 1e-4f);
    EXPECT_NEAR(std::tan(glm::radians(s.views[0].horizontalFovDeg) / 2), 2 * std::tan(0.25f), 1e-5f);

    ASSERT_EQ(s.pointLights.size(), 1u);
    EXPECT_EQ(s.pointLights[0].position, glm::vec3(1, 2, 3));
    EXPECT_EQ(s.pointLights[0].intensity, glm::vec3(4, 2, 1));
}

TEST(GltfLoader, MissingTextureWarnsAndKeepsBaseColour) {
    test::TempDir dir;
    const Scene s = loadGltf(dir.write("model.gltf", testGltf()));  // no Tex.PNG on disk
    EXPECT_EQ(s.materials[0].diffuseTexture, -1);
    EXPECT_TRUE(s.textures.empty());
}

TEST(GltfLoader, JsonSyntaxErrorsNameLineAndColumn) {
    test::TempDir dir;
    try {
        loadGltf(dir.write("bad.gltf", "{\n  \"asset\": {\"version\": \"2.0\"},\n  \"nodes\": [ { ] \n}\n"));
        FAIL();
    } catch (const InputError& e) {
        EXPECT_EQ(e.file().filename(), "bad.gltf");
        EXPECT_EQ(e.line(), 3) << e.what();
        EXPECT_GT(e.column(), 0) << e.what();
    }
}

TEST(GltfLoader, BrokenReferencesAreInputErrors) {
    test::TempDir dir;
    std::string json = testGltf();
    json = replaceAll(json, R"("indices": 3)", R"("indices": 9)");
    EXPECT_THROW(loadGltf(dir.write("a.gltf", json)), InputError);
    json = replaceAll(testGltf(), R"("count": 6)", R"("count": 600)");
    EXPECT_THROW(loadGltf(dir.write("b.gltf", json)), InputError);
    EXPECT_THROW(loadGltf("/nonexistent/model.gltf"), InputError);
}

TEST(GltfLoader, MutatedFilesGiveASceneOrAnInputError) {
    test::TempDir dir;
    const std::string json = testGltf();
    std::mt19937 rng(4242);
    int loaded = 0, rejected = 0;
    for (int i = 0; i < 300; ++i) {
        try {
            const Scene s = loadGltf(dir.write("m.gltf", test::mutate(json, rng, "0123456789-.,:[]{}\" e")));
            for (const glm::uvec3& t : s.mesh.triangles) {
                ASSERT_LT(std::max({t.x, t.y, t.z}), s.mesh.positions.size());
            }
            ++loaded;
        } catch (const InputError&) {
            ++rejected;
        }
    }
    EXPECT_GT(loaded + rejected, 0);
}

}  // namespace
}  // namespace aamap
