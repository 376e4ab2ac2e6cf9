// The irradiance cache against synthetic radiance fields with known answers, its determinism, and
// a Cornell-box pre-pass driven by a small Embree harness (tests/tracer/irradiance_harness.h).
#include <cmath>
#include <numbers>
#include <cstdio>
#include <cstdlib>
#include <limits>

#include <fmt/format.h>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include "scene/camera.h"
#include "tests/tracer/irradiance_harness.h"
#include "tests/tracer/scene_builder.h"
#include "tracer/embree_scene.h"
#include "tracer/irradiance_cache.h"
#include "tracer/irradiance_hemisphere.h"
#include "tracer/lights.h"

namespace aamap {
namespace {


Bounds box(glm::vec3 lo, glm::vec3 hi) { return Bounds{lo, hi}; }

IrradianceRecord record(glm::vec3 p, glm::vec3 n, float radius, glm::vec3 e = glm::vec3(1.0f)) {
    IrradianceRecord r;
    r.position = p;
    r.normal = glm::normalize(n);
    r.radius = radius;
    r.irradiance = e;
    return r;
}

// Points on the floor z = 0 of [0,2]^2, normal +z, in raster order.
std::vector<CachePoint> floorPoints(int k) {
    std::vector<CachePoint> pts;
    for (int y = 0; y < k; ++y)
        for (int x = 0; x < k; ++x)
            pts.push_back({{2.0f * (x + 0.5f) / k, 2.0f * (y + 0.5f) / k, 0.0f}, {0.0f, 0.0f, 1.0f}});
    return pts;
}

// An infinite ceiling z = h over the floor whose radiance is a + b * x at the point seen (x
// clamped far away so the cosine-weighted estimator has finite variance). E on the floor is then
// pi * (a + b x): the linear term integrates to zero around x by symmetry.
RadianceFn ceilingField(float a, float b, float h = 1.0f) {
    return [=](const glm::vec3& o, const glm::vec3& d, int, std::uint64_t) {
        RadianceSample s;
        if (!(d.z > 0.0f)) return s;
        const float t = (h - o.z) / d.z;
        const float x = std::clamp(o.x + t * d.x, -100.0f, 100.0f);
        s.radiance = glm::vec3(a + b * x, 2.0f * (a + b * x), a);
        s.distance = t;
        return s;
    };
}

TEST(IrradianceCache, ErrorAndWeightOnHandCases) {
    const IrradianceRecord r = record({0, 0, 0}, {0, 0, 1}, 2.0f);
    EXPECT_FLOAT_EQ(recordError(r, {0, 0, 0}, {0, 0, 1}), 0.0f);
    EXPECT_FLOAT_EQ(recordError(r, {1, 0, 0}, {0, 0, 1}), 0.5f);     // distance / R
    EXPECT_FLOAT_EQ(recordError(r, {0, 0.6f, 0.8f}, {0, 0, 1}), 0.5f);  // any direction
    // 60 degrees: sqrt(1 - cos) = sqrt(0.5).
    const glm::vec3 n60(std::sin(std::numbers::pi_v<float> / 3), 0.0f, std::cos(std::numbers::pi_v<float> / 3));
    EXPECT_NEAR(recordError(r, {0, 0, 0}, n60), std::sqrt(0.5f), 1e-6f);
    EXPECT_NEAR(recordError(r, {1, 0, 0}, n60), 0.5f + std::sqrt(0.5f), 1e-6f);

    // Acceptance is w > 1/a: with a = 0.2 and R = 2 the record covers p within 0.4.
    IrradianceCacheSettings s;
    s.accuracy = 0.2f;
    s.resolution = 0;
    IrradianceCache cache(s, box({-4, -4, -4}, {4, 4, 4}), ceilingField(1, 0));
    cache.insert(record({0, 0, 0}, {0, 0, 1}, 2.0f, glm::vec3(3.0f)));
    glm::vec3 e(-1.0f);
    EXPECT_TRUE(cache.interpolate({0.39f, 0, 0}, {0, 0, 1}, 0, e));
    EXPECT_EQ(e, glm::vec3(3.0f));
    EXPECT_FALSE(cache.interpolate({0.41f, 0, 0}, {0, 0, 1}, 0, e));
    EXPECT_FALSE(cache.interpolate({0, 0, 0}, glm::normalize(glm::vec3(0.3f, 0, 1)), 0, e));  // 1-cos > 0.04
    // Behind: a point below the record's tangent plane (across an inside corner) is not covered.
    EXPECT_FALSE(cache.interpolate({0.1f, 0, -0.2f}, {0, 0, 1}, 0, e));
    // Levels: a record is used at its own level only. A level-1 record is not used at level 0,
    // nor a level-0 record at level 1: it holds one bounce more than a level-1 lookup may add.
    IrradianceRecord deep = record({2, 2, 2}, {0, 0, 1}, 2.0f);
    deep.level = 1;
    cache.insert(deep);
    EXPECT_FALSE(cache.interpolate({2, 2, 2}, {0, 0, 1}, 0, e));
    EXPECT_TRUE(cache.interpolate({2, 2, 2}, {0, 0, 1}, 1, e));
    EXPECT_FALSE(cache.interpolate({0, 0, 0}, {0, 0, 1}, 1, e));
}

TEST(IrradianceCache, GradientExtrapolationIsExactForLinearFields) {
    // E_c(p, n) = E0_c + G_c . p + (n0 x n) . Q_c; records carry the exact gradients, so every
    // weighted blend of their extrapolations is exact.
    const glm::vec3 E0(4.0f, 5.0f, 6.0f);
    const glm::vec3 G[3] = {{0.3f, -0.2f, 0.0f}, {0.1f, 0.4f, 0.0f}, {-0.5f, 0.05f, 0.0f}};
    auto truth = [&](glm::vec3 p) { return E0 + glm::vec3(glm::dot(G[0], p), glm::dot(G[1], p), glm::dot(G[2], p)); };
    IrradianceCacheSettings s;
    s.accuracy = 0.3f;
    s.resolution = 0;
    IrradianceCache cache(s, box({0, 0, -1}, {2, 2, 1}), ceilingField(1, 0));
    for (const CachePoint& c : floorPoints(5)) {
        IrradianceRecord r = record(c.position, c.normal, 1.5f, truth(c.position));
        for (int ch = 0; ch < 3; ++ch) r.gradT[ch] = G[ch];
        cache.insert(r);
    }
    int tested = 0;
    for (float x = 0.1f; x < 1.9f; x += 0.137f)
        for (float y = 0.1f; y < 1.9f; y += 0.151f) {
            glm::vec3 e;
            ASSERT_TRUE(cache.interpolate({x, y, 0}, {0, 0, 1}, 0, e)) << x << "," << y;
            const glm::vec3 t = truth({x, y, 0});
            for (int ch = 0; ch < 3; ++ch) EXPECT_NEAR(e[ch], t[ch], 1e-5f * t[ch]);
            ++tested;
        }
    EXPECT_GT(tested, 100);
    // Rotational term by hand: turning n by a small angle about +y adds (n0 x n) . gradR.
    IrradianceRecord r = record({0, 0, 0}, {0, 0, 1}, 1.0f, glm::vec3(2.0f));
    r.gradR = {glm::vec3(0, 1, 0), glm::vec3(0, 2, 0), glm::vec3(1, 0, 0)};
    const glm::vec3 n = glm::normalize(glm::vec3(0.1f, 0.0f, 1.0f));
    const glm::vec3 turn = glm::cross(r.normal, n);  // (0, 0.0995, 0)
    const glm::vec3 e = extrapolate(r, {0, 0, 0}, n);
    EXPECT_NEAR(e.x, 2.0f + turn.y, 1e-6f);
    EXPECT_NEAR(e.y, 2.0f + 2.0f * turn.y, 1e-6f);
    EXPECT_NEAR(e.z, 2.0f, 1e-6f);
}

TEST(IrradianceCache, ConstantEnvironmentGivesPiL) {
    const glm::vec3 L(0.5f, 1.0f, 2.0f);
    const RadianceFn constant = [&](const glm::vec3&, const glm::vec3&, int, std::uint64_t) {
        return RadianceSample{L, 0.5f};
    };
    IrradianceCacheSettings s;
    s.divisions = 64;
    s.supersamples = 16;
    s.accuracy = 0.2f;
    s.resolution = 16;
    s.threads = 2;
    IrradianceCache cache(s, box({0, 0, 0}, {2, 2, 1}), constant);
    cache.build(floorPoints(12));
    ASSERT_GT(cache.records().size(), 4u);
    for (const IrradianceRecord& r : cache.records()) {
        for (int c = 0; c < 3; ++c) {
            EXPECT_NEAR(r.irradiance[c], std::numbers::pi_v<float> * L[c], 1e-5f * std::numbers::pi_v<float> * L[c]);
            EXPECT_NEAR(glm::length(r.gradT[c]), 0.0f, 1e-5f);
            EXPECT_NEAR(glm::length(r.gradR[c]), 0.0f, 1e-4f);
        }
        EXPECT_NEAR(r.radius, 0.5f, 1e-5f);  // harmonic mean of 0.5, within [2/16, 64*2/16]
    }
    const HemisphereLayout layout = hemisphereLayout(1024);  // Radiance: 18 x 57
    EXPECT_EQ(layout.theta, 18);
    EXPECT_EQ(layout.phi, 57);
    EXPECT_EQ(cache.stats().buildRays, cache.records().size() * (5u * 16u + 16u));  // 5 x 16 cells + -as
}

TEST(IrradianceCache, EstimatedGradientsMatchAnalyticFields) {
    // Translational: E = pi (a + b x) under the ceiling, so dE_r/dx = pi b.
    const float a = 1.0f, b = 0.2f;
    const RadianceFn field = ceilingField(a, b);
    const HemisphereEstimate est = sampleHemisphere({1, 1, 0}, {0, 0, 1}, 1e-4f, 1024, 256, 1, 7, field);
    EXPECT_NEAR(est.irradiance.x, std::numbers::pi_v<float> * (a + b), 0.01f * std::numbers::pi_v<float> * (a + b));
    EXPECT_NEAR(est.gradT[0].x, std::numbers::pi_v<float> * b, 0.1f * std::numbers::pi_v<float> * b);
    EXPECT_NEAR(est.gradT[0].y, 0.0f, 0.05f * std::numbers::pi_v<float> * b);
    EXPECT_NEAR(est.gradT[2].x, 0.0f, 1e-4f);  // the blue channel is constant
    EXPECT_NEAR(est.harmonicDistance, 1.0f / (2.0f / 3.0f), 0.05f);  // 1 / E[cos] over cosine weighting
    // Rotational: L(w) = 1 + c.w gives E(n) = pi + (2 pi / 3) c.n, so gradR = (2 pi / 3) n x c.
    const glm::vec3 cdir(0.4f, -0.3f, 0.2f);
    const RadianceFn directional = [&](const glm::vec3&, const glm::vec3& d, int, std::uint64_t) {
        return RadianceSample{glm::vec3(1.0f + glm::dot(cdir, d)), 1.0f};
    };
    const glm::vec3 n(0, 0, 1);
    const HemisphereEstimate rot = sampleHemisphere({0, 0, 0}, n, 1e-4f, 1024, 0, 1, 9, directional);
    const glm::vec3 expected = (2.0f * std::numbers::pi_v<float> / 3.0f) * glm::cross(n, cdir);
    EXPECT_NEAR(rot.gradR[1].x, expected.x, 0.05f * glm::length(expected));
    EXPECT_NEAR(rot.gradR[1].y, expected.y, 0.05f * glm::length(expected));
    EXPECT_NEAR(rot.gradR[1].z, 0.0f, 1e-5f);
}

TEST(IrradianceCache, InterpolatesAPlaneUnderALinearField) {
    const float a = 1.0f, b = 0.3f;
    IrradianceCacheSettings s;
    s.divisions = 256;
    s.supersamples = 64;
    s.accuracy = 0.15f;
    s.resolution = 32;
    s.threads = 2;
    IrradianceCache cache(s, box({0, 0, 0}, {2, 2, 1}), ceilingField(a, b));
    cache.build(floorPoints(16));
    const std::size_t built = cache.records().size();
    double worst = 0.0;
    for (float x = 0.3f; x < 1.7f; x += 0.0713f)
        for (float y = 0.3f; y < 1.7f; y += 0.0917f) {
            const glm::vec3 e = cache.irradiance({x, y, 0}, {0, 0, 1}, 0);
            const float t = std::numbers::pi_v<float> * (a + b * x);
            worst = std::max(worst, std::abs(static_cast<double>(e.x - t)) / t);
            EXPECT_NEAR(e.y, 2.0f * e.x, 1e-3f * e.y);
        }
    EXPECT_LT(worst, 0.02);
    EXPECT_EQ(cache.records().size(), built);  // lookups never insert
    EXPECT_LT(cache.stats().renderMisses, 10u);
    // Bounces 0: no cache at all.
    s.bounces = 0;
    IrradianceCache off(s, box({0, 0, 0}, {2, 2, 1}), ceilingField(a, b));
    off.build(floorPoints(4));
    EXPECT_TRUE(off.records().empty());
    EXPECT_EQ(off.irradiance({1, 1, 0}, {0, 0, 1}, 0), glm::vec3(0.0f));
}

// Two bounces between the floor z = 0 and a ceiling z = 1 that emit (the ceiling a pattern): the ceiling's
// level-1 records are made on the way (nothing on it is a candidate).
std::vector<IrradianceRecord> buildTwoBounce(int threads, IrradianceCacheStats* stats = nullptr) {
    IrradianceCacheSettings s;
    s.bounces = 2;
    s.divisions = 48;
    s.supersamples = 12;
    s.accuracy = 0.25f;
    s.resolution = 16;
    s.threads = threads;
    s.seed = 5;
    const IrradianceCache* self = nullptr;
    const RadianceFn fn = [&](const glm::vec3& o, const glm::vec3& d, int depth, std::uint64_t seed) {
        RadianceSample r;
        const bool up = d.z > 0.0f;
        if (std::abs(d.z) < 1e-6f) return r;
        const float t = ((up ? 1.0f : 0.0f) - o.z) / d.z;
        const glm::vec3 q = o + t * d;
        r.distance = t;
        const glm::vec3 nq(0, 0, up ? -1.0f : 1.0f);
        if (up) r.radiance += glm::vec3(1.0f + 0.5f * std::sin(3.0f * q.x), 1.0f, 0.5f + 0.4f * std::cos(2.0f * q.y));
        else r.radiance += glm::vec3(0.2f);  // so that the ceiling's records are not black
        // The seed is the callback's to use: a deterministic dither proves it is passed through.
        r.radiance *= 1.0f + 0.01f * static_cast<float>(seed >> 60);
        r.radiance += 0.5f / std::numbers::pi_v<float> * self->irradiance({q.x, q.y, up ? 1.0f : 0.0f}, nq, depth);
        return r;
    };
    IrradianceCache cache(s, box({0, 0, 0}, {2, 2, 1}), fn);
    self = &cache;
    cache.build(floorPoints(10));
    if (stats) *stats = cache.stats();
    return {cache.records().begin(), cache.records().end()};
}

TEST(IrradianceCache, DeterministicForAnyThreadCount) {
    IrradianceCacheStats stats;
    const auto one = buildTwoBounce(1, &stats);
    const auto again = buildTwoBounce(1);
    const auto two = buildTwoBounce(2);
    const auto four = buildTwoBounce(4);
    ASSERT_GT(one.size(), 4u);
    EXPECT_TRUE(one == again);
    EXPECT_TRUE(one == two);
    EXPECT_TRUE(one == four);
    ASSERT_EQ(stats.recordsPerLevel.size(), 2u);
    EXPECT_GT(stats.recordsPerLevel[1], 0u);  // the ceiling got records
    for (const IrradianceRecord& r : one) EXPECT_GT(r.irradiance.x, 0.0f);
}

Bounds meshBounds(const Scene& scene) {
    Bounds b{glm::vec3(std::numeric_limits<float>::max()), glm::vec3(-std::numeric_limits<float>::max())};
    for (const glm::vec3& p : scene.mesh.positions) {
        b.lo = glm::min(b.lo, p);
        b.hi = glm::max(b.hi, p);
    }
    return b;
}

struct CornellRun {
    std::vector<IrradianceRecord> records;
    IrradianceCacheStats stats;
    std::size_t points = 0;
};

// The Cornell-like box through the Embree harness: 1 bounce unless told otherwise.
CornellRun cornellPrePass(const IrradianceCacheSettings& s, int grid, int lightGrid = 2) {
    const Scene scene = testing::cornellLikeScene();
    const EmbreeScene geometry(scene);
    const LightSet lights = buildLights(scene, geometry);
    testing::CacheHarness harness(geometry, lights, lightGrid);
    IrradianceCache cache(s, meshBounds(scene), harness.fn());
    harness.attach(cache);
    const auto points = cameraCachePoints(geometry, PinholeCamera::fromView(scene.views.front()), grid, grid);
    cache.build(points);
    return {{cache.records().begin(), cache.records().end()}, cache.stats(), points.size()};
}

TEST(IrradianceCache, CornellPrePassIsDeterministicAndPlausible) {
    IrradianceCacheSettings s;
    s.divisions = 64;
    s.supersamples = 16;
    s.threads = 1;
    const CornellRun one = cornellPrePass(s, 24);
    s.threads = 2;
    const CornellRun two = cornellPrePass(s, 24);
    ASSERT_GT(one.records.size(), 10u);
    EXPECT_TRUE(one.records == two.records);
    EXPECT_LT(one.records.size(), one.points);  // most points were covered, not recomputed
    std::size_t dark = 0;
    for (const IrradianceRecord& r : one.records) {
        // Inside a closed white box lit from above, surfaces get some indirect light, and far less
        // than the light's direct irradiance on the floor (~ 17 * 0.25 / 4 = 1). Points exactly on
        // an outer edge (x = 1.0000001 on the floor) see the outside of the box: black.
        dark += brightness(r.irradiance) > 0.0f ? 0 : 1;
        EXPECT_LT(brightness(r.irradiance), 5.0f);
        EXPECT_GE(r.radius, 2.0f / static_cast<float>(s.resolution) * 0.999f);  // scene size 2 / -ar
    }
    EXPECT_LT(dark * 20, one.records.size());
}

// docs/irradiance-cache.md, "Measurements": records grow much more slowly than the candidate
// points (the extra ones fill corners, where the radius is at its minimum), and the pre-pass cost
// is linear in the records: each record costs about the same hemisphere rays at every grid.
// AAMAP_IC_BENCH=1 also prints the table of that section (-ab 1 and 2, -ad 128 and 512).
TEST(IrradianceCache, CornellPrePassRecordsGrowSlowerThanPoints) {
    IrradianceCacheSettings s;
    s.divisions = 64;
    s.supersamples = 16;
    const CornellRun coarse = cornellPrePass(s, 32), fine = cornellPrePass(s, 64);
    ASSERT_GT(coarse.records.size(), 0u);
    const double points = static_cast<double>(fine.points) / static_cast<double>(coarse.points);
    const double growth = static_cast<double>(fine.records.size()) / static_cast<double>(coarse.records.size());
    ASSERT_GT(points, 3.0);  // 4x the camera rays; a few miss
    EXPECT_GT(growth, 1.0);
    EXPECT_LT(growth, 0.6 * points) << "records should grow far more slowly than the points";
    const auto raysPerRecord = [](const CornellRun& r) {
        return static_cast<double>(r.stats.buildRays) / static_cast<double>(r.records.size());
    };
    EXPECT_GE(raysPerRecord(coarse), s.divisions);
    EXPECT_NEAR(raysPerRecord(fine) / raysPerRecord(coarse), 1.0, 0.25);

    if (std::getenv("AAMAP_IC_BENCH") == nullptr) return;
    for (int bounces : {1, 2})
        for (int ad : {128, 512})
            for (int grid : {32, 64, 128}) {
                IrradianceCacheSettings t;
                t.bounces = bounces;
                t.divisions = ad;
                t.supersamples = ad / 4;
                const CornellRun run = cornellPrePass(t, grid, 4);
                std::printf("ab %d ad %4d as %3d grid %3d: %6zu points -> %5zu records (%s), %3zu batches, %7.3f s, %9llu "
                            "hemisphere rays\n",
                            bounces, ad, t.supersamples, grid, run.points, run.stats.records,
                            bounces > 1 ? fmt::format("{} at level 1", run.stats.recordsPerLevel[1]).c_str() : "",
                            run.stats.batches, run.stats.buildSeconds,
                            static_cast<unsigned long long>(run.stats.buildRays));
            }
}

}  // namespace
}  // namespace aamap
