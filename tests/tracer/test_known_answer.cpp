// Known answers: radiance from analytic formulas at the exact points the tracer's rays hit.
#include <cmath>
#include <numbers>
#include <optional>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include "scene/camera.h"
#include "tests/tracer/material_scenes.h"
#include "tests/tracer/scene_builder.h"
#include "tracer/sampler.h"
#include "tracer/tracer.h"

namespace aamap {
namespace {

constexpr int kSize = 16;
constexpr float kRho = 0.5f;
constexpr std::uint64_t kSeed = 3;

using testing::lookAt;

// A large plane y = 0 facing up, in a frame scaled by `scale` and moved by `shift`.
testing::SceneBuilder planeScene(float scale = 1.0f, glm::vec3 shift = glm::vec3(0.0f)) {
    testing::SceneBuilder b;
    const auto mat = b.material("plane", glm::vec3(kRho));
    b.quad(shift + scale * glm::vec3(-50, 0, -50), scale * glm::vec3(0, 0, 100), scale * glm::vec3(100, 0, 0), mat);
    return b;
}

// Where the single (k = 1) sample of pixel (x, y) meets the plane y = planeY, replayed from the
// sampler.
std::optional<glm::dvec3> planeHit(const View& view, int x, int y, double planeY = 0.0) {
    const PinholeCamera cam = PinholeCamera::fromView(view);
    const Sampler s(static_cast<std::uint64_t>(y) * kSize + x, 0, kSeed);
    const glm::vec2 j = s.stratified2D(dims::kFilm, 0, 0, 1);
    const glm::dvec3 d(cam.direction((x + j.x) / kSize, (y + j.y) / kSize));
    if (d.y >= 0.0) return std::nullopt;
    const glm::dvec3 o(cam.origin);
    return o + ((planeY - o.y) / d.y) * d;
}

TraceResult renderOneSample(const Scene& scene, const View& view, int areaLightSamples = 16) {
    const Tracer tracer(scene);
    TraceSettings settings;
    settings.width = settings.height = kSize;
    settings.seed = kSeed;
    settings.threads = 1;
    settings.shading.areaLightSamples = areaLightSamples;
    StrategySettings strategy;
    strategy.strata = 1;
    return tracer.render(view, settings, strategy);
}

void expectClose(glm::vec3 got, glm::dvec3 want, double rel, int x, int y) {
    for (int c = 0; c < 3; ++c)
        EXPECT_NEAR(got[c], want[c], rel * want[c]) << "pixel " << x << "," << y << " channel " << c;
}

const int kPixels[][2] = {{0, 0}, {15, 0}, {8, 8}, {3, 11}, {12, 5}, {0, 15}, {15, 15}, {7, 14}};

// The same scene in any unit: scale multiplies lengths (and intensity by scale^2, so radiance is
// unchanged), shift moves everything away from the origin.
void pointLightCase(glm::vec3 lightNormal, float scale = 1.0f, glm::vec3 shift = glm::vec3(0.0f)) {
    auto b = planeScene(scale, shift);
    const glm::dvec3 lightPos = glm::dvec3(shift) + double(scale) * glm::dvec3(0.3, 2.0, -0.4);
    const glm::dvec3 intensity = double(scale) * double(scale) * glm::dvec3(10.0, 5.0, 2.5);
    b.pointLight(glm::vec3(lightPos), glm::vec3(intensity), lightNormal);
    const View view = lookAt(shift + scale * glm::vec3(0, 1.5f, 3), shift, 40);
    const TraceResult r = renderOneSample(b.scene(), view);
    for (const auto& px : kPixels) {
        const auto p = planeHit(view, px[0], px[1], shift.y);
        ASSERT_TRUE(p) << "test pixel misses the plane";
        const glm::dvec3 w = lightPos - *p;
        const double d2 = glm::dot(w, w);
        const double cosTheta = w.y / std::sqrt(d2);
        double lobe = 1.0;
        if (glm::length(lightNormal) > 0) lobe = std::max(0.0, glm::dot(glm::dvec3(lightNormal), -w / std::sqrt(d2)));
        const glm::dvec3 want = kRho / std::numbers::pi * intensity * (lobe * cosTheta / d2);
        expectClose(r.image.at(px[0], px[1]), want, 0.01, px[0], px[1]);
    }
    EXPECT_EQ(r.nonFiniteSamples, 0u);
}

TEST(KnownAnswer, PointLightOverDiffusePlane) { pointLightCase(glm::vec3(0.0f)); }

// docs/tracer.md (ray offsets): the ray offset scales with the coordinates, so a scene in millimetres or
// far from the origin shows no shadow acne and no light leaks.
TEST(KnownAnswer, PointLightSceneInMillimetresFarFromOrigin) {
    pointLightCase(glm::vec3(0.0f), 1000.0f, glm::vec3(3.0e4f, 2.0e3f, -7.0e4f));
}

TEST(KnownAnswer, PointLightSceneInKilometres) { pointLightCase(glm::vec3(0.0f), 1e-3f, glm::vec3(0.5f, 0.2f, -0.1f)); }

TEST(KnownAnswer, CosineLobePointLightOverDiffusePlane) {
    pointLightCase(glm::normalize(glm::vec3(0.2f, -1.0f, 0.1f)));
}

// Form factor from a differential area to a parallel rectangle [0,X] x [0,Y] (in units of the
// height) whose corner is straight above it; odd in X and in Y, so rectangles anywhere follow by
// superposition.
double cornerFormFactor(double X, double Y) {
    const double a = std::sqrt(1 + X * X), b = std::sqrt(1 + Y * Y);
    return (X / a * std::atan(Y / a) + Y / b * std::atan(X / b)) / (2 * std::numbers::pi);
}

TEST(KnownAnswer, QuadAreaLightMatchesRectangleFormFactor) {
    auto b = planeScene();
    const double h = 1.0, x0 = -0.5, x1 = 0.7, z0 = -0.6, z1 = 0.4;
    const glm::dvec3 radiance(4.0, 2.0, 1.0);
    b.areaLightQuad(glm::vec3(x0, h, z0), glm::vec3(x1 - x0, 0, 0), glm::vec3(0, 0, z1 - z0), glm::vec3(radiance));
    const View view = lookAt({0, 0.9f, 2.5f}, {0, 0, 0}, 30);
    const TraceResult r = renderOneSample(b.scene(), view, 256);
    double nearest = 1e9;
    for (const auto& px : kPixels) {
        const auto p = planeHit(view, px[0], px[1]);
        ASSERT_TRUE(p);
        nearest = std::min(nearest, std::hypot(p->x, p->z));
        const auto f = [&](double x, double z) { return cornerFormFactor((x - p->x) / h, (z - p->z) / h); };
        const double F = f(x1, z1) - f(x0, z1) - f(x1, z0) + f(x0, z0);
        // Lambert: L_out = rho / pi * E, and E = pi * L * F.
        expectClose(r.image.at(px[0], px[1]), double(kRho) * radiance * F, 0.01, px[0], px[1]);
    }
    EXPECT_LT(nearest, 0.1) << "one test pixel should sit (nearly) straight below the light";
}

TEST(KnownAnswer, FrontOfEmitterShowsKeAndBackIsShadedAsSurface) {
    testing::SceneBuilder b;
    const glm::vec3 ke(3.0f, 2.0f, 1.0f);
    b.areaLightQuad({-5, 1, -5}, {10, 0, 0}, {0, 0, 10}, ke, glm::vec3(0.5f));  // faces down
    b.pointLight({0, 3, 0}, glm::vec3(9.0f));
    const Tracer tracer(b.scene());
    TraceSettings settings;
    settings.width = settings.height = 4;
    settings.threads = 1;
    StrategySettings strategy;
    const TraceResult below = tracer.render(lookAt({0, 0, 0}, {0, 1, 0.001f}, 20), settings, strategy);
    for (const glm::vec3& c : below.image.pixels()) EXPECT_EQ(c, ke);
    EXPECT_EQ(below.rays.shadow, 0u);  // the emitter's front is not shaded
    const TraceResult above = tracer.render(lookAt({0, 2, 0}, {0, 1, 0.001f}, 20), settings, strategy);
    for (const glm::vec3& c : above.image.pixels()) {
        EXPECT_GT(c.x, 0.0f);
        EXPECT_NEAR(c.x, 0.5 / std::numbers::pi * 9.0 / 4.0, 0.03);  // back side: diffuse kd under the point light
    }
}

}  // namespace
}  // namespace aamap
