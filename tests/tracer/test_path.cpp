// Path mode (the shading ground truth) against answers it must reproduce, plus the robustness
// properties every mode shares: thread-count determinism and scale invariance.
#include <algorithm>
#include <cmath>
#include <vector>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include "tests/tracer/material_scenes.h"
#include "tracer/embree_scene.h"
#include "tracer/cache_integrator.h"
#include "tracer/direct_integrator.h"
#include "tracer/integrator.h"
#include "tracer/lights.h"
#include "tracer/path_integrator.h"
#include "tracer/ray_packet.h"
#include "tracer/sampler.h"

namespace aamap {
namespace {

using testing::lookAt;
using testing::renderScene;

// Furnace: inside a closed sphere of albedo rho that emits Le everywhere, radiance is
// Le (1 + rho + rho^2 + ...) = Le / (1 - rho) in every direction. Pixels are independent
// estimates, so their spread gives the standard error; the test needs it under 1/4 of the 1%
// tolerance to mean anything, and the mean within 4 standard errors and 1%.
TEST(PathMode, FurnaceSphereGivesLeOverOneMinusRho) {
    const float rho = 0.5f, le = 1.0f;
    testing::SceneBuilder b;
    testing::furnaceSphere(b, {0.1f, -0.2f, 0.3f}, rho, le);
    ShadingSettings sh;
    sh.mode = ShadingMode::Path;
    sh.maxDepth = 1000;  // Russian roulette ends the paths; truncation error rho^1000
    const int size = 32, strata = 6;
    const TraceResult r = renderScene(b.scene(), lookAt({0.1f, -0.2f, 0.3f}, {1, 0, 0}, 90), sh, size, strata);
    std::vector<double> v;
    for (const glm::vec3& c : r.image.pixels()) v.push_back(c.y);
    const auto [mean, error] = testing::meanError(v);
    const double want = le / (1.0 - rho);
    EXPECT_LT(4 * error, 0.01 * want) << "too few samples for a 1% test";
    EXPECT_NEAR(mean, want, 4 * error);
    EXPECT_NEAR(mean, want, 0.01 * want);
    EXPECT_EQ(r.nonFiniteSamples, 0u);
}

// roulette_depth is the first path segment that Russian roulette may end (Mitsuba's rr_depth).
// Inside a closed sphere every bounce ray hits something, and roulette draws from its own
// dimension, so the paths are the same with and without it until roulette ends one: from segment
// maxDepth on (past the last one traced) it never acts, from segment maxDepth - 1 on it ends some
// paths one bounce ray early, and starting earlier ends more.
TEST(PathMode, RouletteDepthIsTheFirstSegmentRouletteMayEnd) {
    testing::SceneBuilder b;
    testing::furnaceSphere(b, {0.0f, 0.0f, 0.0f}, 0.5f, 1.0f);
    const int size = 8, strata = 2, maxDepth = 5;
    const auto bounceRays = [&](bool roulette, int rouletteDepth) {
        ShadingSettings sh;
        sh.mode = ShadingMode::Path;
        sh.maxDepth = maxDepth;
        sh.russianRoulette = roulette;
        sh.rouletteDepth = rouletteDepth;
        return renderScene(b.scene(), lookAt({0, 0, 0}, {1, 0, 0}, 90), sh, size, strata).rays.other;
    };
    const std::uint64_t none = bounceRays(false, 1);
    const std::uint64_t paths = size * size * strata * strata;
    EXPECT_GE(none, paths * (maxDepth - 2)) << "nearly every path should bounce to the end";
    EXPECT_EQ(bounceRays(true, maxDepth), none) << "roulette from past the last segment must not act";
    const std::uint64_t last = bounceRays(true, maxDepth - 1);
    EXPECT_LT(last, none) << "roulette from the last segment on ends none";
    EXPECT_GE(last, none - paths) << "roulette from the last segment on can save at most one ray per path";
    EXPECT_LT(bounceRays(true, maxDepth - 2), last);
}

// A plane under an area light and a point light sees nothing else, so it has no indirect light:
// Path mode (NEE + MIS, BSDF samples that hit the light) must agree with Direct mode. Compared
// per pixel (same pixel, same point): the mean difference within 4 standard errors of the
// per-pixel differences. Lambert, and Lambert + Phong (the glossy sampling/eval pair); the area
// light sampled by solid angle or by area in each mode, so the MIS pdfs of both are checked
// against the other estimator.
void pathMatchesDirect(const Material& plane, LightSampling pathSampling, LightSampling directSampling);
void pathMatchesDirect(float ks, float ns, LightSampling pathSampling, LightSampling directSampling) {
    Material plane;
    plane.name = "plane";
    plane.kd = glm::vec3(0.5f);
    plane.ks = glm::vec3(ks);
    plane.ns = ns;
    pathMatchesDirect(plane, pathSampling, directSampling);
}
void pathMatchesDirect(const Material& plane, LightSampling pathSampling, LightSampling directSampling) {
    testing::SceneBuilder b;
    b.quad({-20, 0, -20}, {0, 0, 40}, {40, 0, 0}, testing::addMaterial(b, plane));
    b.areaLightQuad({-0.6f, 1.2f, -0.4f}, {1.2f, 0, 0}, {0, 0, 0.8f}, glm::vec3(3.0f, 2.0f, 1.0f));  // faces down
    b.pointLight({0.8f, 1.5f, 0.6f}, glm::vec3(1.0f, 2.0f, 3.0f));
    const View view = lookAt({0, 1.8f, 2.5f}, {0, 0, 0}, 50);
    ShadingSettings direct;
    direct.areaLightSamples = 256;  // its own noise is far below Path's
    direct.lightSampling = directSampling;
    ShadingSettings path;
    path.mode = ShadingMode::Path;
    path.lightSampling = pathSampling;
    // The same primary rays in both (same strata and seed): only shading differs.
    const int size = 32, strata = 6;
    const TraceResult d = renderScene(b.scene(), view, direct, size, strata);
    const TraceResult p = renderScene(b.scene(), view, path, size, strata);
    for (int c = 0; c < 3; ++c) {
        std::vector<double> diff, ref;
        for (std::size_t i = 0; i < d.image.pixels().size(); ++i) {
            diff.push_back(p.image.pixels()[i][c] - d.image.pixels()[i][c]);
            ref.push_back(d.image.pixels()[i][c]);
        }
        const auto [mean, error] = testing::meanError(diff);
        // Light selection between the two lights makes Path noisy; the test only means something
        // if 4 standard errors stay under 5% of the signal.
        EXPECT_LT(4 * error, 0.05 * testing::meanError(ref).mean) << "channel " << c;
        EXPECT_NEAR(mean, 0.0, 4 * error + 1e-4 * testing::meanError(ref).mean) << "channel " << c;
    }
}

TEST(PathMode, AgreesWithDirectWithoutIndirectLightAuto) {
    pathMatchesDirect(0.0f, 0.0f, LightSampling::Auto, LightSampling::Auto);
}
TEST(PathMode, AgreesWithDirectWithoutIndirectLightLambert) {
    pathMatchesDirect(0.0f, 0.0f, LightSampling::SolidAngle, LightSampling::Area);
}
TEST(PathMode, AgreesWithDirectWithoutIndirectLightGlossy) {
    pathMatchesDirect(0.4f, 30.0f, LightSampling::SolidAngle, LightSampling::SolidAngle);
}
TEST(PathMode, AgreesWithDirectWithoutIndirectLightByArea) {
    pathMatchesDirect(0.4f, 30.0f, LightSampling::Area, LightSampling::SolidAngle);
}

// Mitsuba's BSDFs (tracer/bsdf.h) through the same check: their sampling and pdf in path mode's
// MIS against direct mode's light sampling alone, and a delta lobe (smooth plastic, a mirror with
// a Lambert part) whose vertex must still sample the lights for the non-delta part.
Material modelPlane(BsdfModel model, MicrofacetType type, float au, float av) {
    Material m;
    m.name = "plane";
    m.model = model;
    m.distribution = type;
    m.alphaU = au;
    m.alphaV = av;
    m.kd = glm::vec3(0.6f, 0.4f, 0.2f);
    m.ior = 1.5f;
    m.eta = glm::vec3(0.2f, 0.9f, 1.1f);  // copper-like
    m.k = glm::vec3(3.9f, 2.4f, 2.1f);
    return m;
}
TEST(PathMode, AgreesWithDirectRoughConductorGgxAnisotropic) {
    pathMatchesDirect(modelPlane(BsdfModel::Conductor, MicrofacetType::GGX, 0.25f, 0.5f), LightSampling::SolidAngle,
                      LightSampling::SolidAngle);
}
TEST(PathMode, AgreesWithDirectRoughConductorBeckmann) {
    pathMatchesDirect(modelPlane(BsdfModel::Conductor, MicrofacetType::Beckmann, 0.3f, 0.3f), LightSampling::Area,
                      LightSampling::SolidAngle);
}
TEST(PathMode, AgreesWithDirectRoughPlastic) {
    pathMatchesDirect(modelPlane(BsdfModel::Plastic, MicrofacetType::GGX, 0.2f, 0.2f), LightSampling::SolidAngle,
                      LightSampling::SolidAngle);
}
TEST(PathMode, AgreesWithDirectSmoothPlastic) {
    pathMatchesDirect(modelPlane(BsdfModel::Plastic, MicrofacetType::Beckmann, 0.0f, 0.0f), LightSampling::SolidAngle,
                      LightSampling::SolidAngle);
}
TEST(PathMode, AgreesWithDirectMirrorWithLambertPart) {
    Material m;
    m.name = "plane";
    m.kind = MaterialKind::Mirror;
    m.kd = glm::vec3(0.5f);
    m.ks = glm::vec3(0.3f);
    pathMatchesDirect(m, LightSampling::SolidAngle, LightSampling::SolidAngle);
}

// Many lights (more than LightSet::kFewLights) switch Direct mode to power-CDF selection: by
// superposition its image must match the sum of one-light renders (the exact estimator).
TEST(DirectMode, ManyLightSelectionMatchesSumOfSingleLights) {
    const auto build = [](int only) {
        testing::SceneBuilder b;
        b.quad({-20, 0, -20}, {0, 0, 40}, {40, 0, 0}, b.material("plane", glm::vec3(0.6f)));
        // Every light quad is present in every scene (they cast shadows); only the chosen ones emit.
        const auto black = b.material("black", glm::vec3(0.0f));
        for (int i = 0; i < 10; ++i) {
            const bool on = only < 0 || i == only;
            const float x = -1.5f + 0.33f * i;
            const glm::vec3 le(1.0f + 0.3f * i, 2.0f, 3.0f - 0.2f * i);
            const glm::vec3 p0(x, 1.0f + 0.05f * i, -0.5f), a(0.2f, 0, 0), c(0, 0, 0.3f);  // faces down
            if (i % 3 == 0) {
                if (on) b.pointLight({x, 1.0f + 0.1f * i, 0.2f * i - 1.0f}, le * 0.5f);
            } else if (on) {
                b.areaLightQuad(p0, a, c, le);
            } else {
                b.quad(p0, a, c, black);
            }
        }
        return std::move(b.scene());
    };
    const View view = lookAt({0, 2.5f, 3.0f}, {0, 0, 0}, 50);
    ShadingSettings sh;
    sh.areaLightSamples = 256;
    const int size = 16;
    const TraceResult many = renderScene(build(-1), view, sh, size, 1);
    std::vector<glm::dvec3> sum(static_cast<std::size_t>(size * size), glm::dvec3(0.0));
    for (int i = 0; i < 10; ++i) {
        const TraceResult one = renderScene(build(i), view, sh, size, 1);
        for (std::size_t k = 0; k < sum.size(); ++k) sum[k] += glm::dvec3(one.image.pixels()[k]);
    }
    std::vector<double> diff, ref;
    for (std::size_t k = 0; k < sum.size(); ++k) {
        diff.push_back(many.image.pixels()[k].y - sum[k].y);
        ref.push_back(sum[k].y);
    }
    const auto [mean, error] = testing::meanError(diff);
    EXPECT_NEAR(mean, 0.0, 4 * error + 1e-4 * testing::meanError(ref).mean);
    EXPECT_LT(std::abs(mean), 0.02 * testing::meanError(ref).mean);
}

TEST(PathMode, BitIdenticalFor1And2And8Threads) {
    const Scene scene = testing::cornellLikeScene();
    ShadingSettings sh;
    sh.mode = ShadingMode::Path;
    const TraceResult a = renderScene(scene, scene.views.front(), sh, 24, 2, 1);
    const TraceResult b = renderScene(scene, scene.views.front(), sh, 24, 2, 2);
    const TraceResult c = renderScene(scene, scene.views.front(), sh, 24, 2, 8);
    EXPECT_EQ(a.image.pixels(), b.image.pixels());
    EXPECT_EQ(a.image.pixels(), c.image.pixels());
    EXPECT_EQ(a.rays.total(), c.rays.total());
}

Scene scaledRoom(float s);

// Path mode advances a packet's paths in lockstep and traces their shadow and bounce rays as
// packets; each lane must come out exactly as the path traced one ray at a time (the room has a
// mirror, glass, an area and a point light, and an open side that bounce rays escape through),
// with the same rays, for full and partly filled packets.
void expectLockstepEqualsSingleRays(const Scene& scene, ShadingMode mode = ShadingMode::Path);
TEST(PathMode, LockstepPacketsEqualSingleRayPaths) { expectLockstepEqualsSingleRays(scaledRoom(1.0f)); }
TEST(DirectMode, PacketsEqualSingleRays) { expectLockstepEqualsSingleRays(scaledRoom(1.0f), ShadingMode::Direct); }

// The room with Mitsuba's BSDFs: rough plastic walls, an anisotropic rough conductor for the
// mirror, a rough dielectric for the glass block (lights sampled through it, from both sides).
Scene withMitsubaBsdfs(Scene scene) {
    for (Material& m : scene.materials) {
        if (m.ke != glm::vec3(0.0f)) continue;
        m.distribution = MicrofacetType::GGX;
        m.alphaU = 0.2f;
        m.alphaV = 0.2f;
        if (m.kind == MaterialKind::Diffuse) {
            m.model = BsdfModel::Plastic;
            m.ior = 1.49f;
        } else if (m.kind == MaterialKind::Mirror) {
            m.model = BsdfModel::Conductor;
            m.distribution = MicrofacetType::Beckmann;
            m.alphaV = 0.05f;
            m.eta = glm::vec3(0.14f, 0.38f, 1.44f);
            m.k = glm::vec3(3.98f, 2.39f, 1.60f);
        } else {
            m.model = BsdfModel::Dielectric;
        }
    }
    return scene;
}

TEST(PathMode, LockstepPacketsEqualSingleRayPathsWithMitsubaBsdfs) {
    expectLockstepEqualsSingleRays(withMitsubaBsdfs(scaledRoom(1.0f)));
}

TEST(PathMode, BitIdenticalForAnyThreadCountWithMitsubaBsdfs) {
    const Scene scene = withMitsubaBsdfs(scaledRoom(1.0f));
    ShadingSettings sh;
    sh.mode = ShadingMode::Path;
    const View view = lookAt({0.0f, 1.0f, 3.9f}, {0, 0.8f, 0}, 60);
    const TraceResult a = renderScene(scene, view, sh, 24, 2, 1);
    const TraceResult c = renderScene(scene, view, sh, 24, 2, 8);
    EXPECT_EQ(a.image.pixels(), c.image.pixels());
    EXPECT_EQ(a.rays.total(), c.rays.total());
    EXPECT_EQ(a.nonFiniteSamples, 0u);
}

void expectLockstepEqualsSingleRays(const Scene& scene, ShadingMode mode) {
    const EmbreeScene geometry(scene);
    const LightSet lights = buildLights(scene, geometry);
    ShadingSettings sh;
    sh.mode = mode;
    sh.maxDepth = 8;
    const std::unique_ptr<Integrator> owned = makeIntegrator(geometry, lights, sh);
    const Integrator& integrator = *owned;
    const glm::vec3 eye(0.0f, 1.0f, 3.9f);
    constexpr int W = Integrator::kMaxPacket;
    int compared = 0;
    for (int pixel = 0; pixel < 256; ++pixel) {
        const int count = pixel % 3 == 0 ? 3 : W;
        RayPacket<W> packet;
        Sampler samplers[W];
        float spreads[W] = {};
        for (int i = 0; i < W; ++i) {
            samplers[i] = Sampler(static_cast<std::uint64_t>(pixel), static_cast<std::uint32_t>(i), 7);
            const glm::vec2 u = samplers[i].get2D(dims::kFilm);
            // Across the whole room, and out of its open side for some.
            const glm::vec3 target(2.4f * u.x - 1.2f, 2.2f * u.y - 0.1f, -1.0f);
            packet.set(i, eye, glm::normalize(target - eye));
        }
        packet.traceFirst(geometry.handle(), count, true);
        glm::vec3 lockstep[W];
        RayCounts packetRays;
        integrator.primaryPacket(packet, count, samplers, spreads, lockstep, packetRays);
        RayCounts singleRays;
        for (int i = 0; i < count; ++i) {
            const glm::vec3 single = integrator.primaryFromHit(packet.hit(i), packet.dir[i], samplers[i], singleRays);
            EXPECT_EQ(lockstep[i], single) << "pixel " << pixel << " lane " << i;
            ++compared;
        }
        EXPECT_EQ(packetRays.primary, singleRays.primary);
        EXPECT_EQ(packetRays.shadow, singleRays.shadow);
        EXPECT_EQ(packetRays.other, singleRays.other);
    }
    EXPECT_GT(compared, 1500);
}

// makeIntegrator is where a mode picks its integrator; the tracer asks that for its packet widths.
TEST(Integrators, FactoryPicksTheModesClassAndPacketWidths) {
    struct Constant final : IndirectDiffuseSource {
        glm::vec3 indirectIrradiance(const SurfaceHit&, const Sampler&, int, RayCounts&) const override {
            return glm::vec3(1.0f);
        }
    } source;
    const Scene scene = scaledRoom(1.0f);
    const EmbreeScene geometry(scene);
    const LightSet lights = buildLights(scene, geometry);
    ShadingSettings sh;
    const auto direct = makeIntegrator(geometry, lights, sh);
    EXPECT_NE(dynamic_cast<const DirectIntegrator*>(direct.get()), nullptr);
    EXPECT_EQ(dynamic_cast<const CacheIntegrator*>(direct.get()), nullptr);
    EXPECT_EQ(direct->packetWidth(1), 1);
    EXPECT_EQ(direct->packetWidth(3), 4);
    EXPECT_EQ(direct->packetWidth(5), 8);
    sh.mode = ShadingMode::Path;
    const auto path = makeIntegrator(geometry, lights, sh);
    EXPECT_NE(dynamic_cast<const PathIntegrator*>(path.get()), nullptr);
    EXPECT_EQ(path->packetWidth(1), 1);
    EXPECT_EQ(path->packetWidth(2), 8);
    sh.mode = ShadingMode::Cache;
    EXPECT_TRUE(readsIndirectDiffuse(sh));
    EXPECT_NE(dynamic_cast<const CacheIntegrator*>(makeIntegrator(geometry, lights, sh, &source).get()), nullptr);
    // Without a source Cache mode shades as Direct.
    const auto uncached = makeIntegrator(geometry, lights, sh);
    EXPECT_NE(dynamic_cast<const DirectIntegrator*>(uncached.get()), nullptr);
    EXPECT_EQ(dynamic_cast<const CacheIntegrator*>(uncached.get()), nullptr);
    sh.cache.bounces = 0;
    EXPECT_FALSE(readsIndirectDiffuse(sh));
}

// A room with a thin shelf 0.02 units above the floor, a mirror and a glass block, rendered at
// scale 1, 1e-3 and 1e4 (lights scaled to keep radiance): the images must match. A fixed
// absolute offset fails this (at 1e-3 the shelf gap is 2e-5: rays would start past the shelf).
Scene scaledRoom(float s) {
    testing::SceneBuilder b;
    const auto white = b.material("white", glm::vec3(0.7f));
    const auto mirror = testing::addMaterial(b, testing::mirrorMaterial(glm::vec3(0.9f)));
    const auto glass = testing::addMaterial(b, testing::glassMaterial(1.5f));
    const glm::vec3 X(2 * s, 0, 0), Y(0, 2 * s, 0), Z(0, 0, 2 * s), o(-s, 0, -s);
    b.quad(o, Z, X, white);
    b.quad(o + Y, X, Z, white);
    b.quad(o, X, Y, mirror);
    b.quad(o, Y, Z, white);
    b.quad(o + X, Z, Y, white);
    b.box(s * glm::vec3(-0.6f, 0.02f, -0.6f), s * glm::vec3(0.0f, 0.03f, 0.0f), white);  // the thin shelf
    b.box(s * glm::vec3(0.2f, 0.0f, -0.2f), s * glm::vec3(0.6f, 0.5f, 0.2f), glass);
    b.areaLightQuad(s * glm::vec3(-0.25f, 1.999f, -0.25f), s * glm::vec3(0.5f, 0, 0), s * glm::vec3(0, 0, 0.5f),
                    glm::vec3(10.0f));
    b.pointLight(s * glm::vec3(0.5f, 1.5f, 0.5f), s * s * glm::vec3(2.0f));
    Scene scene = std::move(b.scene());
    View v = lookAt(s * glm::vec3(0, 1, 3.9f), s * glm::vec3(0, 0.6f, 0), 45);
    scene.views.push_back(v);
    return scene;
}

void expectSameImage(const TraceResult& a, const TraceResult& b, const char* what) {
    int differ = 0;
    double sumA = 0, sumB = 0;
    for (std::size_t i = 0; i < a.image.pixels().size(); ++i) {
        const glm::vec3 x = a.image.pixels()[i], y = b.image.pixels()[i];
        sumA += x.y;
        sumB += y.y;
        if (std::abs(x.y - y.y) > 1e-3f * std::max(x.y, 1e-2f)) ++differ;
    }
    // Float rounding differs between scales, so a ray grazing an edge may land on the other side
    // in a few pixels; acne or leaks would change large areas.
    EXPECT_LE(differ, static_cast<int>(a.image.pixels().size() / 50)) << what;
    EXPECT_NEAR(sumB, sumA, 2e-3 * sumA) << what;
}

TEST(ScaleInvariance, SameImageAtScale1em3And1e4) {
    for (ShadingMode m : {ShadingMode::Direct, ShadingMode::Path}) {
        ShadingSettings sh;
        sh.mode = m;
        sh.areaLightSamples = 4;
        const Scene unit = scaledRoom(1.0f);
        const TraceResult ref = renderScene(unit, unit.views[0], sh, 32, 1);
        for (float s : {1e-3f, 1e4f}) {
            const Scene scaled = scaledRoom(s);
            const TraceResult r = renderScene(scaled, scaled.views[0], sh, 32, 1);
            expectSameImage(ref, r, toString(m));
        }
    }
}

// Cache mode at scale 1e-3 and 1e4. The cache decides by thresholds (a record covers a point when
// its error is below -aa), and float rounding differs between scales, so a few decisions flip and
// the record sets are not identical (1028 records at scale 1, 1009 and 998 scaled); what must hold
// is the same cache up to that: the record count within 4 %, the mean within 0.5 % (0.1 % seen),
// and at most 2 % of the pixels more than 5 % off (1.1-1.2 % seen: two valid record sets
// interpolate differently by a few per cent). A length left absolute (a radius, an offset, a
// tolerance) changes the record count by far more at one of the scales.
TEST(ScaleInvariance, CacheModeAtScale1em3And1e4) {
    ShadingSettings sh;
    sh.mode = ShadingMode::Cache;
    sh.areaLightSamples = 4;
    sh.cache.bounces = 2;
    sh.cache.divisions = 128;
    sh.cache.supersamples = 32;
    const Scene unit = scaledRoom(1.0f);
    const TraceResult ref = renderScene(unit, unit.views[0], sh, 32, 1);
    for (float s : {1e-3f, 1e4f}) {
        const Scene scaled = scaledRoom(s);
        const TraceResult r = renderScene(scaled, scaled.views[0], sh, 32, 1);
        double sumA = 0, sumB = 0, worst = 0;
        int off = 0;
        for (std::size_t i = 0; i < ref.image.pixels().size(); ++i) {
            const double a = ref.image.pixels()[i].y, b = r.image.pixels()[i].y;
            sumA += a;
            sumB += b;
            const double rel = std::abs(a - b) / std::max({a, b, 1e-2});
            worst = std::max(worst, rel);
            if (rel > 0.05) ++off;
        }
        EXPECT_NEAR(static_cast<double>(r.cache.records), static_cast<double>(ref.cache.records),
                    0.04 * static_cast<double>(ref.cache.records)) << "scale " << s;
        EXPECT_NEAR(sumB, sumA, 5e-3 * sumA) << "scale " << s;
        EXPECT_LE(off, static_cast<int>(ref.image.pixels().size() / 50)) << "scale " << s << ", worst " << worst;
    }
}

// Mitsuba's hide_emitters: what a camera ray sees directly -- an area light's emission, the
// environment where it escapes -- is black; a mirror's reflection of the same light is not (the
// emission is hidden at depth 0 only, in every mode).
TEST(HideEmitters, CameraRaysSeeNoEmitterAndMirrorsStillReflectIt) {
    testing::SceneBuilder b;
    const glm::vec3 le(10.0f);
    b.areaLightQuad({-5, -2, -2}, {0, 4, 0}, {0, 0, 4}, le);  // at x = -5, facing +x
    b.scene().materials.push_back(testing::mirrorMaterial(glm::vec3(1.0f)));
    b.quad({5, -2, -2}, {0, 0, 4}, {0, 4, 0}, static_cast<std::uint32_t>(b.scene().materials.size() - 1));
    EnvironmentLight sky;
    sky.name = "sky";
    sky.scale = glm::vec3(0.5f);
    b.scene().environment = sky;
    const auto mean = [&](ShadingMode mode, bool hide, glm::vec3 to) {
        ShadingSettings sh;
        sh.mode = mode;
        sh.hideEmitters = hide;
        const TraceResult r = renderScene(b.scene(), lookAt({0, 0, 0}, to, 10), sh, 8, 1);  // all on the quads
        double sum = 0.0;
        for (const glm::vec3& c : r.image.pixels()) sum += c.y;
        return sum / static_cast<double>(r.image.pixels().size());
    };
    for (ShadingMode mode : {ShadingMode::Direct, ShadingMode::Path, ShadingMode::Cache}) {
        SCOPED_TRACE(static_cast<int>(mode));
        EXPECT_NEAR(mean(mode, false, {-1, 0, 0}), le.y, 1e-3);  // the light, seen directly
        EXPECT_EQ(mean(mode, true, {-1, 0, 0}), 0.0);
        EXPECT_NEAR(mean(mode, false, {0, 0, -1}), 0.5, 1e-3);  // the sky, seen directly
        EXPECT_EQ(mean(mode, true, {0, 0, -1}), 0.0);
        EXPECT_GT(mean(mode, true, {1, 0, 0}), 0.9 * le.y);  // the light in the mirror
        EXPECT_NEAR(mean(mode, true, {1, 0, 0}), mean(mode, false, {1, 0, 0}), 1e-6);
    }
}

}  // namespace
}  // namespace aamap
