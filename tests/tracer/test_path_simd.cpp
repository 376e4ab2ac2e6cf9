// Path mode's SIMD lanes (tracer/path_simd.h) against the scalar path: the same random numbers bit
// for bit, the same radiance per sample up to the bounce's sine and cosine (Highway's against
// libm's), thread-count determinism, and a known answer through them.
#include <algorithm>
#include <cmath>
#include <memory>
#include <vector>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>
#include <hwy/targets.h>

#include "tests/tracer/material_scenes.h"
#include "tracer/embree_scene.h"
#include "tracer/integrator.h"
#include "tracer/lights.h"
#include "tracer/path_integrator.h"
#include "tracer/path_simd.h"
#include "tracer/ray_packet.h"
#include "tracer/sampler.h"

namespace aamap {
namespace {

using testing::lookAt;
using testing::renderScene;

// A closed room of Lambert walls (three colours), a rough plastic floor and box, a Phong box and a
// rough conductor panel (GGX), lit by three area lights of different sizes and colours: every
// lane takes the SIMD path, Lambert and rough plastic lanes to the end, the others for their
// light samples. sky: no area lights and no ceiling, lit by an environment map with a bright
// patch instead (the lanes with no finite light, the sky sampled per lane after them).
Scene simdRoom(bool sky = false) {
    testing::SceneBuilder b;
    const auto white = b.material("white", glm::vec3(0.7f));
    const auto red = b.material("red", glm::vec3(0.6f, 0.1f, 0.1f));
    const auto green = b.material("green", glm::vec3(0.1f, 0.5f, 0.1f));
    Material phong;
    phong.name = "phong";
    phong.kd = glm::vec3(0.3f, 0.3f, 0.5f);
    phong.ks = glm::vec3(0.4f);
    phong.ns = 40.0f;
    const auto glossy = testing::addMaterial(b, phong);
    Material plastic;
    plastic.name = "plastic";
    plastic.kd = glm::vec3(0.5f, 0.4f, 0.2f);
    plastic.model = BsdfModel::Plastic;
    plastic.distribution = MicrofacetType::GGX;
    plastic.alphaU = plastic.alphaV = 0.15f;
    plastic.ior = 1.5f;
    const auto roughPlastic = testing::addMaterial(b, plastic);
    Material metal;
    metal.name = "metal";
    metal.kd = glm::vec3(0.0f);
    metal.model = BsdfModel::Conductor;
    metal.distribution = MicrofacetType::GGX;
    metal.alphaU = metal.alphaV = 0.2f;
    metal.eta = glm::vec3(0.2f, 0.9f, 1.1f);
    metal.k = glm::vec3(3.9f, 2.4f, 2.2f);
    const auto conductor = testing::addMaterial(b, metal);
    const glm::vec3 X(2, 0, 0), Y(0, 2, 0), Z(0, 0, 2), o(-1, 0, -1);
    b.quad(o, Z, X, roughPlastic);  // the floor
    if (!sky) b.quad(o + Y, X, Z, white);
    b.quad(o, X, Y, white);
    b.quad(o, Y, Z, red);
    b.quad(o + X, Z, Y, green);
    b.quad(o + Z, Y, X, white);  // the wall behind the camera closes the room
    b.box({-0.7f, 0.0f, -0.6f}, {-0.2f, 0.7f, -0.1f}, glossy);
    b.box({0.2f, 0.0f, -0.3f}, {0.7f, 0.4f, 0.2f}, roughPlastic);
    b.quad({-0.9f, 0.2f, -0.99f}, {0.6f, 0, 0}, {0, 0.8f, 0}, conductor);
    if (!sky) {
        b.areaLightQuad({-0.25f, 1.999f, -0.25f}, {0.5f, 0, 0}, {0, 0, 0.5f}, glm::vec3(8.0f, 7.0f, 6.0f));
        b.areaLightQuad({0.5f, 1.999f, 0.4f}, {0.2f, 0, 0}, {0, 0, 0.2f}, glm::vec3(20.0f, 20.0f, 30.0f));
        b.areaLightQuad({-0.999f, 1.2f, 0.3f}, {0, 0, 0.3f}, {0, 0.3f, 0}, glm::vec3(5.0f, 3.0f, 2.0f));
    }
    Scene scene = std::move(b.scene());
    if (sky) {
        EnvironmentLight env;
        env.mapWidth = 16;
        env.mapHeight = 8;
        for (int y = 0; y < env.mapHeight; ++y)
            for (int x = 0; x < env.mapWidth; ++x)
                env.map.push_back(y == 1 && x >= 6 && x <= 8 ? glm::vec3(40.0f, 36.0f, 30.0f)
                                                             : glm::vec3(0.3f, 0.4f, 0.6f) * (1.0f - 0.1f * y));
        scene.environment = env;
    }
    scene.views.push_back(lookAt({0, 1, 0.95f}, {0, 0.6f, -1}, 70));
    return scene;
}

// Runs f once per Highway target this CPU has (SSE4 and AVX2 as well as the best one it picks).
template <class F>
void forEachTarget(F&& f) {
    for (const std::int64_t target : hwy::SupportedAndGeneratedTargets()) {
        hwy::SetSupportedTargetsForTest(target);
        SCOPED_TRACE(hwy::TargetName(target));
        f();
    }
    hwy::SetSupportedTargetsForTest(0);
}

void expectScalarSamplersNumbers() {
    const Scene scene = simdRoom();
    const EmbreeScene geometry(scene);
    const LightSet lights = buildLights(scene, geometry);
    const pathsimd::LightTable table = pathsimd::makeLightTable(lights);
    for (int depth : {0, 1, 7, 64}) {
        for (int count : {1, 3, 8}) {
            pathsimd::Lanes lanes{};
            Sampler samplers[pathsimd::kLanes];
            for (int k = 0; k < pathsimd::kLanes; ++k) {
                samplers[k] = Sampler(static_cast<std::uint64_t>(1000 * depth + k), static_cast<std::uint32_t>(k), 11);
                lanes.key[k] = samplers[k].key();
                for (int c = 0; c < 3; ++c) {
                    lanes.p[c][k] = 0.1f * static_cast<float>(c);
                    lanes.g[c][k] = lanes.n[c][k] = c == 1 ? 1.0f : 0.0f;
                    lanes.albedo[c][k] = lanes.beta[c][k] = 0.5f;
                }
                lanes.offset[k] = 1e-4f;
                lanes.etaScale[k] = 1.0f;
            }
            pathsimd::shade(table, lanes, count, depth, true);
            using dims::PathSlot;
            for (int k = 0; k < count; ++k) {
                const Sampler& s = samplers[k];
                EXPECT_EQ(lanes.uLobe[k], s.get1D(dims::path(depth, PathSlot::Lobe)));
                EXPECT_EQ(lanes.uLight[0][k], s.get2D(dims::path(depth, PathSlot::Light)).x);
                EXPECT_EQ(lanes.uLight[1][k], s.get2D(dims::path(depth, PathSlot::Light)).y);
                EXPECT_EQ(lanes.uBsdf[0][k], s.get2D(dims::path(depth, PathSlot::Bsdf)).x);
                EXPECT_EQ(lanes.uBsdf[1][k], s.get2D(dims::path(depth, PathSlot::Bsdf)).y);
                EXPECT_EQ(lanes.uRoulette[k], s.get1D(dims::path(depth, PathSlot::Roulette)));
            }
        }
    }
}

TEST(PathSimd, DrawsTheScalarSamplersNumbers) { forEachTarget(expectScalarSamplersNumbers); }

// Each lane of a lockstep packet against the same sample's path traced one ray at a time by the
// scalar code (tracePath). Highway's sine and cosine round differently from libm's, so a bounce
// direction may differ in its last bits and, rarely, a path then takes another way (an edge, a
// roulette draw at its threshold): the test bounds how many samples do, and how far the sums
// drift, well below what any wrong weight, pdf or light pick would give.
void expectLanesAgreeWithSingleRays(bool sky) {
    const Scene scene = simdRoom(sky);
    const EmbreeScene geometry(scene);
    const LightSet lights = buildLights(scene, geometry);
    ShadingSettings sh;
    sh.mode = ShadingMode::Path;
    sh.maxDepth = 8;
    sh.rouletteDepth = 2;
    const PathIntegrator integrator(geometry, lights, sh);
    ASSERT_TRUE(integrator.simdLanes());
    const glm::vec3 eye(0.0f, 1.0f, 0.95f);
    constexpr int W = Integrator::kMaxPacket;
    int compared = 0, differ = 0, pixelsDiffer = 0, pixels = 0;
    double sumLockstep = 0.0, sumSingle = 0.0;
    for (int pixel = 0; pixel < 512; ++pixel) {
        const int count = pixel % 3 == 0 ? 5 : W;
        RayPacket<W> packet;
        Sampler samplers[W];
        float spreads[W] = {};
        for (int i = 0; i < W; ++i) {
            samplers[i] = Sampler(static_cast<std::uint64_t>(pixel), static_cast<std::uint32_t>(i), 7);
            const glm::vec2 u = samplers[i].get2D(dims::kFilm);
            const glm::vec3 target(1.8f * u.x - 0.9f, 1.8f * u.y + 0.05f, -1.0f);
            packet.set(i, eye, glm::normalize(target - eye));
        }
        packet.traceFirst(geometry.handle(), count, true);
        glm::vec3 lockstep[W];
        RayCounts packetRays;
        integrator.primaryPacket(packet, count, samplers, spreads, lockstep, packetRays);
        RayCounts singleRays;
        glm::dvec3 pixelLockstep(0.0), pixelSingle(0.0);
        for (int i = 0; i < count; ++i) {
            const glm::vec3 single = integrator.primaryFromHit(packet.hit(i), packet.dir[i], samplers[i], singleRays);
            const glm::vec3 a = lockstep[i];
            EXPECT_TRUE(std::isfinite(a.x) && std::isfinite(a.y) && std::isfinite(a.z));
            const float scale = std::max({single.x, single.y, single.z, 1e-2f});
            const float diff = std::max({std::abs(a.x - single.x), std::abs(a.y - single.y), std::abs(a.z - single.z)});
            if (diff > 1e-4f * scale) ++differ;
            pixelLockstep += glm::dvec3(a);
            pixelSingle += glm::dvec3(single);
            ++compared;
        }
        const double pixelScale = std::max(pixelSingle.y, 1e-2 * count);
        if (std::abs(pixelLockstep.y - pixelSingle.y) > 1e-3 * pixelScale) ++pixelsDiffer;
        ++pixels;
        sumLockstep += pixelLockstep.y;
        sumSingle += pixelSingle.y;
        EXPECT_EQ(packetRays.primary, singleRays.primary);
    }
    EXPECT_GT(compared, 3500);
    EXPECT_GT(sumSingle, 0.05 * compared);  // lit: the comparison is not of zeros
    EXPECT_LE(differ, compared / 500) << differ << " of " << compared << " samples differ";
    EXPECT_LE(pixelsDiffer, pixels / 100) << pixelsDiffer << " of " << pixels << " pixels differ";
    EXPECT_NEAR(sumLockstep, sumSingle, 2e-5 * sumSingle);
}

TEST(PathSimd, LanesAgreeWithSingleRayPaths) {
    forEachTarget([] { expectLanesAgreeWithSingleRays(false); });
}

TEST(PathSimd, SkyLitLanesAgreeWithSingleRayPaths) {
    forEachTarget([] { expectLanesAgreeWithSingleRays(true); });
}

TEST(PathSimd, BitIdenticalFor1And2Threads) {
    const Scene scene = simdRoom();
    ShadingSettings sh;
    sh.mode = ShadingMode::Path;
    const TraceResult a = renderScene(scene, scene.views.front(), sh, 24, 3, 1);
    const TraceResult b = renderScene(scene, scene.views.front(), sh, 24, 3, 2);
    EXPECT_EQ(a.image.pixels(), b.image.pixels());
    EXPECT_EQ(a.rays.total(), b.rays.total());
    EXPECT_EQ(a.nonFiniteSamples, 0u);
}

// The furnace (tests/tracer/test_path.cpp, FurnaceSphereGivesLeOverOneMinusRho) is lit by one
// area light of 576 triangles: its known answer is reached through the SIMD lanes, the
// triangle picked by the lanes' binary search.
TEST(PathSimd, FurnaceRunsOnTheSimdLanes) {
    testing::SceneBuilder b;
    testing::furnaceSphere(b, {0.1f, -0.2f, 0.3f}, 0.5f, 1.0f);
    const EmbreeScene geometry(b.scene());
    const LightSet lights = buildLights(b.scene(), geometry);
    ShadingSettings sh;
    sh.mode = ShadingMode::Path;
    EXPECT_TRUE(PathIntegrator(geometry, lights, sh).simdLanes());
    // The same answer with the light sampled by area on the lanes: 1 / (1 - rho) within 1%.
    sh.maxDepth = 1000;
    const TraceResult r = renderScene(b.scene(), lookAt({0.1f, -0.2f, 0.3f}, {1, 0, 0}, 90), sh, 16, 6);
    double sum = 0.0;
    for (const glm::vec3& c : r.image.pixels()) sum += c.y;
    EXPECT_NEAR(sum / static_cast<double>(r.image.pixels().size()), 2.0, 0.02);
}

}  // namespace
}  // namespace aamap
