// White furnace under a constant environment L (tracer/environment.h). What each shading mode
// must give for a Lambertian surface of albedo a:
// - a convex object (every hemisphere ray leaves the scene): a L in every mode. Direct: the
//   environment's direct light alone is a L; Cache: the same, plus indirect irradiance from
//   hemisphere rays that all escape (the environment is direct light there, so they bring 0);
//   Path: the first bounce escapes with weight a. With BSDF sampling of the constant sky each
//   sample is exactly a L, so even one ray per pixel is noise-free.
// - a concave object: Direct gives a L F, F the cosine-weighted fraction of the sky the point
//   sees (its view factor to the opening); Path with albedo 1 gives L everywhere (the furnace's
//   equilibrium); Cache lies between (Direct plus the cached bounces, all non-negative).
// Rays that miss everything return L exactly, camera rays included.
#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include "tests/tracer/material_scenes.h"

namespace aamap {
namespace {

using testing::lookAt;
using testing::renderScene;

const glm::vec3 kSky(0.5f, 1.0f, 2.0f);

void addSky(Scene& scene, glm::vec3 radiance) {
    EnvironmentLight env;
    env.name = "sky";
    env.scale = radiance;
    scene.environment = env;
}

ShadingSettings modeSettings(ShadingMode mode) {
    ShadingSettings s;
    s.mode = mode;
    return s;
}

// Every pixel of a one-ray-per-pixel render is the sky exactly or a L (to float rounding); both occur.
void expectSkyOrAlbedoTimesSky(const TraceResult& r, float albedo, const char* what) {
    int sky = 0, surface = 0;
    for (const glm::vec3& c : r.image.pixels()) {
        if (c == kSky) {
            ++sky;
            continue;
        }
        ++surface;
        for (int ch = 0; ch < 3; ++ch) ASSERT_NEAR(c[ch], albedo * kSky[ch], 1e-4f * kSky[ch]) << what << " channel " << ch;
    }
    EXPECT_GT(sky, 50) << what;
    EXPECT_GT(surface, 200) << what;
    EXPECT_EQ(r.nonFiniteSamples, 0u) << what;
}

TEST(Furnace, ConvexBoxUnderConstantSkyIsAlbedoTimesSkyInEveryMode) {
    const float a = 0.6f;
    testing::SceneBuilder b;
    b.box({-0.5f, -0.4f, -0.3f}, {0.5f, 0.4f, 0.3f}, b.material("white", glm::vec3(a)));
    addSky(b.scene(), kSky);
    const View view = lookAt({1.6f, 1.3f, 2.0f}, {0, 0, 0}, 45);
    for (ShadingMode mode : {ShadingMode::Direct, ShadingMode::Cache, ShadingMode::Path})
        expectSkyOrAlbedoTimesSky(renderScene(b.scene(), view, modeSettings(mode), 48, 1), a, toString(mode));
}

TEST(Furnace, OpenQuadSeenFromBothSidesIsAlbedoTimesSky) {
    const float a = 0.35f;
    testing::SceneBuilder b;
    b.quad({-1, 0, -1}, {0, 0, 2}, {2, 0, 0}, b.material("white", glm::vec3(a)));  // faces +y
    addSky(b.scene(), kSky);
    for (const glm::vec3 eye : {glm::vec3(0.3f, 1.5f, 2.0f), glm::vec3(0.3f, -1.5f, 2.0f)})
        for (ShadingMode mode : {ShadingMode::Direct, ShadingMode::Cache, ShadingMode::Path})
            expectSkyOrAlbedoTimesSky(renderScene(b.scene(), lookAt(eye, {0, 0, 0}, 60), modeSettings(mode), 48, 1), a,
                                      toString(mode));
}

// Smooth plastic over a white (linear) base conserves energy exactly (its coating reflects F, the
// base sends out 1 - F through it: tracer/bsdf.h), so a convex box of it under a constant sky
// is the sky on average in every mode: path mode through the delta lobe's and the base's
// sampling weights, direct and cache modes through the environment's BSDF samples and the
// coating's specular branch. The view sees the box only.
TEST(Furnace, WhiteSmoothPlasticBoxIsTheSkyOnAverageInEveryMode) {
    testing::SceneBuilder b;
    Material m;
    m.name = "white plastic";
    m.model = BsdfModel::Plastic;
    m.kd = glm::vec3(1.0f);
    m.ior = 1.5f;
    b.box({-0.5f, -0.4f, -0.3f}, {0.5f, 0.4f, 0.3f}, testing::addMaterial(b, m));
    addSky(b.scene(), kSky);
    const View view = lookAt({1.6f, 1.3f, 2.0f}, {0, 0, 0}, 10);
    for (ShadingMode mode : {ShadingMode::Direct, ShadingMode::Cache, ShadingMode::Path}) {
        ShadingSettings s = modeSettings(mode);
        s.areaLightSamples = 64;
        const TraceResult r = renderScene(b.scene(), view, s, 24, 6);
        for (int c = 0; c < 3; ++c) {
            std::vector<double> v;
            for (const glm::vec3& p : r.image.pixels()) v.push_back(p[c] / kSky[c]);
            const auto [mean, error] = testing::meanError(v);
            EXPECT_NEAR(mean, 1.0, 4 * error + 5e-3) << toString(mode) << " channel " << c;
        }
        EXPECT_EQ(r.nonFiniteSamples, 0u) << toString(mode);
    }
}

// A closed box of nearly smooth rough glass (GGX alpha 0.1) under a constant sky: every path
// leaves through the interfaces sooner or later, so path mode gives the sky less only what
// single-scattering microfacets lose at each crossing (a few per cent), never more than the sky.
TEST(Furnace, RoughGlassBoxLosesOnlyMicrofacetEnergyInPathMode) {
    testing::SceneBuilder b;
    Material m;
    m.name = "rough glass";
    m.kind = MaterialKind::Glass;
    m.model = BsdfModel::Dielectric;
    m.distribution = MicrofacetType::GGX;
    m.alphaU = m.alphaV = 0.1f;
    m.ior = 1.5f;
    m.ks = glm::vec3(1.0f);
    m.kd = glm::vec3(0.0f);
    b.box({-0.5f, -0.4f, -0.3f}, {0.5f, 0.4f, 0.3f}, testing::addMaterial(b, m));
    addSky(b.scene(), kSky);
    ShadingSettings s = modeSettings(ShadingMode::Path);
    s.maxDepth = 64;
    const TraceResult r = renderScene(b.scene(), lookAt({1.6f, 1.3f, 2.0f}, {0, 0, 0}, 10), s, 24, 6);
    for (int c = 0; c < 3; ++c) {
        std::vector<double> v;
        for (const glm::vec3& p : r.image.pixels()) v.push_back(p[c] / kSky[c]);
        const auto [mean, error] = testing::meanError(v);
        EXPECT_LT(mean, 1.0 + 4 * error) << "channel " << c;
        EXPECT_GT(mean, 0.9) << "channel " << c;
    }
    EXPECT_EQ(r.nonFiniteSamples, 0u);
}

// A square well (floor 2 x 2, walls 1 high, open at the top), seen straight down through a
// narrow view of the floor's centre.
Scene well(float albedo) {
    testing::SceneBuilder b;
    const auto m = b.material("white", glm::vec3(albedo));
    const glm::vec3 X(2, 0, 0), Y(0, 1, 0), Z(0, 0, 2), o(-1, 0, -1);
    b.quad(o, Z, X, m);      // floor
    b.quad(o, X, Y, m);      // walls (surfaces are two-sided)
    b.quad(o + Z, X, Y, m);
    b.quad(o, Y, Z, m);
    b.quad(o + X, Y, Z, m);
    addSky(b.scene(), kSky);
    return std::move(b.scene());
}

View wellView() { return lookAt({0, 3, 0}, {0, 0, 0}, 1.0f, {0, 0, -1}); }

// View factor from a differential area to a parallel rectangle a x b at height c over one corner:
// (1 / 2 pi) [X / sqrt(1 + X^2) atan(Y / sqrt(1 + X^2)) + Y / sqrt(1 + Y^2) atan(X / sqrt(1 + Y^2))].
double cornerViewFactor(double a, double b, double c) {
    const double X = a / c, Y = b / c;
    const double sx = std::sqrt(1 + X * X), sy = std::sqrt(1 + Y * Y);
    return (X / sx * std::atan(Y / sx) + Y / sy * std::atan(X / sy)) / (2 * std::numbers::pi);
}

TEST(Furnace, DirectInAWellIsAlbedoTimesSkyTimesTheOpeningsViewFactor) {
    const float a = 0.5f;
    const double F = 4 * cornerViewFactor(1.0, 1.0, 1.0);  // four quarters of the opening: 0.554
    ShadingSettings s = modeSettings(ShadingMode::Direct);
    s.areaLightSamples = 256;
    const TraceResult r = renderScene(well(a), wellView(), s, 24, 1);
    for (int ch = 0; ch < 3; ++ch) {
        std::vector<double> v;
        for (const glm::vec3& c : r.image.pixels()) v.push_back(c[ch]);
        const auto [mean, error] = testing::meanError(v);
        const double want = a * kSky[ch] * F;
        EXPECT_LT(4 * error, 0.01 * want) << "too few samples for a 1% test";
        EXPECT_NEAR(mean, want, 4 * error + 2e-3 * want) << "channel " << ch;
    }
}

TEST(Furnace, PathInAWhiteWellIsTheSkyAndCacheLiesBetweenDirectAndIt) {
    ShadingSettings path = modeSettings(ShadingMode::Path);
    path.maxDepth = 1000;  // Russian roulette ends the paths
    const Scene scene = well(1.0f);
    const TraceResult p = renderScene(scene, wellView(), path, 24, 4);
    std::vector<double> v;
    for (const glm::vec3& c : p.image.pixels()) v.push_back(c.y);
    const auto [mean, error] = testing::meanError(v);
    EXPECT_LT(4 * error, 0.02 * kSky.y) << "too few samples for a 2% test";
    EXPECT_NEAR(mean, kSky.y, 4 * error + 1e-3);

    ShadingSettings direct = modeSettings(ShadingMode::Direct);
    direct.areaLightSamples = 64;
    ShadingSettings cache = modeSettings(ShadingMode::Cache);
    cache.areaLightSamples = 64;
    const TraceResult d = renderScene(scene, wellView(), direct, 24, 1);
    const TraceResult c = renderScene(scene, wellView(), cache, 24, 1);
    double sumD = 0, sumC = 0;
    for (std::size_t i = 0; i < d.image.pixels().size(); ++i) {
        sumD += d.image.pixels()[i].y;
        sumC += c.image.pixels()[i].y;
    }
    const double n = static_cast<double>(d.image.pixels().size());
    EXPECT_GT(sumC / n, 1.1 * sumD / n);  // the cached bounce adds light ...
    EXPECT_LT(sumC / n, mean + 4 * error);  // ... but not more than all bounces
}

}  // namespace
}  // namespace aamap
