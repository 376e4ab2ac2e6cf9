// Cache mode end to end (tracer/irradiance_source.h): the irradiance cache against path tracing
// with the same light transport, determinism, the bounces-0 fallback, and the property selective
// rendering rests on (docs/tracer.md, the shading budget): 1 ray per pixel agrees with 36 away from edges.
#include <algorithm>
#include <cmath>
#include <span>
#include <utility>
#include <vector>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include "scene/builtin_scenes.h"
#include "scene/camera.h"
#include "tests/tracer/material_scenes.h"
#include "tracer/sampler.h"

namespace aamap {
namespace {

using testing::renderScene;

double luminance(const glm::vec3& c) { return 0.2126 * c.x + 0.7152 * c.y + 0.0722 * c.z; }

ShadingSettings cacheShading(int bounces = 1, int divisions = 512, int supersamples = 128) {
    ShadingSettings sh;
    sh.mode = ShadingMode::Cache;
    sh.cache.bounces = bounces;
    sh.cache.divisions = divisions;
    sh.cache.supersamples = supersamples;
    return sh;
}

// An axis-aligned rectangle of the Cornell box (metres): plane coordinate `axis` = `at`, the other
// two coordinates within [lo, hi]. Chosen so that no block stands between it and the camera.
struct Patch {
    const char* name;
    int axis;
    float at;
    glm::vec2 lo, hi;  // the two remaining coordinates in (x, y, z) order
};

// Pixels whose centre ray meets the patch, eroded by 2 pixels: every pixel within 2 (Chebyshev)
// of a kept pixel meets it too, so the kept ones are away from the patch's edges.
std::vector<int> patchPixels(const PinholeCamera& cam, int size, const Patch& patch) {
    std::vector<char> in(static_cast<std::size_t>(size) * size, 0);
    for (int y = 0; y < size; ++y)
        for (int x = 0; x < size; ++x) {
            const glm::vec3 d = cam.direction((x + 0.5f) / size, (y + 0.5f) / size);
            if (std::abs(d[patch.axis]) < 1e-6f) continue;
            const float t = (patch.at - cam.origin[patch.axis]) / d[patch.axis];
            if (!(t > 0.0f)) continue;
            const glm::vec3 p = cam.origin + t * d;
            const int a = (patch.axis + 1) % 3, b = (patch.axis + 2) % 3;
            const float pa = p[std::min(a, b)], pb = p[std::max(a, b)];
            in[static_cast<std::size_t>(y) * size + x] =
                pa >= patch.lo.x && pa <= patch.hi.x && pb >= patch.lo.y && pb <= patch.hi.y;
        }
    std::vector<int> kept;
    for (int y = 2; y < size - 2; ++y)
        for (int x = 2; x < size - 2; ++x) {
            bool all = true;
            for (int dy = -2; dy <= 2 && all; ++dy)
                for (int dx = -2; dx <= 2 && all; ++dx) all = in[static_cast<std::size_t>(y + dy) * size + x + dx] != 0;
            if (all) kept.push_back(y * size + x);
        }
    return kept;
}

// Cache mode at 1 ray per pixel (-ab 1) against Path mode with maxDepth 3 (camera, first hit,
// one diffuse bounce, light: docs/tracer.md counts segments as Mitsuba, so 2 would be direct light
// only). Both compute direct + one diffuse bounce; the cache hides emitters from its hemisphere
// rays exactly as MIS splits them into the first hit's direct light. Block means of luminance over
// flat patches within 2%. The reference is two independent renders A, B (seeds 5, 6) of
// strata^2 paths per pixel; its block mean's standard error is sqrt(sum (A_i - B_i)^2 / 4) / n
// and must be under 1/6 of the tolerance, so a pass is not luck.
// With `bounces` B the same holds against maxDepth B + 2.
void cacheMatchesPath(const Scene& scene, const View& view, int size, int strata, std::span<const Patch> patches,
                      int bounces = 1) {
    const TraceResult cache = renderScene(scene, view, cacheShading(bounces), size, 1);
    ShadingSettings path;
    path.mode = ShadingMode::Path;
    path.maxDepth = bounces + 2;
    path.russianRoulette = false;  // the same truncated series as the cache's B levels
    const TraceResult refA = renderScene(scene, view, path, size, strata, 0, 5);
    const TraceResult refB = renderScene(scene, view, path, size, strata, 0, 6);
    EXPECT_TRUE(cache.cache.built);
    const PinholeCamera cam = PinholeCamera::fromView(view);
    const auto Y = [](const TraceResult& r, int i) { return luminance(r.image.pixels()[static_cast<std::size_t>(i)]); };
    for (const Patch& patch : patches) {
        const std::vector<int> pixels = patchPixels(cam, size, patch);
        ASSERT_GE(pixels.size(), 40u) << patch.name;
        double sumCache = 0.0, sumRef = 0.0, sumD2 = 0.0;
        for (int i : pixels) {
            sumCache += Y(cache, i);
            sumRef += 0.5 * (Y(refA, i) + Y(refB, i));
            sumD2 += (Y(refA, i) - Y(refB, i)) * (Y(refA, i) - Y(refB, i));
        }
        const double n = static_cast<double>(pixels.size());
        const double cacheMean = sumCache / n, refMean = sumRef / n, refError = std::sqrt(sumD2 / 4.0) / n;
        EXPECT_LT(6.0 * refError, 0.02 * refMean) << patch.name << ": too few path samples for a 2% test";
        EXPECT_NEAR(cacheMean, refMean, 0.02 * refMean)
            << patch.name << ": " << pixels.size() << " pixels, path " << refMean << " +- " << refError;
    }
}

// From inside the box, straight up, so that the ceiling fills the image.
View ceilingView() {
    View up;
    up.position = {0.278f, 0.25f, 0.1f};
    up.direction = {0.0f, 1.0f, 0.0f};
    up.up = {0.0f, 0.0f, 1.0f};
    up.horizontalFovDeg = up.verticalFovDeg = 50.0f;
    return up;
}

// The published view: back wall and floor, lit directly and indirectly (SE measured 0.1%).
TEST(CacheMode, CornellWallAndFloorMatchPathWithOneBounce) {
    const Scene scene = builtinScene("cornell");
    const Patch patches[] = {
        {"back wall", 2, 0.5592f, {0.02f, 0.15f}, {0.24f, 0.53f}},  // left of the tall block
        {"floor", 1, 0.0f, {0.33f, 0.0f}, {0.54f, 0.2f}},          // in front of the blocks
    };
    cacheMatchesPath(scene, scene.views.front(), 64, 16, patches);
}

// The ceiling sees no light directly: all of it is the cache's bounce, the hardest case. Looked at
// from inside the box, straight up, so that the patch fills the image (SE measured 0.3%).
TEST(CacheMode, CornellCeilingMatchesPathWithOneBounce) {
    const Scene scene = builtinScene("cornell");
    const View up = ceilingView();
    const Patch patches[] = {{"ceiling", 1, 0.5488f, {0.03f, 0.0f}, {0.53f, 0.2f}}};  // in front of the light
    cacheMatchesPath(scene, up, 32, 24, patches);
}

// Multi-bounce: each level's records gather from the next level's, so B bounces of cache are B
// diffuse bounces of path tracing. The ceiling, lit only indirectly, with 3 bounces.
TEST(CacheMode, CornellCeilingMatchesPathWithThreeBounces) {
    const Scene scene = builtinScene("cornell");
    const View up = ceilingView();
    const Patch patches[] = {{"ceiling", 1, 0.5488f, {0.03f, 0.0f}, {0.53f, 0.2f}}};
    cacheMatchesPath(scene, up, 32, 24, patches, 3);
}

// A furnace: inside a closed sphere of albedo rho emitting Le everywhere, B cache bounces see
// Le (1 + rho + ... + rho^(B+1)): emission, direct light, then one term per level. The field is
// constant, so interpolation is exact and the only error is the records' hemisphere sampling.
// As B grows it converges to path mode's Le / (1 - rho).
TEST(CacheMode, FurnaceSphereSumsOneTermPerBounce) {
    const float rho = 0.5f, le = 1.0f;
    testing::SceneBuilder b;
    testing::furnaceSphere(b, {0.1f, -0.2f, 0.3f}, rho, le);
    for (int bounces : {1, 2, 4, 8}) {
        const TraceResult r = renderScene(b.scene(), testing::lookAt({0.1f, -0.2f, 0.3f}, {1, 0, 0}, 90),
                                          cacheShading(bounces), 16, 1);
        double want = 0.0;
        for (int i = 0; i <= bounces + 1; ++i) want += le * std::pow(rho, i);
        double mean = 0.0;
        for (const glm::vec3& c : r.image.pixels()) mean += c.y;
        mean /= static_cast<double>(r.image.pixels().size());
        EXPECT_NEAR(mean, want, 0.01 * want) << bounces << " bounces";
        if (bounces == 8) {
            EXPECT_NEAR(mean, le / (1.0 - rho), 0.01 * le / (1.0 - rho)) << "path mode's answer";
        }
    }
}

// The cache is frozen before the render and misses are not stored: any thread count gives the
// same image, records and ray counts. Rays are counted exactly: in a diffuse-only scene every
// "other" ray of the render is a hemisphere ray of a cache miss.
TEST(CacheMode, ImageIndependentOfThreadsAndRaysCounted) {
    const Scene scene = builtinScene("cornell");
    const int size = 32;
    const ShadingSettings sh = cacheShading(1, 128, 32);
    const TraceResult one = renderScene(scene, scene.views.front(), sh, size, 1, 1);
    const TraceResult two = renderScene(scene, scene.views.front(), sh, size, 1, 2);
    ASSERT_TRUE(one.cache.built);
    EXPECT_TRUE(std::equal(one.image.pixels().begin(), one.image.pixels().end(), two.image.pixels().begin()));
    EXPECT_EQ(one.cache.records, two.cache.records);
    EXPECT_EQ(one.cache.misses, two.cache.misses);
    EXPECT_EQ(one.rays.total(), two.rays.total());
    EXPECT_EQ(one.cache.prepassRays.total(), two.cache.prepassRays.total());

    EXPECT_EQ(one.rays.primary, static_cast<std::uint64_t>(size * size));
    EXPECT_EQ(one.rays.other, one.cache.missRays);
    // The probe render found the points the grid's records left uncovered, and records for them
    // leave the render proper (the same samples) no miss at all.
    EXPECT_GT(one.cache.probed, 0u);
    EXPECT_EQ(one.cache.misses, 0u);
    EXPECT_EQ(one.cache.probeRays.primary, static_cast<std::uint64_t>(size * size));
    EXPECT_EQ(one.cache.gridWidth, 32);
    EXPECT_EQ(one.cache.prepassRays.primary, 32u * 32u);
    EXPECT_GT(one.cache.prepassRays.other, one.cache.records * 128u);  // >= -ad rays per record
    EXPECT_GT(one.cache.prepassRays.shadow, one.cache.prepassRays.other);
}

// The Cornell box with Mitsuba's rough plastic on every wall: the cache stores irradiance, which
// the base reflects through the coating (bsdf::lambertEquivalent). Any thread count gives the same
// image, and the image is close to path mode's (the coating's angular weighting of the indirect
// light is averaged, so not exactly it).
TEST(CacheMode, RoughPlasticThreadIndependentAndCloseToPathMode) {
    Scene scene = builtinScene("cornell");
    for (Material& m : scene.materials)
        if (m.ke == glm::vec3(0.0f)) {
            m.model = BsdfModel::Plastic;
            m.distribution = MicrofacetType::GGX;
            m.alphaU = m.alphaV = 0.3f;
            m.ior = 1.49f;
        }
    const int size = 32;
    ShadingSettings sh = cacheShading(4, 128, 32);
    const TraceResult one = renderScene(scene, scene.views.front(), sh, size, 2, 1);
    const TraceResult two = renderScene(scene, scene.views.front(), sh, size, 2, 2);
    ASSERT_TRUE(one.cache.built);
    EXPECT_EQ(one.image.pixels(), two.image.pixels());
    EXPECT_EQ(one.nonFiniteSamples, 0u);
    ShadingSettings path;
    path.mode = ShadingMode::Path;
    path.maxDepth = 6;
    const TraceResult p = renderScene(scene, scene.views.front(), path, size, 8);
    glm::dvec3 meanCache(0.0), meanPath(0.0);
    for (std::size_t i = 0; i < p.image.pixels().size(); ++i) {
        meanCache += glm::dvec3(one.image.pixels()[i]);
        meanPath += glm::dvec3(p.image.pixels()[i]);
    }
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(meanCache[c] / meanPath[c], 1.0, 0.08) << "channel " << c;
}

// A closed white room (albedo 0.8, so the third bounce still carries a quarter of the indirect
// light), a block on the floor and a small ceiling light, seen from inside towards a corner: edges,
// corners, a contact shadow and a ceiling lit only indirectly. The cache with B = 3 bounces against
// path mode's max_depth 5 (no Russian roulette, two seeds for the reference's own error), as
// 4 x 4 block means of luminance. Each level's records hold that level's remaining bounces only,
// so the image mean agrees within the reference's error plus 0.5%; and as -ad, -as and -aa
// tighten, the blocks' mean error shrinks towards the reference's own (measured: 0.95% at -ad 64
// -aa 0.4, 0.28% at -ad 256 -aa 0.15, reference 0.28%). A record used at deeper levels than its
// own, as Radiance does, puts the mean 4.8% high.
TEST(CacheMode, ClosedRoomConvergesToPathAsSettingsTighten) {
    testing::SceneBuilder b;
    const auto white = b.material("white", glm::vec3(0.8f));
    const glm::vec3 X(2, 0, 0), Y(0, 2, 0), Z(0, 0, 2), o(-1, 0, -1);
    b.quad(o, Z, X, white);      // floor, faces +y
    b.quad(o + Y, X, Z, white);  // ceiling, faces -y
    b.quad(o, X, Y, white);      // back, faces +z
    b.quad(o + Z, Y, X, white);  // front, faces -z
    b.quad(o, Y, Z, white);      // left, faces +x
    b.quad(o + X, Z, Y, white);  // right, faces -x
    b.box({-0.6f, 0.0f, -0.6f}, {0.0f, 0.7f, 0.0f}, white);
    b.areaLightQuad({0.2f, 1.999f, 0.2f}, {0.3f, 0, 0}, {0, 0, 0.3f}, glm::vec3(40.0f));
    const View view = testing::lookAt({0.7f, 1.2f, 0.8f}, {-1.0f, 0.4f, -1.0f}, 90.0f);
    const int size = 24, blocks = 4, bs = size / blocks;
    ShadingSettings path;
    path.mode = ShadingMode::Path;
    path.maxDepth = 5;
    path.russianRoulette = false;
    const TraceResult refA = renderScene(b.scene(), view, path, size, 16, 0, 5);
    const TraceResult refB = renderScene(b.scene(), view, path, size, 16, 0, 6);
    const auto blockMeans = [&](const TraceResult& r) {
        std::vector<double> m(blocks * blocks, 0.0);
        for (int y = 0; y < size; ++y)
            for (int x = 0; x < size; ++x)
                m[(y / bs) * blocks + x / bs] += luminance(r.image.pixels()[static_cast<std::size_t>(y) * size + x]);
        return m;
    };
    const std::vector<double> a = blockMeans(refA), bm = blockMeans(refB);
    double refMean = 0.0, refNoise = 0.0;  // mean |A - B| / 2 relative: the reference's own block error
    for (std::size_t i = 0; i < a.size(); ++i) {
        refMean += 0.5 * (a[i] + bm[i]);
        refNoise += 0.5 * std::abs(a[i] - bm[i]) / (0.5 * (a[i] + bm[i]));
    }
    refNoise /= static_cast<double>(a.size());
    const auto error = [&](const TraceResult& r, double& mean) {
        const std::vector<double> c = blockMeans(r);
        double e = 0.0;
        mean = 0.0;
        for (std::size_t i = 0; i < c.size(); ++i) {
            const double ref = 0.5 * (a[i] + bm[i]);
            e += std::abs(c[i] - ref) / ref;
            mean += c[i];
        }
        return e / static_cast<double>(c.size());
    };
    ShadingSettings coarse = cacheShading(3, 64, 16);
    coarse.cache.accuracy = 0.4f;
    ShadingSettings fine = cacheShading(3, 256, 64);
    fine.cache.accuracy = 0.15f;
    double coarseMean = 0.0, fineMean = 0.0;
    const double coarseError = error(renderScene(b.scene(), view, coarse, size, 2), coarseMean);
    const double fineError = error(renderScene(b.scene(), view, fine, size, 2), fineMean);
    EXPECT_LT(refNoise, 0.01) << "too few path samples";
    EXPECT_NEAR(fineMean / refMean, 1.0, 0.005 + refNoise) << "coarse " << coarseMean / refMean;
    EXPECT_LT(fineError, coarseError);
    EXPECT_LT(fineError, 0.005 + refNoise) << "coarse " << coarseError << ", reference noise " << refNoise;
}

// -ab 0 means no cache: exactly the Direct image, and no pre-pass.
TEST(CacheMode, ZeroBouncesIsDirect) {
    const Scene scene = builtinScene("cornell");
    ShadingSettings direct;
    direct.mode = ShadingMode::Direct;
    const TraceResult d = renderScene(scene, scene.views.front(), direct, 24, 2);
    const TraceResult c = renderScene(scene, scene.views.front(), cacheShading(0), 24, 2);
    EXPECT_FALSE(c.cache.built);
    EXPECT_EQ(c.cache.prepassRays.total(), 0u);
    EXPECT_TRUE(std::equal(d.image.pixels().begin(), d.image.pixels().end(), c.image.pixels().begin()));
    EXPECT_EQ(d.rays.total(), c.rays.total());
}

// 1 ray per pixel against 36 in Cache mode, where the aamap would be zero, approximated by:
// - no geometric edge: the 3x3 neighbourhood in the 36-ray image is linear to within 2% (every
//   second difference through the pixel under 2% of its luminance; a plain "varies by < 2%" range
//   test would drop every pixel of a 64-pixel Cornell box, whose gradients exceed 2% per pixel);
// - no shadow boundary: two Direct renders (36 rays, seeds 5 and 7) agree within 0.2%, i.e. the
//   light's visibility is all or nothing (penumbrae are what the aamap's shadow edges cover).
// The 1-ray sample is compared with the 36-ray image's linear neighbourhood evaluated at its film
// position, so film jitter across a gradient does not count. Mean relative difference under 1%
// (measured 0.78% over ~260 pixels: cache misses and stratified light noise).
TEST(CacheMode, OneRayMatches36AwayFromEdges) {
    const Scene scene = builtinScene("cornell");
    const int size = 64;
    ShadingSettings sh = cacheShading(1, 256, 64);
    sh.cache.resolution = 16;  // coarser minimum radius: fewer misses in corners at this tiny size
    sh.cache.gridStep = 1;
    const TraceResult r1 = renderScene(scene, scene.views.front(), sh, size, 1);
    const TraceResult r36 = renderScene(scene, scene.views.front(), sh, size, 6);
    ShadingSettings direct;  // penumbrae: where the direct light's visibility is partial
    const TraceResult dA = renderScene(scene, scene.views.front(), direct, size, 6, 0, 5);
    const TraceResult dB = renderScene(scene, scene.views.front(), direct, size, 6, 0, 7);
    const auto Y = [&](const TraceResult& r, int x, int y) {
        return luminance(r.image.pixels()[static_cast<std::size_t>(y) * size + x]);
    };
    double sum = 0.0;
    int count = 0;
    for (int y = 1; y < size - 1; ++y)
        for (int x = 1; x < size - 1; ++x) {
            const double c = Y(r36, x, y);
            if (!(c > 1e-3)) continue;
            bool smooth = true;
            for (const auto& [dx, dy] : {std::pair{1, 0}, {0, 1}, {1, 1}, {1, -1}})
                smooth = smooth && std::abs(Y(r36, x - dx, y - dy) + Y(r36, x + dx, y + dy) - 2.0 * c) < 0.02 * c;
            const double a = Y(dA, x, y), b = Y(dB, x, y);
            if (!smooth || std::abs(a - b) > 0.002 * std::max(a, b)) continue;
            // The 1-ray sample's film position (as tracer.cpp draws it), where the linear
            // neighbourhood of the 36-ray image is evaluated: compares like with like.
            const Sampler sampler(static_cast<std::uint64_t>(y) * size + x, 0, 5);
            const glm::vec2 j = sampler.stratified2D(dims::kFilm, 0, 0, 1) - glm::vec2(0.5f);
            const double at = c + j.x * 0.5 * (Y(r36, x + 1, y) - Y(r36, x - 1, y)) +
                              j.y * 0.5 * (Y(r36, x, y + 1) - Y(r36, x, y - 1));
            sum += std::abs(Y(r1, x, y) - at) / at;
            ++count;
        }
    ASSERT_GE(count, size * size / 20) << "the smooth mask is too small to mean anything";
    EXPECT_LT(sum / count, 0.01) << count << " smooth pixels";
}

}  // namespace
}  // namespace aamap
