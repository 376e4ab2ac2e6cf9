#include <cmath>
#include <numbers>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>
#include <gtest/gtest.h>

#include "scene/lights.h"
#include "tests/tracer/scene_builder.h"
#include "tracer/embree_scene.h"
#include "tracer/integrator.h"
#include "tracer/lights.h"

namespace aamap {
namespace {

// A light made of `strips` quads side by side along x with widths 1, 2, 3, ...: samples must land
// in each strip in proportion to its area, whichever triangle-selection path the count takes.
void checkAreaSampling(int strips) {
    testing::SceneBuilder b;
    std::vector<float> edges{0.0f};
    for (int i = 0; i < strips; ++i) edges.push_back(edges.back() + static_cast<float>(i + 1));
    AreaLight light;
    light.radiance = glm::vec3(1.0f);
    const auto mat = b.material("light", glm::vec3(0.0f), glm::vec3(1.0f));
    for (int i = 0; i < strips; ++i) {
        // Faces -y: cross(+x, +z).
        const auto tris = b.quad({edges[i], 0, 0}, {edges[i + 1] - edges[i], 0, 0}, {0, 0, 1}, mat);
        light.triangles.insert(light.triangles.end(), tris.begin(), tris.end());
    }
    const EmbreeScene geometry(b.scene());
    const AreaLightSampler sampler(light, geometry);
    EXPECT_NEAR(sampler.area(), edges.back(), 1e-4);

    // Fine in u.x, which picks the triangle: each triangle gets a whole number of columns.
    constexpr int kColumns = 4096, kRows = 4;
    std::vector<int> counts(static_cast<std::size_t>(strips), 0);
    for (int y = 0; y < kRows; ++y)
        for (int x = 0; x < kColumns; ++x) {
            const LightPoint p = sampler.sample({(x + 0.5f) / kColumns, (y + 0.5f) / kRows});
            ASSERT_EQ(p.position.y, 0.0f);
            ASSERT_GE(p.position.z, 0.0f);
            ASSERT_LE(p.position.z, 1.0f);
            ASSERT_EQ(p.normal, glm::vec3(0, -1, 0));
            int strip = 0;
            while (strip + 1 < strips && p.position.x >= edges[strip + 1]) ++strip;
            ASSERT_GE(p.position.x, 0.0f);
            ASSERT_LE(p.position.x, edges.back());
            ++counts[static_cast<std::size_t>(strip)];
        }
    for (int i = 0; i < strips; ++i) {
        const double expected = kColumns * kRows * (i + 1) / static_cast<double>(edges.back());
        EXPECT_NEAR(counts[static_cast<std::size_t>(i)], expected, 4.0 * kRows) << "strip " << i;
    }
}

TEST(AreaLightSampler, UniformByAreaFewTriangles) { checkAreaSampling(3); }
TEST(AreaLightSampler, UniformByAreaManyTriangles) { checkAreaSampling(12); }

// ---- Spot lights: known answers on a plane ----------------------------------------------------

constexpr float kAlbedo = 0.5f;
constexpr double kInnerDeg = 20.0, kOuterDeg = 40.0;

struct Spot {
    glm::dvec3 position, axis, intensity;
};

// A large plane y = 0 (albedo kAlbedo) under the given spots (inner 20, outer 40 degrees).
Scene spotScene(const std::vector<Spot>& spots) {
    testing::SceneBuilder b;
    b.quad({-100, 0, -100}, {0, 0, 200}, {200, 0, 0}, b.material("plane", glm::vec3(kAlbedo)));
    Scene s = std::move(b.scene());
    for (const Spot& spot : spots) {
        PointLight p;
        p.name = "spot";
        p.position = glm::vec3(spot.position);
        p.intensity = glm::vec3(spot.intensity);
        p.spotDirection = glm::vec3(glm::normalize(spot.axis));
        p.cosInner = static_cast<float>(std::cos(glm::radians(kInnerDeg)));
        p.cosOuter = static_cast<float>(std::cos(glm::radians(kOuterDeg)));
        s.pointLights.push_back(p);
    }
    return s;
}

// The analytic falloff in double: 1 inside, 0 outside, t^2 with t linear in the cosine between.
double falloff(double angleDeg) {
    const double ci = std::cos(glm::radians(kInnerDeg)), co = std::cos(glm::radians(kOuterDeg));
    const double c = std::cos(glm::radians(angleDeg));
    if (c >= ci) return 1.0;
    if (c <= co) return 0.0;
    const double t = (c - co) / (ci - co);
    return t * t;
}

// Irradiance at point x on the plane (normal +y) from one spot: I f(angle to the axis) cos / d^2.
glm::dvec3 spotIrradiance(const Spot& spot, const glm::dvec3& x) {
    const glm::dvec3 w = x - spot.position;
    const double d = glm::length(w);
    const double angle = glm::degrees(std::acos(std::clamp(glm::dot(w / d, glm::normalize(spot.axis)), -1.0, 1.0)));
    const double cosSurface = -w.y / d;
    return cosSurface > 0.0 ? spot.intensity * (falloff(angle) * cosSurface / (d * d)) : glm::dvec3(0.0);
}

// How far float rounding may move the result at x: the hit point is rebuilt in float on a plane
// 200 units wide (~1e-5 of the distance to the spot), which moves the cosine to the axis by up to
// ~1e-5, and the falloff t^2 changes by 2 t / (cos inner - cos outer) per unit of cosine. Tight
// where the falloff is flat, and never looser than 1e-5 of the unattenuated value.
double roundingBound(const Spot& spot, const glm::dvec3& x) {
    const double ci = std::cos(glm::radians(kInnerDeg)), co = std::cos(glm::radians(kOuterDeg));
    const glm::dvec3 w = x - spot.position;
    const double d = glm::length(w);
    const double c = glm::dot(w / d, glm::normalize(spot.axis));
    const double t = std::clamp((c - co) / (ci - co), 0.0, 1.0);
    const double unattenuated = glm::length(spot.intensity) * std::max(-w.y / d, 0.0) / (d * d);
    return double(kAlbedo) / std::numbers::pi * unattenuated * (2.0 * t / (ci - co) + 1.0) * 1e-5;
}

// Radiance the integrator returns for a ray straight down onto x.
glm::vec3 radianceAt(const Integrator& integrator, const glm::dvec3& x) {
    RayCounts rays;
    const Sampler sampler(7, 0, 1);
    return integrator.primary(glm::vec3(x) + glm::vec3(0, 0.5f, 0), {0, -1, 0}, sampler, rays);
}

// Points on the plane at the given angles from the spot's axis, in the plane of the axis and y.
glm::dvec3 pointAtAngle(const Spot& spot, double angleDeg) {
    // Walk from the spot along the axis rotated by angleDeg about z; meet y = 0.
    const glm::dvec3 a = glm::normalize(spot.axis);
    const double r = glm::radians(angleDeg);
    const glm::dvec3 dir(a.x * std::cos(r) - a.y * std::sin(r), a.x * std::sin(r) + a.y * std::cos(r), a.z);
    return spot.position + (-spot.position.y / dir.y) * dir;
}

void expectSpotKnownAnswers(ShadingMode mode, const Spot& spot) {
    const Scene scene = spotScene({spot});
    const EmbreeScene geometry(scene);
    const LightSet lights = buildLights(scene, geometry);
    ShadingSettings shading;
    shading.mode = mode;
    shading.maxDepth = 2;  // path: direct light only (the plane sees nothing else)
    const std::unique_ptr<Integrator> owned = makeIntegrator(geometry, lights, shading);
    const Integrator& integrator = *owned;
    // On the axis, inside the inner cone, across the falloff band, and outside the outer cone.
    for (double angle : {0.0, 12.0, 21.0, 25.0, 30.0, 35.0, 39.0, 41.0, 55.0}) {
        const glm::dvec3 x = pointAtAngle(spot, angle);
        ASSERT_NEAR(x.y, 0.0, 1e-9);
        const glm::dvec3 want = double(kAlbedo) / std::numbers::pi * spotIrradiance(spot, x);
        const glm::vec3 got = radianceAt(integrator, x);
        for (int c = 0; c < 3; ++c) {
            if (angle > kOuterDeg) {
                EXPECT_EQ(got[c], 0.0f) << "outside the cone at " << angle << " degrees";
            } else {
                EXPECT_NEAR(got[c], want[c], 1e-5 * want[c] + roundingBound(spot, x) + 1e-12)
                    << angle << " degrees, channel " << c;
            }
        }
    }
}

TEST(SpotLight, IrradianceOnAxisInTheBandAndOutsideMatchesTheAnalyticValue) {
    expectSpotKnownAnswers(ShadingMode::Direct, {{0.3, 2.0, -0.2}, {0, -1, 0}, {10, 5, 2.5}});
}

TEST(SpotLight, TiltedSpotKnownAnswers) {
    expectSpotKnownAnswers(ShadingMode::Direct, {{-0.5, 1.5, 0.4}, {0.5, -1, 0}, {4, 8, 2}});
}

TEST(SpotLight, PathModeNextEventMatchesTheAnalyticValue) {
    // One light: NEE picks it with probability 1, and BSDF rays escape, so the estimate is exact.
    expectSpotKnownAnswers(ShadingMode::Path, {{0.3, 2.0, -0.2}, {0.2, -1, 0}, {10, 5, 2.5}});
}

TEST(SpotLight, FalloffIsGltfsAndItsSolidAngleIsItsIntegral) {
    const float ci = std::cos(glm::radians(20.0f)), co = std::cos(glm::radians(40.0f));
    EXPECT_EQ(spotFalloff(1.0f, ci, co), 1.0f);
    EXPECT_EQ(spotFalloff(ci, ci, co), 1.0f);
    EXPECT_EQ(spotFalloff(co, ci, co), 0.0f);
    EXPECT_NEAR(spotFalloff(0.5f * (ci + co), ci, co), 0.25f, 1e-6f);
    EXPECT_EQ(spotFalloff(0.9f, 0.9f, 0.9f), 1.0f);  // equal cones: a hard edge
    EXPECT_EQ(spotFalloff(0.8999f, 0.9f, 0.9f), 0.0f);
    // 2 pi * integral of the falloff over cos in [-1, 1], by the midpoint rule.
    PointLight p;
    p.spotDirection = {0, 0, 1};
    p.cosInner = ci;
    p.cosOuter = co;
    const int n = 200000;
    double sum = 0.0;
    for (int i = 0; i < n; ++i) sum += spotFalloff(static_cast<float>(-1.0 + (i + 0.5) * 2.0 / n), ci, co);
    EXPECT_NEAR(emittingSolidAngle(p), 2.0 * std::numbers::pi * sum * 2.0 / n, 1e-4);
}

TEST(SpotLight, ContributionBoundIsExactInsideAndZeroOutside) {
    const Spot spot{{0, 2, 0}, {0, -1, 0}, {1, 1, 1}};
    const Scene scene = spotScene({spot});
    const EmbreeScene geometry(scene);
    const LightSet lights = buildLights(scene, geometry);
    ASSERT_EQ(lights.count(), 1u);
    for (double angle : {0.0, 25.0, 39.0, 41.0, 70.0}) {
        const glm::dvec3 x = pointAtAngle(spot, angle);
        const float c = lights.contribution(0, glm::vec3(x), {0, 1, 0});
        EXPECT_NEAR(c, spotIrradiance(spot, x).y, 1e-5 * spotIrradiance(spot, x).y + 1e-12) << angle;
        if (angle > kOuterDeg) {
            EXPECT_EQ(c, 0.0f);
        }
    }
    // Power selection weighs a spot by I times its cone's solid angle.
    const Scene two = [&] {
        Scene s = spotScene({spot});
        PointLight iso;
        iso.position = {5, 2, 0};
        iso.intensity = glm::vec3(1.0f);
        s.pointLights.push_back(iso);
        return s;
    }();
    const EmbreeScene g2(two);
    const LightSet l2 = buildLights(two, g2);
    EXPECT_NEAR(l2.selectPdf[0] / l2.selectPdf[1], emittingSolidAngle(two.pointLights[0]) / (4.0 * std::numbers::pi), 1e-5);
}

TEST(SpotLight, PerHitSelectionOverManyGreySpotsIsExact) {
    // Ten grey spots (more than kFewLights): per-hit selection by exact contribution makes every
    // sample of a delta light worth the total, so the many-light estimate equals the analytic sum.
    std::vector<Spot> spots;
    for (int i = 0; i < 10; ++i) {
        const double a = 2.0 * std::numbers::pi * i / 10.0;
        spots.push_back({{1.5 * std::cos(a), 2.0 + 0.1 * i, 1.5 * std::sin(a)},
                         {-0.4 * std::cos(a), -1.0, -0.4 * std::sin(a)}, glm::dvec3(3.0 + i)});
    }
    const Scene scene = spotScene(spots);
    const EmbreeScene geometry(scene);
    const LightSet lights = buildLights(scene, geometry);
    ASSERT_TRUE(lights.many());
    ASSERT_TRUE(lights.perHitSelectable());
    ShadingSettings shading;
    shading.lightSelection = LightSelection::Contribution;
    shading.areaLightSamples = 4;
    const std::unique_ptr<Integrator> owned = makeIntegrator(geometry, lights, shading);
    const Integrator& integrator = *owned;
    int lit = 0;
    for (double x = -3.0; x <= 3.0; x += 0.5)
        for (double z = -3.0; z <= 3.0; z += 0.75) {
            const glm::dvec3 p(x, 0.0, z);
            glm::dvec3 e(0.0);
            double bound = 1e-12;
            for (const Spot& s : spots) {
                e += spotIrradiance(s, p);
                bound += roundingBound(s, p);
            }
            const glm::dvec3 want = double(kAlbedo) / std::numbers::pi * e;
            const glm::vec3 got = radianceAt(integrator, p);
            lit += want.x > 0.0;
            EXPECT_NEAR(got.x, want.x, 1e-5 * want.x + bound) << x << "," << z;
        }
    EXPECT_GT(lit, 20);
}

}  // namespace
}  // namespace aamap
