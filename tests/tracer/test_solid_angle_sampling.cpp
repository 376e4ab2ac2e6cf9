// Area lights sampled by solid angle: the spherical triangle's measure and its uniform sampling,
// the per-receiver choice between solid angle and area, and the estimator against the analytic
// irradiance under a large light close to the receiver.
#include <cmath>
#include <numbers>
#include <vector>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include "tests/tracer/scene_builder.h"
#include "tracer/embree_scene.h"
#include "tracer/lights.h"
#include "tracer/sampler.h"
#include "tracer/spherical_triangle.h"

namespace aamap {
namespace {


TEST(SphericalTriangle, OctantIsAnEighthOfTheSphereAtAnyScale) {
    for (float scale : {1e-3f, 1.0f, 1e4f}) {
        const glm::vec3 a(scale, 0, 0), b(0, scale, 0), c(0, 0, scale);
        EXPECT_NEAR(triangleSolidAngle(a, b, c), std::numbers::pi / 2, 1e-6) << scale;
        SphericalTriangle s;
        ASSERT_TRUE(s.setup(a, b, c));
        EXPECT_NEAR(s.area(), std::numbers::pi / 2, 1e-5) << scale;
    }
}

TEST(SphericalTriangle, SmallTriangleSubtendsItsAreaOverDistanceSquared) {
    // A triangle of area 0.5e-6 facing the receiver at distance 10: omega = A / d^2 to first order.
    const glm::vec3 a(0, 0, 10), b(1e-3f, 0, 10), c(0, 1e-3f, 10);
    EXPECT_NEAR(triangleSolidAngle(a, b, c), 0.5e-6 / 100.0, 1e-12);
}

TEST(SphericalTriangle, DegenerateTrianglesAreRefused) {
    SphericalTriangle s;
    EXPECT_FALSE(s.setup({1, 0, 0}, {2, 0, 0}, {0, 1, 0}));   // two vertices in one direction
    EXPECT_FALSE(s.setup({1, 0, 0}, {2, 1, 0}, {1, 1, 0}));   // in one plane with the receiver
    EXPECT_EQ(triangleSolidAngle({1, 0, 0}, {0, 1, 0}, {-1, 1, 0}), 0.0f);
}

// Directions land inside the triangle, unit, and in each quarter of it (split at the edge
// midpoints) in proportion to the quarter's own solid angle.
TEST(SphericalTriangle, SamplesAreUniformInSolidAngle) {
    // Large and lopsided as seen from the origin: area sampling would be far from uniform here.
    const glm::vec3 v0(-0.3f, -0.2f, 0.25f), v1(1.5f, -0.1f, 0.6f), v2(0.1f, 1.2f, 0.2f);
    const glm::vec3 e1 = v1 - v0, e2 = v2 - v0, n = glm::normalize(glm::cross(e1, e2));
    SphericalTriangle s;
    ASSERT_TRUE(s.setup(v0, v1, v2));
    const double total = triangleSolidAngle(v0, v1, v2);
    const glm::vec3 m01 = 0.5f * (v0 + v1), m12 = 0.5f * (v1 + v2), m02 = 0.5f * (v0 + v2);
    const double quarters[4] = {triangleSolidAngle(v0, m01, m02), triangleSolidAngle(m01, v1, m12),
                                triangleSolidAngle(m02, m12, v2), triangleSolidAngle(m01, m12, m02)};
    EXPECT_NEAR(quarters[0] + quarters[1] + quarters[2] + quarters[3], total, 1e-5 * total);

    constexpr int kGrid = 256;
    int counts[4] = {0, 0, 0, 0};
    for (int y = 0; y < kGrid; ++y)
        for (int x = 0; x < kGrid; ++x) {
            const glm::vec3 d = s.sample({(x + 0.5f) / kGrid, (y + 0.5f) / kGrid});
            ASSERT_NEAR(glm::length(d), 1.0f, 1e-5f);
            // Barycentrics of where the direction meets the triangle's plane.
            const float t = glm::dot(n, v0) / glm::dot(n, d);
            ASSERT_GT(t, 0.0f);
            const glm::vec3 w = t * d - v0;
            const float d11 = glm::dot(e1, e1), d12 = glm::dot(e1, e2), d22 = glm::dot(e2, e2);
            const float det = d11 * d22 - d12 * d12;
            const float u = (d22 * glm::dot(w, e1) - d12 * glm::dot(w, e2)) / det;
            const float v = (d11 * glm::dot(w, e2) - d12 * glm::dot(w, e1)) / det;
            ASSERT_GE(u, -1e-4f);
            ASSERT_GE(v, -1e-4f);
            ASSERT_LE(u + v, 1.0f + 1e-4f);
            const int quarter = u + v < 0.5f ? 0 : u > 0.5f ? 1 : v > 0.5f ? 2 : 3;
            ++counts[quarter];
        }
    for (int q = 0; q < 4; ++q)
        EXPECT_NEAR(counts[q] / double(kGrid * kGrid), quarters[q] / total, 2e-3) << "quarter " << q;
}

// A unit square light facing down at height h over the origin, in a scene of its own.
struct SquareLight {
    testing::SceneBuilder builder;
    EmbreeScene geometry;
    AreaLightSampler light;
    explicit SquareLight(float h)
        : builder(make(h)), geometry(builder.scene()), light(builder.scene().areaLights[0], geometry) {}
    static testing::SceneBuilder make(float h) {
        testing::SceneBuilder b;
        b.areaLightQuad({-0.5f, h, -0.5f}, {1, 0, 0}, {0, 0, 1}, glm::vec3(1.0f));  // faces down
        return b;
    }
};

// Irradiance at the origin (normal +y) from a unit-radiance square [-0.5, 0.5]^2 at height h:
// E = pi F, with the form factor of a parallel rectangle by superposition of corner rectangles.
double squareIrradiance(double h) {
    const double X = 0.5 / h, a = std::sqrt(1 + X * X);
    const double corner = (2 * X / a * std::atan(X / a)) / (2 * std::numbers::pi);
    return std::numbers::pi * 4 * corner;
}

// The stratified m x m estimate of irradiance at the origin, under `sampling`, for one seed.
double estimateIrradiance(const AreaLightSampler& light, bool bySolidAngle, int m, std::uint64_t seed) {
    const glm::vec3 p(0.0f), n(0, 1, 0);
    LightView view = light.view(p, bySolidAngle);
    const Sampler sampler(0, 0, seed);
    const float invM = 1.0f / static_cast<float>(m);
    double sum = 0.0;
    for (int j = 0; j < m * m; ++j) {
        const LightPoint q = light.sample(view, p, sampler.jittered2D(1 + static_cast<std::uint64_t>(j), j % m, j / m, invM));
        const glm::vec3 w = q.position - p;
        const float d2 = glm::dot(w, w);
        const glm::vec3 l = w / std::sqrt(d2);
        const float cosLight = -glm::dot(q.normal, l), cosSurface = glm::dot(n, l);
        if (cosLight <= 0.0f || cosSurface <= 0.0f) continue;
        sum += cosSurface * light.inversePdf(view, cosLight, d2);
    }
    return sum / (m * m);
}

struct Estimate {
    double mean = 0.0, variance = 0.0, standardError = 0.0;
};
// Mean, variance and standard error of the estimate over `seeds` independent seeds.
Estimate estimateOverSeeds(const AreaLightSampler& light, bool bySolidAngle, int m, int seeds) {
    std::vector<double> e;
    for (int s = 0; s < seeds; ++s) e.push_back(estimateIrradiance(light, bySolidAngle, m, 100 + s));
    Estimate r;
    for (double v : e) r.mean += v / seeds;
    for (double v : e) r.variance += (v - r.mean) * (v - r.mean) / (seeds - 1);
    r.standardError = std::sqrt(r.variance / seeds);
    return r;
}

TEST(SolidAngleLightSampling, NearALargeLightItIsExactAndQuieterThanArea) {
    // Height 0.05 under a unit square: area sampling's solid-angle density varies ~10^4-fold.
    const float h = 0.05f;
    SquareLight square(h);
    const LightView view = square.light.view(glm::vec3(0.0f), true);
    // The square's solid angle from its centre line: 4 asin(a^2 / (a^2 + 4 h^2)) for side a = 1.
    EXPECT_NEAR(view.solidAngle, 4 * std::asin(1.0 / (1.0 + 4.0 * h * h)), 1e-4);
    const double expected = squareIrradiance(h);
    const Estimate bySolidAngle = estimateOverSeeds(square.light, true, 4, 64);
    const Estimate byArea = estimateOverSeeds(square.light, false, 4, 64);
    EXPECT_NEAR(bySolidAngle.mean, expected, 4 * bySolidAngle.standardError + 1e-4 * expected);
    EXPECT_NEAR(byArea.mean, expected, 4 * byArea.standardError + 1e-4 * expected);
    // Unbiased both ways; by solid angle the 1/d^2 peak under the receiver is no longer noise.
    EXPECT_LT(bySolidAngle.variance * 10, byArea.variance);
}

TEST(SolidAngleLightSampling, UnbiasedCloseToTheLightAndByAreaWhereItAlmostTouches) {
    // Down to 0.6 % of the light's size the spherical triangles approach hemispheres and the
    // directions graze the plane; the estimate stays unbiased, tending to pi L.
    for (float h : {0.03f, 0.01f, 0.006f}) {
        SquareLight square(h);
        const LightView view = square.light.view(glm::vec3(0.0f), true);
        EXPECT_GT(view.solidAngle, 0.0f) << h;
        EXPECT_NEAR(view.solidAngle, 4 * std::asin(1.0 / (1.0 + 4.0 * h * h)), 1e-4) << h;
        const Estimate e = estimateOverSeeds(square.light, true, 8, 32);
        EXPECT_NEAR(e.mean, squareIrradiance(h), 4 * e.standardError + 1e-3 * squareIrradiance(h)) << h;
    }
    // Closer, the float solid angles themselves err (at 1e-5 the two triangles' sum exceeds
    // 2 pi): sampled by area, with finite estimates.
    for (float h : {1e-3f, 1e-5f}) {
        SquareLight square(h);
        EXPECT_EQ(square.light.view(glm::vec3(0.0f), true).solidAngle, 0.0f) << h;
        EXPECT_TRUE(std::isfinite(estimateIrradiance(square.light, true, 8, 3))) << h;
    }
}

TEST(SolidAngleLightSampling, FarFromALightAreaSamplingIsKept) {
    SquareLight square(1.0f);
    // Height 1: cos' / d^2 spans only (farthest / nearest)^3 = 1.5^1.5 = 1.84 over the square.
    EXPECT_EQ(square.light.view(glm::vec3(0.0f), true).solidAngle, 0.0f);
    // Height 0.2: (sqrt(0.54) / 0.2)^3 = 50: by solid angle.
    SquareLight nearer(0.2f);
    EXPECT_GT(nearer.light.view(glm::vec3(0.0f), true).solidAngle, 0.0f);
    EXPECT_EQ(nearer.light.view(glm::vec3(0.0f), false).solidAngle, 0.0f) << "area sampling asked for";
    // Far or near, the estimate is unbiased.
    for (float h : {1.0f, 0.2f}) {
        SquareLight s(h);
        const Estimate e = estimateOverSeeds(s.light, true, 8, 64);
        EXPECT_NEAR(e.mean, squareIrradiance(h), 4 * e.standardError + 1e-4 * squareIrradiance(h)) << h;
    }
}

TEST(AreaLightSampler, IrradianceEstimateIsLambertsPolygonFormula) {
    for (float h : {0.05f, 0.3f, 1.0f, 10.0f}) {
        SquareLight square(h);
        EXPECT_NEAR(square.light.irradianceEstimate(glm::vec3(0.0f), {0, 1, 0}), squareIrradiance(h),
                    1e-4 * squareIrradiance(h)) << h;
    }
    SquareLight square(0.5f);
    EXPECT_EQ(square.light.irradianceEstimate(glm::vec3(0.0f), {0, -1, 0}), 0.0f) << "light below the horizon";
    EXPECT_EQ(square.light.irradianceEstimate(glm::vec3(0, 1, 0), {0, 1, 0}), 0.0f) << "behind the light";
}

TEST(SolidAngleLightSampling, ALightFacingAwaySendsNothing) {
    SquareLight square(-0.05f);  // below the receiver, still facing down
    EXPECT_EQ(square.light.view(glm::vec3(0.0f), true).solidAngle, 0.0f);
    EXPECT_EQ(estimateIrradiance(square.light, true, 4, 1), 0.0);
}

}  // namespace
}  // namespace aamap
