// The tracer's pixel facts (core/pixel_facts.h) on scenes with one cause each: what a pixel's 4 x 4
// sub-rays hit, and whether a light reaches some of its sub-hits and not others.
#include <cmath>

#include <glm/trigonometric.hpp>
#include <gtest/gtest.h>

#include "tests/tracer/material_scenes.h"
#include "tests/tracer/scene_builder.h"
#include "tracer/tracer.h"

namespace aamap::testing {
namespace {

using namespace pixel_fact;

constexpr int kFactsSize = 63;  // odd: no band edge falls on a pixel boundary
constexpr float kDistance = 5.0f;   // camera on +z looking at the plane z = 0
constexpr float kTanHalf = 0.8f;    // the view spans x, y in [-4, 4] on that plane

View topView() {
    View v;
    v.position = {0.0f, 0.0f, kDistance};
    v.direction = {0.0f, 0.0f, -1.0f};
    v.up = {0.0f, 1.0f, 0.0f};
    v.horizontalFovDeg = v.verticalFovDeg = 2.0f * glm::degrees(std::atan(kTanHalf));
    return v;
}

// The point of the plane z = 0 at the centre of pixel (x, y), and one pixel's width there.
glm::vec2 planePoint(int x, int y) {
    const float u = (static_cast<float>(x) + 0.5f) / kFactsSize, v = (static_cast<float>(y) + 0.5f) / kFactsSize;
    return {(2.0f * u - 1.0f) * kTanHalf * kDistance, (1.0f - 2.0f * v) * kTanHalf * kDistance};
}
constexpr float kPixel = 2.0f * kTanHalf * kDistance / kFactsSize;

// Distance from p to the boundary of the axis-aligned square [lo, hi]^2 (positive either side).
float boundaryDistance(glm::vec2 p, float lo, float hi) {
    const float dx = std::max({lo - p.x, p.x - hi, 0.0f}), dy = std::max({lo - p.y, p.y - hi, 0.0f});
    if (dx > 0.0f || dy > 0.0f) return std::hypot(dx, dy);
    return std::min({p.x - lo, hi - p.x, p.y - lo, hi - p.y});
}

PixelFacts factsOf(Scene& scene, int threads = 0) {
    const Tracer tracer(scene);
    return tracer.pixelFacts(topView(), kFactsSize, kFactsSize, threads);
}

TEST(PixelFacts, MaterialsAndSilhouettes) {
    // Four vertical bands, left to right: diffuse, planar mirror, glass, emitter; background above
    // y = 2 and a curved mirror (sphere) below y = -2.
    SceneBuilder b;
    const auto grey = b.material("grey", glm::vec3(0.5f));
    const auto mirror = addMaterial(b, mirrorMaterial(glm::vec3(0.9f)));
    const auto glass = addMaterial(b, glassMaterial(1.5f));
    const auto light = b.material("lamp", glm::vec3(0.0f), glm::vec3(1.0f));
    const glm::vec3 X(2, 0, 0), Y(0, 4, 0);
    b.quad({-4, -2, 0}, X, Y, grey);
    b.quad({-2, -2, 0}, X, Y, mirror);
    b.quad({0, -2, 0}, X, Y, glass);
    b.quad({2, -2, 0}, X, Y, light);
    sphere(b, {0.0f, -3.2f, 0.0f}, 0.7f, mirror, false);
    const PixelFacts f = factsOf(b.scene());

    const auto at = [&](float wx, float wy) {
        const int x = static_cast<int>((wx / (kTanHalf * kDistance) + 1.0f) * 0.5f * kFactsSize);
        const int y = static_cast<int>((1.0f - wy / (kTanHalf * kDistance)) * 0.5f * kFactsSize);
        return f.at(x, y);
    };
    EXPECT_EQ(at(-3.0f, 0.0f), 0) << "plain diffuse interior";
    EXPECT_EQ(at(-1.0f, 0.0f), PlanarMirror);
    EXPECT_EQ(at(1.0f, 0.0f), Glass);
    EXPECT_EQ(at(3.0f, 0.0f), Emitter);
    EXPECT_EQ(at(0.0f, 3.0f), Background);
    EXPECT_NE(at(0.0f, -3.2f) & CurvedMirror, 0) << "a sphere's interpolated normals";
    EXPECT_EQ(at(0.0f, -3.2f) & PlanarMirror, 0);
    // Pixels whose footprint straddles y = 2, the top edge of every band, see two things; those
    // more than a pixel from any band edge see one.
    int silhouettes = 0;
    for (int y = 0; y < kFactsSize; ++y)
        for (int x = 0; x < kFactsSize; ++x) {
            const glm::vec2 p = planePoint(x, y);
            const bool straddles = std::abs(p.y - 2.0f) < 0.5f * kPixel;
            if (straddles) {
                EXPECT_NE(f.at(x, y) & Silhouette, 0) << x << "," << y;
                ++silhouettes;
            }
            if (std::abs(p.y) < 1.5f && std::abs(p.x - std::round(p.x / 2.0f) * 2.0f) > kPixel) {
                EXPECT_EQ(f.at(x, y) & Silhouette, 0) << x << "," << y;
            }
        }
    EXPECT_GE(silhouettes, kFactsSize / 2);
}

// A floor, a square occluder at height 1.5 and a light at (2, 0, 3): the shadow is the square
// [-3, -1]^2 (light-to-floor scale 2 around (-2, 0)), away from where the camera sees the occluder.
Scene shadowScene(bool areaLight) {
    SceneBuilder b;
    const auto grey = b.material("grey", glm::vec3(0.5f));
    b.quad({-4, -4, 0}, {8, 0, 0}, {0, 8, 0}, grey);                 // floor, faces +z
    b.quad({-0.5f, -0.5f, 1.5f}, {0, 1, 0}, {1, 0, 0}, grey);        // occluder, faces -z (towards the floor)
    if (areaLight) b.areaLightQuad({1.75f, -0.25f, 3.0f}, {0, 0.5f, 0}, {0.5f, 0, 0}, glm::vec3(10.0f));  // faces -z
    else b.pointLight({2.0f, 0.0f, 3.0f}, glm::vec3(10.0f));
    return std::move(b.scene());
}

TEST(PixelFacts, ShadowBoundaryFollowsTheShadowEdge) {
    Scene scene = shadowScene(false);
    const PixelFacts f = factsOf(scene);
    int boundary = 0;
    for (int y = 0; y < kFactsSize; ++y)
        for (int x = 0; x < kFactsSize; ++x) {
            const glm::vec2 p = planePoint(x, y);
            if (std::abs(p.x) < 1.0f && std::abs(p.y) < 1.0f) continue;  // the occluder and its rim
            const float d = boundaryDistance({p.x + 2.0f, p.y}, -1.0f, 1.0f);
            const bool edge = (f.at(x, y) & ShadowBoundary) != 0;
            boundary += edge ? 1 : 0;
            // A pixel is 0.125 wide: within 0.75 pixel of the edge it may straddle it, beyond it must not.
            if (d > 0.75f * kPixel * std::sqrt(2.0f)) {
                EXPECT_FALSE(edge) << x << "," << y;
            }
            EXPECT_EQ(f.at(x, y) & Penumbra, 0) << "a point light casts no penumbra";
        }
    EXPECT_GE(boundary, 3 * static_cast<int>(2.0f / kPixel)) << "the sides of the shadow";
}

TEST(PixelFacts, PenumbraAroundAnAreaLightsShadow) {
    Scene scene = shadowScene(true);
    const PixelFacts f = factsOf(scene);
    const auto pixelOf = [](float wx, float wy) {
        return glm::ivec2(static_cast<int>((wx / (kTanHalf * kDistance) + 1.0f) * 0.5f * kFactsSize),
                          static_cast<int>((1.0f - wy / (kTanHalf * kDistance)) * 0.5f * kFactsSize));
    };
    const glm::ivec2 umbra = pixelOf(-2.0f, 0.0f), lit = pixelOf(3.0f, 3.0f), edge = pixelOf(-1.0f, 0.0f);
    EXPECT_EQ(f.at(umbra.x, umbra.y) & Penumbra, 0);
    EXPECT_EQ(f.at(lit.x, lit.y) & Penumbra, 0);
    EXPECT_NE(f.at(edge.x, edge.y) & Penumbra, 0);
    EXPECT_EQ(f.at(edge.x, edge.y) & ShadowBoundary, 0) << "shadow boundaries are point lights'";
}

TEST(PixelFacts, IndependentOfTheThreadCount) {
    Scene scene = shadowScene(true);
    EXPECT_EQ(factsOf(scene, 1).pixels(), factsOf(scene, 2).pixels());
}

}  // namespace
}  // namespace aamap::testing
