// Alpha in the scene model: glTF alphaMode / alphaCutoff / baseColorFactor.a / the base-colour
// texture's alpha, and MTL d / Tr / map_d (coverage maps read as data, not as sRGB colour).
#include <gtest/gtest.h>

#include "core/error.h"
#include "scene/gltf_loader.h"
#include "scene/obj_loader.h"
#include "tests/common/temp_dir.h"
#include "textured_quad_files.h"

namespace aamap::test {
namespace {

float coverageAt(const Scene& scene, int texture, int x, int y) {
    const Texture& t = scene.textures.at(static_cast<std::size_t>(texture));
    return t.rgba[4 * (static_cast<std::size_t>(y) * t.width + x) + 3];
}

TEST(AlphaMaterials, GltfMaskTakesCutoffAndTextureAlpha) {
    TempDir dir;
    writePng(dir, "tex.png", 16, holeTexture(16, true));
    const Scene scene = loadGltf(writeQuadGltf(dir, "tex.png"));
    ASSERT_EQ(scene.materials.size(), 1u);
    const Material& m = scene.materials[0];
    EXPECT_EQ(m.alphaMode, AlphaMode::Mask);
    EXPECT_FLOAT_EQ(m.alphaCutoff, 0.5f);
    EXPECT_FLOAT_EQ(m.alpha, 1.0f);
    ASSERT_GE(m.diffuseTexture, 0);
    EXPECT_EQ(m.alphaTexture, m.diffuseTexture);
    EXPECT_FLOAT_EQ(coverageAt(scene, m.alphaTexture, 0, 0), 1.0f);
    EXPECT_FLOAT_EQ(coverageAt(scene, m.alphaTexture, 8, 8), 0.0f);
    EXPECT_TRUE(isAlphaTested(m));
}

TEST(AlphaMaterials, GltfBlendCutsAtHalfAndOpaqueIgnoresAlpha) {
    TempDir dir;
    writePng(dir, "tex.png", 16, holeTexture(16, true));
    const Scene blend = loadGltf(writeQuadGltf(dir, "tex.png", "BLEND"));
    EXPECT_EQ(blend.materials[0].alphaMode, AlphaMode::Blend);
    EXPECT_FLOAT_EQ(effectiveAlphaCutoff(blend.materials[0]), 0.5f);
    const Scene opaque = loadGltf(writeQuadGltf(dir, "tex.png", "OPAQUE"));
    EXPECT_EQ(opaque.materials[0].alphaMode, AlphaMode::Opaque);
    EXPECT_EQ(opaque.materials[0].alphaTexture, -1);
    EXPECT_FALSE(isAlphaTested(opaque.materials[0]));
    EXPECT_THROW(loadGltf(writeQuadGltf(dir, "tex.png", "CUTOUT")), InputError);
}

TEST(AlphaMaterials, MtlDissolveTrAndMapD) {
    TempDir dir;
    // A grey coverage map (one channel, no alpha): coverage is the grey value itself.
    std::vector<std::uint8_t> grey(4 * 4 * 4, 128);
    writePng(dir, "mask.png", 4, grey, 1);
    writePng(dir, "tex.png", 16, holeTexture(16, true));
    dir.write("m.mtl",
              "newmtl solid\nKd 1 1 1\nd 1\n"
              "newmtl faded\nKd 1 1 1\nd 0.25\n"
              "newmtl tr\nKd 1 1 1\nTr 0.75\n"
              "newmtl leaf\nKd 1 1 1\nmap_d mask.png\n"
              "newmtl hole\nKd 1 1 1\nmap_Kd tex.png\nmap_d tex.png\n");
    const auto obj = dir.write("m.obj",
                               "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\n"
                               "usemtl solid\nf 1/1 2/2 3/3\nusemtl faded\nf 1/1 2/2 3/3\nusemtl tr\nf 1/1 2/2 3/3\n"
                               "usemtl leaf\nf 1/1 2/2 3/3\nusemtl hole\nf 1/1 2/2 3/3\n");
    const Scene scene = loadObj(obj);
    ASSERT_EQ(scene.materials.size(), 5u);
    EXPECT_EQ(scene.materials[0].alphaMode, AlphaMode::Opaque);
    EXPECT_EQ(scene.materials[1].alphaMode, AlphaMode::Blend);
    EXPECT_FLOAT_EQ(scene.materials[1].alpha, 0.25f);
    EXPECT_EQ(scene.materials[2].alphaMode, AlphaMode::Blend);
    EXPECT_FLOAT_EQ(scene.materials[2].alpha, 0.25f);  // Tr is 1 - d
    const Material& leaf = scene.materials[3];
    EXPECT_EQ(leaf.alphaMode, AlphaMode::Mask);
    ASSERT_GE(leaf.alphaTexture, 0);
    EXPECT_EQ(leaf.diffuseTexture, -1);
    EXPECT_NEAR(coverageAt(scene, leaf.alphaTexture, 1, 1), 128.0f / 255.0f, 1e-6f);  // data: no sRGB decode
    const Material& hole = scene.materials[4];
    ASSERT_GE(hole.alphaTexture, 0);
    ASSERT_GE(hole.diffuseTexture, 0);
    EXPECT_NE(hole.alphaTexture, hole.diffuseTexture);  // colour and coverage are cached apart
    EXPECT_FLOAT_EQ(coverageAt(scene, hole.alphaTexture, 0, 0), 1.0f);  // the PNG's alpha channel
    EXPECT_FLOAT_EQ(coverageAt(scene, hole.alphaTexture, 8, 8), 0.0f);
}

TEST(AlphaMaterials, MissingMapDWarnsAndKeepsConstantCoverage) {
    TempDir dir;
    dir.write("m.mtl", "newmtl leaf\nKd 1 1 1\nmap_d nowhere.png\n");
    const auto obj = dir.write("m.obj", "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl leaf\nf 1 2 3\n");
    ObjLoadReport report;
    const Scene scene = loadObj(obj, &report);
    EXPECT_EQ(scene.materials[0].alphaTexture, -1);
    EXPECT_FLOAT_EQ(scene.materials[0].alpha, 1.0f);
    bool named = false;
    for (const std::string& w : report.warnings) named |= w.find("nowhere.png") != std::string::npos;
    EXPECT_TRUE(named);
}

}  // namespace
}  // namespace aamap::test
