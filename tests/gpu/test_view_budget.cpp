// What a view needs (passes/view_budget.h), on the CPU: area-light samples follow the light's
// solid angle over the visible region, and the view culls never drop a triangle the view or a
// shadow in it needs.
#include <cmath>
#include <random>

#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <gtest/gtest.h>

#include "passes/view_budget.h"

namespace aamap::passes {
namespace {

const Bounds kUnitRegion{glm::vec3(-0.5f), glm::vec3(0.5f)};

TEST(ViewBudget, SolidAngleFallsWithTheSquareOfTheDistance) {
    const double area = 0.04;  // a 0.2 x 0.2 light facing down the y axis at the region
    const Bounds tiny{glm::vec3(-1e-3f), glm::vec3(1e-3f)};
    const double near = meanSolidAngle(area, {0, 2, 0}, {0, -1, 0}, tiny);
    const double far = meanSolidAngle(area, {0, 4, 0}, {0, -1, 0}, tiny);
    EXPECT_NEAR(near, area / 4.0, 1e-4);
    EXPECT_NEAR(far / near, 0.25, 1e-3);
    // Facing away from the region: nothing of it is seen there.
    EXPECT_EQ(meanSolidAngle(area, {0, 2, 0}, {0, 1, 0}, tiny), 0.0);
    // Without a normal (curved or two-faced light) the emitter's cosine is left out.
    EXPECT_NEAR(meanSolidAngle(area, {0, 2, 0}, {0, 0, 0}, tiny), near, 1e-6);
    // A light nearer than its own size counts as 1 sr at that point, not as an unbounded angle.
    EXPECT_LE(meanSolidAngle(1.0, {0, 0.01f, 0}, {0, -1, 0}, tiny), 1.0 + 1e-9);
}

TEST(ViewBudget, ALightTwiceAsFarGetsFewerSamples) {
    const double area = 1.0;
    int previous = 1 << 30;
    int fewer = 0;
    for (float d : {1.0f, 2.0f, 4.0f, 8.0f, 16.0f}) {
        const double omega = meanSolidAngle(area, {0, 0.5f + d, 0}, {0, -1, 0}, kUnitRegion);
        const int n = areaLightSamplesFor(omega, 0.05, 16);
        EXPECT_LE(n, previous) << "at distance " << d;
        fewer += n < previous;
        previous = n;
        EXPECT_GE(n, 1);
        EXPECT_LE(n, 16);
    }
    EXPECT_GE(fewer, 3);  // it does fall, from the cap down to one
    EXPECT_EQ(previous, 1);
    // Larger light at the same place: at least as many samples.
    EXPECT_GE(areaLightSamplesFor(meanSolidAngle(4.0, {0, 2.5f, 0}, {0, -1, 0}, kUnitRegion), 0.05, 16),
              areaLightSamplesFor(meanSolidAngle(1.0, {0, 2.5f, 0}, {0, -1, 0}, kUnitRegion), 0.05, 16));
}

TEST(ViewBudget, SampleCountIsTheCeilingClamped) {
    EXPECT_EQ(areaLightSamplesFor(0.0, 0.05, 5), 1);
    EXPECT_EQ(areaLightSamplesFor(0.05, 0.05, 5), 1);
    EXPECT_EQ(areaLightSamplesFor(0.051, 0.05, 5), 2);
    EXPECT_EQ(areaLightSamplesFor(0.149, 0.05, 5), 3);
    EXPECT_EQ(areaLightSamplesFor(10.0, 0.05, 5), 5);
    EXPECT_EQ(areaLightSamplesFor(0.001, 0.0, 5), 5);  // 0: always the configured count
}

glm::mat4 testViewProjection() {
    const glm::mat4 proj = glm::perspective(glm::radians(50.0f), 1.5f, 0.1f, 100.0f);
    const glm::mat4 view = glm::lookAt(glm::vec3(0, 0, 5), glm::vec3(0.3f, -0.2f, 0), glm::vec3(0, 1, 0));
    return proj * view;
}

bool projectsInside(const glm::mat4& viewProj, const glm::vec3& p) {
    const glm::vec4 c = viewProj * glm::vec4(p, 1.0f);
    return c.w > 0.0f && std::abs(c.x) <= c.w && std::abs(c.y) <= c.w;
}

TEST(ViewBudget, VisibleRegionHoldsWhatTheViewSees) {
    const glm::mat4 vp = testViewProjection();
    const Bounds scene{glm::vec3(-10.0f), glm::vec3(10.0f)};
    const Bounds region = visibleRegion(vp, scene);
    std::mt19937 rng(3);
    std::uniform_real_distribution<float> coord(-10.0f, 10.0f);
    for (int i = 0; i < 20000; ++i) {
        const glm::vec3 p(coord(rng), coord(rng), coord(rng));
        if (!projectsInside(vp, p)) continue;
        for (int a = 0; a < 3; ++a) {
            EXPECT_GE(p[a], region.lo[a] - 1e-3f);
            EXPECT_LE(p[a], region.hi[a] + 1e-3f);
        }
    }
    // Behind the camera (z > 5) is outside it.
    EXPECT_LT(region.hi.z, 5.01f);
}

// Random small triangles; every one with a point that projects into the frustum is kept.
TEST(ViewBudget, TrianglesInViewKeepsEveryVisibleTriangle) {
    const glm::mat4 vp = testViewProjection();
    const ViewFrustum frustum = ViewFrustum::fromViewProjection(vp, 0.0f);
    std::mt19937 rng(5);
    std::uniform_real_distribution<float> coord(-8.0f, 8.0f), small(-0.6f, 0.6f), bary(0.0f, 1.0f);
    std::vector<glm::vec3> positions;
    for (int t = 0; t < 3000; ++t) {
        const glm::vec3 c(coord(rng), coord(rng), coord(rng));
        for (int k = 0; k < 3; ++k) positions.push_back(c + glm::vec3(small(rng), small(rng), small(rng)));
    }
    const std::vector<std::uint32_t> kept = trianglesInView(positions, 3000, frustum);
    std::vector<char> isKept(3000, 0);
    for (std::uint32_t t : kept) isKept[t] = 1;
    int visible = 0;
    for (std::uint32_t t = 0; t < 3000; ++t) {
        bool seen = false;
        for (int s = 0; s < 64 && !seen; ++s) {
            float u = bary(rng), v = bary(rng);
            if (u + v > 1.0f) u = 1.0f - u, v = 1.0f - v;
            seen = projectsInside(vp, positions[3 * t] + u * (positions[3 * t + 1] - positions[3 * t]) +
                                          v * (positions[3 * t + 2] - positions[3 * t]));
        }
        visible += seen;
        if (seen) {
            EXPECT_TRUE(isKept[t]) << "triangle " << t << " is seen but culled";
        }
    }
    EXPECT_GT(visible, 100);
    EXPECT_LT(kept.size(), 3000u / 2);  // and most of the space around it is culled
}

// Moller-Trumbore: does segment a-b cross triangle (p, q, r)?
bool segmentHits(const glm::vec3& a, const glm::vec3& b, const glm::vec3& p, const glm::vec3& q, const glm::vec3& r) {
    const glm::vec3 d = b - a, e1 = q - p, e2 = r - p, h = glm::cross(d, e2);
    const float det = glm::dot(e1, h);
    if (std::abs(det) < 1e-12f) return false;
    const glm::vec3 s = a - p;
    const float u = glm::dot(s, h) / det;
    if (u < 0.0f || u > 1.0f) return false;
    const glm::vec3 qv = glm::cross(s, e1);
    const float v = glm::dot(d, qv) / det;
    if (v < 0.0f || u + v > 1.0f) return false;
    const float t = glm::dot(e2, qv) / det;
    return t >= 0.0f && t <= 1.0f;
}

// A caster the shadow cull drops never lies between the light (or any point of its patch) and a
// point in view, so no visible shadow is lost; and it does drop some.
TEST(ViewBudget, ShadowCullKeepsEveryCasterOfAVisiblePoint) {
    const glm::mat4 vp = testViewProjection();
    const ViewFrustum frustum = ViewFrustum::fromViewProjection(vp, 0.0f);
    std::mt19937 rng(11);
    std::uniform_real_distribution<float> coord(-8.0f, 8.0f), small(-0.8f, 0.8f), unit(-1.0f, 1.0f);
    std::vector<glm::vec3> positions;
    std::vector<std::uint32_t> face;
    for (std::uint32_t t = 0; t < 4000; ++t) {
        const glm::vec3 c(coord(rng), coord(rng), coord(rng));
        for (std::uint32_t k = 0; k < 3; ++k) {
            positions.push_back(c + glm::vec3(small(rng), small(rng), small(rng)));
            face.push_back(3 * t + k);
        }
    }
    // Visible points: random points that project into the frustum, within the scene.
    std::vector<glm::vec3> visible;
    while (visible.size() < 300) {
        const glm::vec3 p(coord(rng), coord(rng), coord(rng));
        if (projectsInside(vp, p)) visible.push_back(p);
    }
    for (const auto& [light, radius] : {std::pair{glm::vec3(0.5f, 1.0f, 0.0f), 0.0f},
                                        std::pair{glm::vec3(-1.0f, 2.0f, -3.0f), 0.5f},
                                        std::pair{glm::vec3(6.0f, 0.0f, 0.0f), 0.0f}}) {
        std::vector<std::uint32_t> kept;
        cullShadowCasters(positions, face, light, radius, frustum, kept);
        std::vector<char> isKept(4000, 0);
        for (std::size_t i = 0; i < kept.size(); i += 3) isKept[kept[i] / 3] = 1;
        std::size_t dropped = 0;
        for (std::uint32_t t = 0; t < 4000; ++t) {
            if (isKept[t]) continue;
            ++dropped;
            for (const glm::vec3& p : visible)
                for (int s = 0; s < (radius > 0.0f ? 4 : 1); ++s) {
                    // Points of the light's patch: within `radius` of the light.
                    const glm::vec3 offset = s == 0 ? glm::vec3(0.0f)
                                                    : radius * glm::normalize(glm::vec3(unit(rng), unit(rng), unit(rng)));
                    ASSERT_FALSE(segmentHits(light + offset, p, positions[3 * t], positions[3 * t + 1],
                                             positions[3 * t + 2]))
                        << "dropped triangle " << t << " shadows a visible point";
                }
        }
        EXPECT_GT(dropped, 0u);
    }
}

// Shadow-map resolution by need: a camera at the origin looking down -z (20 degrees, 256^2
// pixels) at a wall `distance` away, which fills the view; lights in front of the wall.
ShadowNeedView wallView(float distance) {
    ShadowNeedView v;
    v.viewProj = glm::perspective(glm::radians(20.0f), 1.0f, 0.01f, 1000.0f) *
                 glm::lookAt(glm::vec3(0.0f), glm::vec3(0, 0, -1), glm::vec3(0, 1, 0));
    v.eye = glm::vec3(0.0f);
    v.pixels = {256u, 256u};
    const Bounds wall{glm::vec3(-1000.0f, -1000.0f, -1.01f * distance), glm::vec3(1000.0f, 1000.0f, -distance)};
    v.region = visibleRegion(v.viewProj, wall);
    return v;
}

PointLight pointLight(const glm::vec3& position, float intensity = 1.0f) {
    PointLight l;
    l.position = position;
    l.intensity = glm::vec3(intensity);
    return l;
}

TEST(ShadowNeed, ReceiversLieInTheVisibleRegion) {
    const ShadowNeedView v = wallView(10.0f);
    const std::vector<glm::vec3> receivers = shadowReceivers(v);
    ASSERT_EQ(receivers.size(), 100u);  // 5 x 5 rays, 4 points each, every ray meets the wall
    for (const glm::vec3& p : receivers) {
        EXPECT_GE(p.z, v.region.lo.z - 1e-3f);
        EXPECT_LE(p.z, v.region.hi.z + 1e-3f);
    }
}

TEST(ShadowNeed, ALightAndWhatItLightsTwiceAsFarFromTheEyeNeverGetMoreTexels) {
    int previous = 1 << 30;
    for (const float d : {2.0f, 4.0f, 8.0f, 16.0f, 32.0f, 64.0f}) {
        const PointLight light = pointLight({0.0f, 0.0f, 1.0f - d});  // one unit in front of the wall
        for (const float texelPixels : {1.0f, 4.0f}) {
            const int size = shadowFaceSizes(std::span(&light, 1), 0.0, wallView(d), texelPixels, 256)[0];
            if (texelPixels == 1.0f) {
                EXPECT_LE(size, previous) << "at distance " << d;
                previous = size;
            }
        }
    }
    // Near the eye a texel must be small: the whole resolution.
    const PointLight near = pointLight({0.0f, 0.0f, -1.0f});
    EXPECT_EQ(shadowFaceSizes(std::span(&near, 1), 0.0, wallView(2.0f), 1.0f, 256)[0], 256);
}

TEST(ShadowNeed, ALightTwiceAsFarAsABrighterOneNeverGetsMoreTexels) {
    // Light a one unit from the wall; light b further: its share of the irradiance falls faster
    // than its texels grow, so it needs fewer, down to the least size.
    const float d = 20.0f;
    const PointLight a = pointLight({0.0f, 0.0f, 1.0f - d});
    int previous = 1 << 30;
    for (const float h : {1.5f, 3.0f, 6.0f, 12.0f}) {
        const std::vector<PointLight> lights{a, pointLight({0.0f, 0.0f, h - d})};
        const std::vector<int> sizes = shadowFaceSizes(lights, 0.0, wallView(d), 1.0f, 256);
        EXPECT_LE(sizes[1], previous) << "at " << h;
        EXPECT_LE(sizes[1], sizes[0]);
        previous = sizes[1];
    }
    EXPECT_LT(previous, 256);
    // A dimmer light (and one outshone by lights at infinity) never gets more.
    int dimmer = 1 << 30;
    for (const float intensity : {1.0f, 0.5f, 0.1f, 0.01f}) {
        const std::vector<PointLight> lights{a, pointLight({0.0f, 0.0f, 3.0f - d}, intensity)};
        const int size = shadowFaceSizes(lights, 0.0, wallView(d), 1.0f, 256)[1];
        EXPECT_LE(size, dimmer) << "at intensity " << intensity;
        dimmer = size;
        EXPECT_LE(shadowFaceSizes(lights, 1.0, wallView(d), 1.0f, 256)[1], size);
    }
    EXPECT_EQ(dimmer, kMinShadowFaceSize);
}

TEST(ShadowNeed, SizesStayWithinTheLimits) {
    const float d = 20.0f;
    const std::vector<PointLight> lights{pointLight({0.0f, 0.0f, 1.0f - d}), pointLight({3.0f, 1.0f, 2.0f - d}, 0.3f),
                                         pointLight({0.0f, 0.0f, -1.0f})};
    int previous[3] = {1 << 30, 1 << 30, 1 << 30};
    for (const float texelPixels : {0.25f, 0.5f, 1.0f, 2.0f, 4.0f, 16.0f, 64.0f}) {
        for (const int maxSize : {16, 100, 256, 1024}) {
            const std::vector<int> sizes = shadowFaceSizes(lights, 0.0, wallView(d), texelPixels, maxSize);
            for (std::size_t i = 0; i < sizes.size(); ++i) {
                EXPECT_LE(sizes[i], maxSize);
                EXPECT_GE(sizes[i], std::min(kMinShadowFaceSize, maxSize));
                EXPECT_TRUE(sizes[i] == maxSize || sizes[i] % kShadowFaceStep == 0) << sizes[i];
                if (maxSize == 1024) {  // a wider texel allowed: never more texels
                    EXPECT_LE(sizes[i], previous[i]) << "light " << i << " at " << texelPixels;
                    previous[i] = sizes[i];
                }
            }
        }
    }
    EXPECT_EQ(previous[0], kMinShadowFaceSize);  // 64 pixels per texel: the least size
    // 0: every light at the full resolution; so without any receiver in view.
    for (const int size : shadowFaceSizes(lights, 0.0, wallView(d), 0.0f, 256)) EXPECT_EQ(size, 256);
    ShadowNeedView away = wallView(d);
    away.region = Bounds{glm::vec3(10.0f, 10.0f, 10.0f), glm::vec3(11.0f, 11.0f, 11.0f)};  // behind the eye
    for (const int size : shadowFaceSizes(lights, 0.0, away, 1.0f, 256)) EXPECT_EQ(size, 256);
}

}  // namespace
}  // namespace aamap::passes
