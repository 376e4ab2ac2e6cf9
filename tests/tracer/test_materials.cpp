// Materials with analytic answers: mirrors, a glass slab (Fresnel), textures, and the feature
// switches that keep unused code paths out of a scene.
#include <cmath>
#include <numbers>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include "scene/camera.h"
#include "tests/tracer/material_scenes.h"
#include "tracer/embree_scene.h"
#include "tracer/sampler.h"

namespace aamap {
namespace {

using testing::lookAt;
using testing::renderScene;

ShadingSettings mode(ShadingMode m) {
    ShadingSettings s;
    s.mode = m;
    return s;
}

// Camera at the origin looking +z at a mirror; an emitter behind the camera faces it. Seen via a
// mirror of reflectance ks the emitter shows ks * Le: a perfect mirror (ks = 1) conserves energy.
TEST(Mirror, ReflectsAnEmitterWithItsReflectance) {
    for (float ks : {1.0f, 0.9f}) {
        for (ShadingMode m : {ShadingMode::Direct, ShadingMode::Path}) {
            testing::SceneBuilder b;
            const auto mirror = testing::addMaterial(b, testing::mirrorMaterial(glm::vec3(ks)));
            b.quad({-50, -50, 2}, {0, 100, 0}, {100, 0, 0}, mirror);  // faces -z
            const glm::vec3 le(2.0f, 1.0f, 0.5f);
            b.areaLightQuad({-50, -50, -5}, {100, 0, 0}, {0, 100, 0}, le);  // faces +z
            const View direct = lookAt({0, 0, 0}, {0, 0, -1}, 30);
            const View viaMirror = lookAt({0, 0, 0}, {0, 0, 1}, 30);
            const TraceResult seen = renderScene(b.scene(), direct, mode(m), 8, 1);
            const TraceResult reflected = renderScene(b.scene(), viaMirror, mode(m), 8, 1);
            for (std::size_t i = 0; i < seen.image.pixels().size(); ++i)
                for (int c = 0; c < 3; ++c) {
                    EXPECT_FLOAT_EQ(seen.image.pixels()[i][c], le[c]);
                    EXPECT_NEAR(reflected.image.pixels()[i][c], ks * seen.image.pixels()[i][c], 1e-6f * le[c])
                        << "ks " << ks << " mode " << toString(m);
                }
        }
    }
}

// A mirror floor under a diffuse ceiling lit by a point light: each pixel shows the ceiling point
// that the reflected camera ray reaches, with radiance rho / pi * I cos / d^2 (Direct mode).
TEST(Mirror, ShowsTheReflectedSceneKnownAnswer) {
    constexpr int kSize = 16;
    testing::SceneBuilder b;
    const auto mirror = testing::addMaterial(b, testing::mirrorMaterial(glm::vec3(1.0f)));
    const float rho = 0.5f;
    const auto ceiling = b.material("ceiling", glm::vec3(rho));
    b.quad({-50, 0, -50}, {0, 0, 100}, {100, 0, 0}, mirror);   // y = 0, faces up
    b.quad({-50, 2, -50}, {100, 0, 0}, {0, 0, 100}, ceiling);  // y = 2, faces down
    const glm::dvec3 light(0.3, 1.0, -0.4), intensity(10.0, 5.0, 2.5);
    b.pointLight(glm::vec3(light), glm::vec3(intensity));
    const View view = lookAt({0, 0.5f, 3}, {0, 0, 0}, 40);
    const std::uint64_t seed = 9;
    const TraceResult r = renderScene(b.scene(), view, mode(ShadingMode::Direct), kSize, 1, 1, seed);
    const PinholeCamera cam = PinholeCamera::fromView(view);
    int checked = 0;
    for (int y = 0; y < kSize; ++y)
        for (int x = 0; x < kSize; ++x) {
            const Sampler s(static_cast<std::uint64_t>(y) * kSize + x, 0, seed);
            const glm::vec2 j = s.stratified2D(dims::kFilm, 0, 0, 1);
            const glm::dvec3 d = glm::normalize(glm::dvec3(cam.direction((x + j.x) / kSize, (y + j.y) / kSize)));
            if (d.y > -0.02) continue;  // sees the ceiling directly (or grazes the mirror)
            const glm::dvec3 o(cam.origin);
            const glm::dvec3 p0 = o + (-o.y / d.y) * d;
            const glm::dvec3 r1(d.x, -d.y, d.z);
            const glm::dvec3 p1 = p0 + (2.0 / r1.y) * r1;
            if (std::abs(p1.x) > 40 || std::abs(p1.z) > 40) continue;  // past the ceiling's edge
            const glm::dvec3 w = light - p1;
            const double d2 = glm::dot(w, w);
            const glm::dvec3 want = rho / std::numbers::pi * intensity * ((p1.y - light.y) / std::sqrt(d2) / d2);
            for (int c = 0; c < 3; ++c) EXPECT_NEAR(r.image.at(x, y)[c], want[c], 1e-3 * want[c]) << x << "," << y;
            ++checked;
        }
    EXPECT_GT(checked, kSize * kSize / 3);
}

// A glass slab (ior 1.5, 1 unit thick) between the camera and an emitter of radiance 1, viewed at
// normal incidence (1 degree field of view: cos > 0.99996, so R stays 0.04 to 1e-6). Each face
// transmits 1 - R with R = ((n - 1) / (n + 1))^2. What reaches the camera:
// - single pass, T = (1 - R)^2, when at most 3 specular events are followed (the first internal
//   reflection path has 4: transmit, reflect, reflect, transmit);
// - all internal reflections, T = (1 - R)^2 / (1 - R^2) = (1 - R) / (1 + R); Direct mode drops
//   branches below weight 1e-3, which here loses the terms from 2 round trips on: < 3e-6.
struct SlabScene {
    Scene scene;
    View view = lookAt({0, 0, 5}, {0, 0, 0}, 1.0f);
    static constexpr double R = 0.04;
    SlabScene() {
        testing::SceneBuilder b;
        const auto glass = testing::addMaterial(b, testing::glassMaterial(1.5f));
        b.box({-10, -10, -0.5f}, {10, 10, 0.5f}, glass);
        b.areaLightQuad({-20, -20, -3}, {40, 0, 0}, {0, 40, 0}, glm::vec3(1.0f));  // faces +z
        scene = std::move(b.scene());
    }
};

TEST(GlassSlab, SinglePassTransmissionIsFresnelSquared) {
    SlabScene s;
    ShadingSettings sh = mode(ShadingMode::Direct);
    sh.maxSpecularDepth = 3;
    const TraceResult r = renderScene(s.scene, s.view, sh, 4, 1);
    for (const glm::vec3& c : r.image.pixels()) EXPECT_NEAR(c.x, (1 - s.R) * (1 - s.R), 1e-5);
}

TEST(GlassSlab, MultipleInternalReflectionsSumToOneMinusROverOnePlusR) {
    SlabScene s;
    ShadingSettings sh = mode(ShadingMode::Direct);
    sh.maxSpecularDepth = 16;
    const TraceResult r = renderScene(s.scene, s.view, sh, 4, 1);
    for (const glm::vec3& c : r.image.pixels()) EXPECT_NEAR(c.x, (1 - s.R) / (1 + s.R), 1e-5);
}

// Path mode picks one Fresnel branch per event: each sample is 0 or 1, so the image mean is a
// binomial estimate of (1 - R) / (1 + R); tolerance 4 standard errors.
TEST(GlassSlab, PathModeAgreesWithinItsStandardError) {
    SlabScene s;
    ShadingSettings sh = mode(ShadingMode::Path);
    sh.maxDepth = 64;
    const int size = 16, strata = 4;
    const TraceResult r = renderScene(s.scene, s.view, sh, size, strata);
    std::vector<double> v;
    for (const glm::vec3& c : r.image.pixels()) v.push_back(c.x);
    const double want = (1 - s.R) / (1 + s.R);
    const double n = size * size * strata * strata;
    const double error = std::sqrt(want * (1 - want) / n);
    EXPECT_NEAR(testing::meanError(v).mean, want, 4 * error);
}

// A textured quad (16 x 16 texels in four colour blocks) under a point light, against the same
// quad untextured with kd = 1: the ratio is the texel colour at the pixel's uv. The uv comes from
// replaying the camera ray, with v = 0 on the texture's top row.
TEST(Texture, ShowsTheTexelColourAtKnownUvs) {
    constexpr int kSize = 16;
    const glm::vec3 colours[2][2] = {{{0.9f, 0.1f, 0.1f}, {0.1f, 0.8f, 0.2f}}, {{0.2f, 0.3f, 0.9f}, {0.7f, 0.7f, 0.1f}}};
    Texture tex;
    tex.width = tex.height = 16;
    for (int y = 0; y < 16; ++y)
        for (int x = 0; x < 16; ++x) {
            const glm::vec3 c = colours[y / 8][x / 8];  // [row block][column block]
            tex.rgba.insert(tex.rgba.end(), {c.x, c.y, c.z, 1.0f});
        }
    const auto build = [&](bool textured) {
        testing::SceneBuilder b;
        const auto mat = b.material("quad", glm::vec3(1.0f));
        if (textured) b.scene().materials[mat].diffuseTexture = 0;
        b.scene().textures.push_back(tex);
        // Quad (-1,0,-1) + s (2,0,0) + t (0,0,2), facing up; uv = (s, t).
        b.quad({-1, 0, -1}, {0, 0, 2}, {2, 0, 0}, mat);
        b.scene().mesh.uvs = {{0, 0}, {0, 1}, {1, 1}, {1, 0}};
        b.pointLight({0.2f, 3, 0.1f}, glm::vec3(20.0f));
        return std::move(b.scene());
    };
    const View view = lookAt({0, 2, 0}, {0, 0, 0}, 50, {0, 0, -1});
    // The texel rule itself, so the point lookup: a filtered one also averages over the pixel's
    // footprint (about a texel here), tested in test_texture_filtering.cpp.
    ShadingSettings pointLookup = mode(ShadingMode::Direct);
    pointLookup.textureFilter = TextureFilter::None;
    const TraceResult tex1 = renderScene(build(true), view, pointLookup, kSize, 1, 1, 4);
    const TraceResult white = renderScene(build(false), view, mode(ShadingMode::Direct), kSize, 1, 1, 4);
    const PinholeCamera cam = PinholeCamera::fromView(view);
    int checked = 0;
    for (int y = 0; y < kSize; ++y)
        for (int x = 0; x < kSize; ++x) {
            const Sampler s(static_cast<std::uint64_t>(y) * kSize + x, 0, 4);
            const glm::vec2 j = s.stratified2D(dims::kFilm, 0, 0, 1);
            const glm::dvec3 d(cam.direction((x + j.x) / kSize, (y + j.y) / kSize));
            const glm::dvec3 p = glm::dvec3(cam.origin) + (-cam.origin.y / d.y) * d;
            const double u = (p.x + 1) / 2, v = (p.z + 1) / 2;
            // Skip the blocks' borders (bilinear filtering blends within half a texel) and the edge.
            const auto inner = [](double t) { return t > 0.04 && t < 0.96 && std::abs(t - 0.5) > 0.04; };
            if (!inner(u) || !inner(v)) continue;
            const glm::vec3 want = colours[v < 0.5 ? 0 : 1][u < 0.5 ? 0 : 1];
            for (int c = 0; c < 3; ++c)
                EXPECT_NEAR(tex1.image.at(x, y)[c], want[c] * white.image.at(x, y)[c], 1e-5 + 1e-5 * white.image.at(x, y)[c])
                    << x << "," << y << " uv " << u << "," << v;
            ++checked;
        }
    EXPECT_GT(checked, 100);
}

// Only what a scene requires: features follow the materials that triangles use.
TEST(Features, FollowTheMaterialsInUse) {
    testing::SceneBuilder b;
    const auto plain = b.material("plain", glm::vec3(0.5f));
    const auto unusedGlass = testing::addMaterial(b, testing::glassMaterial(1.5f));
    (void)unusedGlass;
    b.quad({0, 0, 0}, {1, 0, 0}, {0, 0, 1}, plain);
    {
        const EmbreeScene g(b.scene());
        EXPECT_FALSE(g.features().glass) << "an unused glass material must not enable the glass path";
        EXPECT_FALSE(g.features().textures);
        EXPECT_FALSE(g.features().glossy);
        EXPECT_FALSE(g.features().mirror);
    }
    Material shiny;
    shiny.name = "shiny";
    shiny.kd = glm::vec3(0.7f);
    shiny.ks = glm::vec3(0.6f);
    shiny.ns = 20;
    b.quad({0, 1, 0}, {1, 0, 0}, {0, 0, 1}, testing::addMaterial(b, shiny));
    const EmbreeScene g(b.scene());
    EXPECT_TRUE(g.features().glossy);
    // kd + ks = 1.3 > 1: scaled to conserve energy.
    const ShadingMaterial& m = g.material(static_cast<std::uint32_t>(b.scene().materials.size() - 1));
    EXPECT_NEAR(m.kd.x + m.ks.x, 1.0f, 1e-6f);
}

}  // namespace
}  // namespace aamap
