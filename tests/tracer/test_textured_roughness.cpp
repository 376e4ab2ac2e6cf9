// Textured roughness (Mitsuba's `alpha` as a texture on roughconductor / roughplastic): where the
// texture is constant, a hit shades as the untextured BSDF with that alpha.
#include <cmath>
#include <vector>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include "tests/tracer/material_scenes.h"
#include "tests/tracer/scene_builder.h"
#include "tracer/tracer.h"

namespace aamap {
namespace {

constexpr int kRoughSize = 16;

// A 2 x 2 quad at y = 0 facing up (u along +x, v along +z), under a directional light, seen from
// above: the view spans about 2.1 units, so every u from 0 to 1 shows.
Scene quadScene(BsdfModel model, float alpha, int roughnessTexture, std::vector<Texture> textures) {
    testing::SceneBuilder b;
    const auto mat = b.material("rough", glm::vec3(0.4f, 0.5f, 0.6f));
    b.quad(glm::vec3(-1, 0, -1), glm::vec3(0, 0, 2), glm::vec3(2, 0, 0), mat);
    Scene s = std::move(b.scene());
    s.mesh.uvs = {{0, 0}, {0, 1}, {1, 1}, {1, 0}};
    s.textures = std::move(textures);
    Material& m = s.materials[0];
    m.model = model;
    m.distribution = MicrofacetType::GGX;
    m.alphaU = m.alphaV = alpha;
    m.roughnessTexture = roughnessTexture;
    m.eta = glm::vec3(0.2f, 0.9f, 1.1f);
    m.k = glm::vec3(3.9f, 2.4f, 2.1f);
    m.ior = 1.5f;
    DirectionalLight d;
    d.direction = glm::normalize(glm::vec3(-0.3f, -1.0f, 0.1f));
    d.irradiance = glm::vec3(3.0f);
    s.directionalLights.push_back(d);
    return s;
}

// 8 x 1 texels: the left four at `left`, the right four at `right` (grey, exact floats).
Texture halves(float left, float right) {
    Texture t;
    t.path = "halves";
    t.width = 8;
    t.height = 1;
    for (int i = 0; i < 8; ++i) {
        const float a = i < 4 ? left : right;
        t.rgba.insert(t.rgba.end(), {a, a, a, 1.0f});
    }
    return t;
}

ImageRGB renderRough(const Scene& scene, ShadingMode mode) {
    View v;
    v.position = {0.0f, 4.0f, 0.0f};
    v.direction = {0.0f, -1.0f, 0.0f};
    v.up = {0, 0, -1};
    v.horizontalFovDeg = v.verticalFovDeg = 30.0f;
    ShadingSettings shading;
    shading.mode = mode;
    shading.maxDepth = 2;
    return testing::renderScene(scene, v, shading, kRoughSize, 1, 1, 9).image;
}

// The image column x shows u = (x + 0.5) / kRoughSize * 2.14 / 2 + 0.5 - 1.07 / 2 (about): columns 3-5
// lie in the left half's constant run (u 0.06-0.44), columns 10-12 in the right half's (0.56-0.94).
TEST(TexturedRoughness, ConstantRunsShadeAsTheUntexturedBsdf) {
    for (BsdfModel model : {BsdfModel::Conductor, BsdfModel::Plastic}) {
        for (ShadingMode mode : {ShadingMode::Direct, ShadingMode::Path}) {
            const float lo = 0.05f, hi = 0.5f;
            const ImageRGB textured = renderRough(quadScene(model, 0.3f, 0, {halves(lo, hi)}), mode);
            const ImageRGB left = renderRough(quadScene(model, lo, -1, {}), mode);
            const ImageRGB right = renderRough(quadScene(model, hi, -1, {}), mode);
            double differs = 0.0;
            for (int y = 2; y < kRoughSize - 2; ++y) {
                for (int x : {3, 4, 5, 10, 11, 12}) {
                    const glm::vec3 want = (x < 8 ? left : right).at(x, y);
                    for (int c = 0; c < 3; ++c)
                        ASSERT_NEAR(textured.at(x, y)[c], want[c], 2e-4f * std::max(want[c], 1e-3f))
                            << (model == BsdfModel::Conductor ? "conductor " : "plastic ") << toString(mode) << " pixel "
                            << x << "," << y;
                    differs += std::abs(left.at(x, y).x - right.at(x, y).x);
                }
            }
            EXPECT_GT(differs, 0.1) << "the two roughnesses must shade differently for the test to mean anything";
        }
    }
}

TEST(TexturedRoughness, ConstantTextureEqualsItsAlpha) {
    for (BsdfModel model : {BsdfModel::Conductor, BsdfModel::Plastic}) {
        const ImageRGB textured = renderRough(quadScene(model, 0.1f, 0, {halves(0.25f, 0.25f)}), ShadingMode::Direct);
        const ImageRGB plain = renderRough(quadScene(model, 0.25f, -1, {}), ShadingMode::Direct);
        for (int y = 0; y < kRoughSize; ++y)
            for (int x = 0; x < kRoughSize; ++x)
                for (int c = 0; c < 3; ++c)
                    ASSERT_NEAR(textured.at(x, y)[c], plain.at(x, y)[c], 2e-4f * std::max(plain.at(x, y)[c], 1e-3f))
                        << "pixel " << x << "," << y;
    }
}

}  // namespace
}  // namespace aamap
