// The sub-pixel aamap (snapshot.map: subpixel; glsl/shared/subpixel_map.h): the GPU pass against
// its CPU reference on the same samples, the FLIP tolerance against the metrics' colour pipeline,
// and known answers from whole Snapshots: smooth shading (a plane in a wide penumbra of a large
// area light, a glossy sphere's highlight) flags nothing, every pixel a hard edge crosses is
// flagged, and so is a one-pixel wire along its length.
#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <stdexcept>
#include <string>

#include <glm/geometric.hpp>

#include "eval/metrics/flip_color.h"
#include "glsl/shared/subpixel_map.h"
#include "gpu_fixture.h"
#include "passes/cpu_subpixel.h"
#include "passes/snapshot.h"
#include "passes/subpixel_map.h"
#include "scene/camera.h"
#include "scene/lights.h"
#include "tests/common/test_scenes.h"

namespace aamap::test {
namespace {

class SubpixelTest : public GpuTest {};

// k x k blocks of random content: flat pixels, smooth ramps, hard steps and geometry changes,
// far from the rule's thresholds so float rounding cannot decide differently on the two sides.
struct Samples {
    ImageRGB colour;
    cpu::GeometryImages geometry;
};

Samples randomSamples(int W, int H, int k, std::uint32_t seed) {
    std::mt19937 rng(seed);
    const int Ws = k * W, Hs = k * H;
    Samples s{ImageRGB(Ws, Hs), {Image<glm::vec4>(Ws, Hs), Image<glm::vec4>(Ws, Hs)}};
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) {
            const int kind = static_cast<int>(rng() % 6);  // flat (3 in 6), ramp, step, another object
            // A smooth field, so that neighbouring flat pixels agree.
            const glm::vec3 a(0.4f + 0.2f * std::sin(0.05f * x), 0.5f + 0.2f * std::cos(0.04f * y), 0.3f);
            const glm::vec3 b = kind == 4 ? glm::vec3(1.0f) - a : a;
            for (int j = 0; j < k; ++j)
                for (int i = 0; i < k; ++i) {
                    const int sx = k * x + i, sy = k * y + j;
                    glm::vec3 c = i < k / 2 ? a : b;
                    if (kind == 3) c = a * (1.0f + 0.02f * static_cast<float>(i + j));
                    s.colour.at(sx, sy) = c;
                    const bool other = kind == 5 && i == 0 && j == 0;  // uncovered, or another object
                    const float depth = 2.0f + 0.001f * static_cast<float>(sx + sy);
                    s.geometry.normalDepth.at(sx, sy) = other && x % 2 ? glm::vec4(0.0f) : glm::vec4(0, 0, 1, depth);
                    s.geometry.ids.at(sx, sy) = glm::vec4(other ? 1.0f : 0.0f, 1, 0, 0);
                }
        }
    return s;
}

// Shared shading's colour: one shade per pixel, its last sample of the first row (the step's far
// side in a step pixel, so that neighbouring shades differ there).
ImageRGB pixelShades(const ImageRGB& samples, int k) {
    ImageRGB shades(samples.width() / k, samples.height() / k);
    for (int y = 0; y < shades.height(); ++y)
        for (int x = 0; x < shades.width(); ++x) shades.at(x, y) = samples.at(k * x + k - 1, k * y);
    return shades;
}

TEST_F(SubpixelTest, PassMatchesCpuReference) {
    passes::GpuSubpixelMap gpu(context());
    const float tau = subpixelTolerance(0.1f);
    for (bool shared : {false, true})
    for (int k = SUBPIXEL_MIN_K; k <= SUBPIXEL_MAX_K; ++k)
        for (auto [W, H] : {std::pair{37, 23}, std::pair{1, 1}, std::pair{5, 1}}) {
            Samples s = randomSamples(W, H, k, static_cast<std::uint32_t>(k * 1000 + W));
            if (shared) s.colour = pixelShades(s.colour, k);
            for (float exposure : {1.0f, 2.5f}) {
                const cpu::SubpixelImages expected = cpu::subpixelMap(s.colour, s.geometry, k, exposure, tau, shared);
                const ImageGrey got = gpu.map(s.colour, s.geometry, {k, exposure, tau, shared});
                ASSERT_EQ(got.width(), W);
                ASSERT_EQ(got.height(), H);
                int flagged = 0;
                for (int y = 0; y < H; ++y)
                    for (int x = 0; x < W; ++x) {
                        const float e = expected.error.at(x, y);
                        // The same samples, the same rule: equal up to the GPU's pow and division.
                        EXPECT_NEAR(got.at(x, y), expected.map.at(x, y), 1e-5f)
                            << shared << " " << k << " " << x << "," << y;
                        if (std::abs(e - tau) > 1e-4f) {
                            EXPECT_EQ(got.at(x, y) > 0.0f, e > tau) << shared << " " << k << " " << x << "," << y;
                        }
                        flagged += e > tau;
                    }
                if (W * H > 100) {  // a real mix of flagged and smooth pixels
                    EXPECT_GT(flagged, W * H / 10) << shared << " " << k;
                    EXPECT_LT(flagged, W * H * 9 / 10) << shared << " " << k;
                }
            }
        }
    const Samples s = randomSamples(4, 4, 2, 1);
    EXPECT_THROW(cpu::subpixelMap(s.colour, s.geometry, 5, 1.0f, tau, false), std::invalid_argument);
    EXPECT_THROW(cpu::subpixelMap(s.colour, s.geometry, 3, 1.0f, tau, false), std::invalid_argument);  // 8 not a multiple of 3
    EXPECT_THROW(cpu::subpixelMap(s.colour, s.geometry, 2, 1.0f, tau, true), std::invalid_argument);  // colour k W x k H
    EXPECT_THROW(cpu::subpixelMap(pixelShades(s.colour, 2), s.geometry, 2, 1.0f, tau, false), std::invalid_argument);
}

// Shades at the extremes (NaN, infinities, negative, 1e30) and exposures from 1e-6 to 1e6: the
// display transform takes them to [0, 1] (non-finite to 0), so GPU and CPU agree and every map
// value stays finite in [0, 1), at both shading rates.
TEST_F(SubpixelTest, ExtremeShadesStayInRange) {
    passes::GpuSubpixelMap gpu(context());
    const float tau = subpixelTolerance(0.1f);
    const float extremes[] = {std::numeric_limits<float>::quiet_NaN(), std::numeric_limits<float>::infinity(),
                              -std::numeric_limits<float>::infinity(), -1.0f, 1e30f, 0.0f, 1e-30f};
    for (bool shared : {false, true})
        for (int k : {2, 4}) {
            Samples s = randomSamples(19, 11, k, static_cast<std::uint32_t>(77 + k));
            if (shared) s.colour = pixelShades(s.colour, k);
            std::mt19937 rng(5);
            for (glm::vec3& c : s.colour.pixels())
                if (rng() % 3 == 0) c[rng() % 3] = extremes[rng() % std::size(extremes)];
            for (float exposure : {1e-6f, 1.0f, 1e6f}) {
                const cpu::SubpixelImages expected = cpu::subpixelMap(s.colour, s.geometry, k, exposure, tau, shared);
                const ImageGrey got = gpu.map(s.colour, s.geometry, {k, exposure, tau, shared});
                for (int y = 0; y < got.height(); ++y)
                    for (int x = 0; x < got.width(); ++x) {
                        const float v = got.at(x, y);
                        ASSERT_TRUE(std::isfinite(v) && v >= 0.0f && v < 1.0f) << v << " at " << x << "," << y;
                        EXPECT_NEAR(v, expected.map.at(x, y), 1e-5f) << shared << " " << k << " " << exposure;
                    }
            }
        }
}

// tau is the display-value step at which FLIP's colour error (without its spatial filter)
// reaches the threshold: check it on grey steps against the metrics' own colour pipeline.
TEST_F(SubpixelTest, ToleranceIsTheFlipThresholdInDisplayValues) {
    EXPECT_NEAR(SUBPIXEL_FLIP_CMAX, metrics::flip::maxColourDistance(), 1e-3);
    for (float t : {0.05f, 0.1f, 0.2f}) {
        const float tau = subpixelTolerance(t);
        EXPECT_GT(tau, 0.0f);
        for (float v : {0.3f, 0.5f, 0.8f}) {  // grey display values: L* is about 100 v
            const auto lab = [](float display) {
                const float linear = metrics::flip::srgbToLinear(display);
                return metrics::flip::hunt(
                    metrics::flip::xyzToLab(metrics::flip::linearRgbToXyz(glm::vec3(linear))));
            };
            const float e = metrics::flip::redistribute(
                std::pow(metrics::flip::hyab(lab(v), lab(v + tau)), static_cast<float>(SUBPIXEL_FLIP_QC)));
            EXPECT_NEAR(e, t, 0.15f * t) << "t " << t << " grey " << v;
        }
    }
    EXPECT_LT(subpixelTolerance(0.05f), subpixelTolerance(0.1f));
}

// What the camera ray through image point (u, v) in [0,1]^2 hits on the plane z = 0.
glm::vec2 onFloor(const PinholeCamera& camera, float u, float v) {
    const glm::vec3 d = camera.direction(u, v);
    const glm::vec3 q = camera.origin - (camera.origin.z / d.z) * d;
    return {q.x, q.y};
}

Material emitter(const std::string& name, glm::vec3 ke) {
    Material m;
    m.name = name;
    m.kd = glm::vec3(0.0f);
    m.ke = ke;
    return m;
}

// A convex quad a, b, c, d (counter-clockwise seen from +z) at height z, facing +z.
void addQuadAt(Scene& s, glm::vec2 a, glm::vec2 b, glm::vec2 c, glm::vec2 d, float z, std::uint32_t material) {
    const auto base = static_cast<std::uint32_t>(s.mesh.positions.size());
    for (glm::vec2 p : {a, b, c, d}) {
        s.mesh.positions.push_back({p.x, p.y, z});
        s.mesh.normals.push_back({0, 0, 1});
    }
    s.mesh.triangles.insert(s.mesh.triangles.end(), {{base, base + 1, base + 2}, {base, base + 2, base + 3}});
    s.mesh.materialIds.insert(s.mesh.materialIds.end(), 2, material);
    s.mesh.objectIds.insert(s.mesh.objectIds.end(), 2, material);
}

constexpr passes::SubpixelShading kShadings[] = {passes::SubpixelShading::Pixel, passes::SubpixelShading::Sample};

// Colour raster texels per render pixel side.
int colourScale(const SnapshotSettings& settings) {
    return settings.subpixelShading == passes::SubpixelShading::Pixel ? 1 : settings.subpixel;
}

int countFlagged(const ImageGrey& map) {
    return static_cast<int>(std::count_if(map.pixels().begin(), map.pixels().end(), [](float v) { return v > 0.0f; }));
}

// A floor seen from below a 2 x 2 area light, with a plate behind the camera that shades the
// whole view with one wide penumbra: shading varies across the image but not within a pixel.
TEST_F(SubpixelTest, PlaneInAWidePenumbraFlagsNothing) {
    Scene scene;
    Material floor;
    floor.name = "floor";
    floor.kd = glm::vec3(0.7f);
    scene.materials = {floor, emitter("lamp", glm::vec3(3.0f))};
    addQuadZ(scene, 0.0f, -5.0f, 5.0f, -5.0f, 5.0f, 0);
    // The lamp at z = 1 facing down (its triangles wound clockwise seen from +z).
    const auto lamp = static_cast<std::uint32_t>(scene.mesh.positions.size());
    scene.mesh.positions.insert(scene.mesh.positions.end(), {{-1, -1, 1}, {1, -1, 1}, {1, 1, 1}, {-1, 1, 1}});
    scene.mesh.normals.insert(scene.mesh.normals.end(), 4, glm::vec3(0, 0, -1));
    scene.mesh.triangles.insert(scene.mesh.triangles.end(), {{lamp, lamp + 2, lamp + 1}, {lamp, lamp + 3, lamp + 2}});
    scene.mesh.materialIds.insert(scene.mesh.materialIds.end(), 2, 1u);
    scene.mesh.objectIds.insert(scene.mesh.objectIds.end(), 2, 1u);
    scene.areaLights = buildAreaLights(scene);
    ASSERT_EQ(scene.areaLights.size(), 1u);
    // The plate x < 0 at z = 0.9 (above the camera, so out of view) hides part of the lamp from
    // every visible floor point: a penumbra 18 units wide.
    Material plate = floor;
    plate.name = "plate";
    scene.materials.push_back(plate);
    addQuadAt(scene, {-5, -5}, {0, -5}, {0, 5}, {-5, 5}, 0.9f, 2);

    const View view = viewDownZ({0.1f, 0.0f, 0.8f}, 60.0f);
    SnapshotRenderer renderer(context(), scene);
    SnapshotSettings settings;
    settings.map = passes::AamapSource::Subpixel;
    const int W = 48, H = 48;
    for (const passes::SubpixelShading shading : kShadings)
    for (int k : {2, 3}) {
        settings.subpixel = k;
        settings.subpixelShading = shading;
        const SnapshotResult r = renderer.render(view, W, H, settings);
        const int cs = colourScale(settings);
        ASSERT_EQ(r.snapshot.width(), cs * W);
        // The shading does vary: the penumbra darkens the floor towards -x.
        const float left = r.snapshot.at(1, cs * H / 2).r, right = r.snapshot.at(cs * W - 2, cs * H / 2).r;
        EXPECT_GT(right, 1.02f * left) << "k " << k;
        EXPECT_EQ(countFlagged(r.aamap), 0) << toString(shading) << " k " << k;
    }
}

// A glossy sphere lit from near the camera: its highlight and its diffuse falloff are smooth at
// pixel scale, so only the silhouette is flagged.
TEST_F(SubpixelTest, GlossySphereFlagsOnlyItsSilhouette) {
    Scene scene;
    Material glossy;
    glossy.name = "glossy";
    glossy.kd = glm::vec3(0.5f, 0.3f, 0.2f);
    glossy.ks = glm::vec3(0.3f);
    glossy.ns = 20.0f;
    scene.materials = {glossy};
    addSphere(scene, {0, 0, 0}, 1.0f, 96, 48, 0, 0);
    PointLight light;
    light.name = "bulb";
    light.position = {0.0f, 0.0f, 6.0f};  // behind the camera: every visible point is lit
    light.intensity = glm::vec3(12.0f);
    scene.pointLights.push_back(light);
    const View view = viewDownZ({0.0f, 0.0f, 4.0f}, 40.0f);
    const PinholeCamera camera = PinholeCamera::fromView(view);
    SnapshotRenderer renderer(context(), scene);
    SnapshotSettings settings;
    settings.map = passes::AamapSource::Subpixel;
    const int W = 128, H = 128;
    const float disk = std::asin(1.0f / 4.0f);  // the sphere's angular radius from the camera
    for (const passes::SubpixelShading shading : kShadings)
    for (int k : {2, 3}) {
        settings.subpixel = k;
        settings.subpixelShading = shading;
        const SnapshotResult r = renderer.render(view, W, H, settings);
        const int cs = colourScale(settings);
        int interior = 0, silhouette = 0, silhouetteFlagged = 0;
        float brightest = 0.0f, sum = 0.0f;
        for (int y = 0; y < H; ++y)
            for (int x = 0; x < W; ++x) {
                const float u = (static_cast<float>(x) + 0.5f) / W, v = (static_cast<float>(y) + 0.5f) / H;
                const glm::vec3 d = glm::normalize(camera.direction(u, v));
                const float angle = std::acos(std::clamp(glm::dot(d, glm::vec3(0, 0, -1)), -1.0f, 1.0f));
                const float pixelAngle =
                    std::acos(std::clamp(glm::dot(d, glm::normalize(camera.direction(u + 1.0f / W, v))), -1.0f, 1.0f));
                if (angle < disk - 2.5f * pixelAngle) {  // well inside the silhouette, tessellation included
                    ++interior;
                    EXPECT_EQ(r.aamap.at(x, y), 0.0f) << toString(shading) << " k " << k << " pixel " << x << "," << y;
                    brightest = std::max(brightest, r.snapshot.at(cs * x, cs * y).r);
                    sum += r.snapshot.at(cs * x, cs * y).r;
                }
                if (std::abs(angle - disk) < 0.25f * pixelAngle) {  // the outline runs through the pixel
                    ++silhouette;
                    silhouetteFlagged += r.aamap.at(x, y) > 0.0f;
                }
            }
        EXPECT_GT(interior, 5000);
        EXPECT_GT(brightest, 2.0f * sum / static_cast<float>(interior)) << "no highlight to test";
        EXPECT_GT(silhouette, 50);
        EXPECT_EQ(silhouetteFlagged, silhouette) << toString(shading) << " k " << k;
    }
}

// Coverage of pixel (x, y) by the floor region `inside`, from 16 x 16 camera rays.
template <class Inside>
float coverage(const PinholeCamera& camera, int x, int y, int W, int H, Inside inside) {
    int hits = 0;
    for (int j = 0; j < 16; ++j)
        for (int i = 0; i < 16; ++i)
            hits += inside(onFloor(camera, (static_cast<float>(x) + (i + 0.5f) / 16.0f) / W,
                                   (static_cast<float>(y) + (j + 0.5f) / 16.0f) / H));
    return static_cast<float>(hits) / 256.0f;
}

// A tilted square of light and a one-pixel wire across it, over a dark grey floor: every pixel
// an edge of the square crosses is flagged, the wire along its whole length, and nothing far
// from either.
TEST_F(SubpixelTest, HardEdgesAndAOnePixelWireAreFlagged) {
    Scene scene;
    Material floor;
    floor.name = "floor";
    floor.kd = glm::vec3(0.0f);
    floor.ke = glm::vec3(0.05f);
    scene.materials = {floor, emitter("square", glm::vec3(0.8f, 0.7f, 0.6f)), emitter("wire", glm::vec3(0.02f))};
    addQuadZ(scene, 0.0f, -5.0f, 5.0f, -5.0f, 5.0f, 0);
    const float c = std::cos(0.3f), s = std::sin(0.3f);
    const auto turn = [&](float x, float y) { return glm::vec2(c * x - s * y, s * x + c * y); };
    // Just above the floor, so that the rays through z = 0 below classify the pixels.
    addQuadAt(scene, turn(-0.5f, -0.5f), turn(0.5f, -0.5f), turn(0.5f, 0.5f), turn(-0.5f, 0.5f), 0.001f, 1);
    const View view = viewDownZ({0.03f, -0.02f, 2.0f}, 50.0f);
    const PinholeCamera camera = PinholeCamera::fromView(view);
    const int W = 96, H = 96;
    // The wire: a strip one pixel wide (at the plane's scale) at 20 degrees, above the square.
    const float pixel = 2.0f * 2.0f * std::tan(glm::radians(25.0f)) / W;
    const glm::vec2 dir(std::cos(0.35f), std::sin(0.35f)), side(-dir.y, dir.x);
    const glm::vec2 w0 = glm::vec2(-0.8f, -0.3f), w1 = w0 + 1.6f * dir;
    addQuadAt(scene, w0 - 0.5f * pixel * side, w1 - 0.5f * pixel * side, w1 + 0.5f * pixel * side,
              w0 + 0.5f * pixel * side, 0.002f, 2);
    const auto inSquare = [&](glm::vec2 p) {
        const glm::vec2 q(c * p.x + s * p.y, -s * p.x + c * p.y);  // turned back
        return std::abs(q.x) < 0.5f && std::abs(q.y) < 0.5f;
    };
    const auto onWire = [&](glm::vec2 p) {
        const float along = glm::dot(p - w0, dir), across = glm::dot(p - w0, side);
        return along > 0.0f && along < 1.6f && std::abs(across) < 0.5f * pixel;
    };

    SnapshotRenderer renderer(context(), scene);
    SnapshotSettings settings;
    settings.map = passes::AamapSource::Subpixel;
    for (const passes::SubpixelShading shading : kShadings)
    for (int k : {2, 3, 4}) {
        settings.subpixel = k;
        settings.subpixelShading = shading;
        const SnapshotResult r = renderer.render(view, W, H, settings);
        int crossed = 0, wirePixels = 0, far = 0;
        for (int y = 0; y < H; ++y)
            for (int x = 0; x < W; ++x) {
                const bool flagged = r.aamap.at(x, y) > 0.0f;
                const float square = coverage(camera, x, y, W, H, inSquare);
                const float wire = coverage(camera, x, y, W, H, onWire);
                if (square > 0.0f && square < 1.0f) {
                    ++crossed;
                    EXPECT_TRUE(flagged) << toString(shading) << " k " << k << ": edge pixel " << x << "," << y
                                         << " coverage " << square;
                }
                // The wire's centre line runs through the pixel (away from its two ends).
                const glm::vec2 mid = onFloor(camera, (x + 0.5f) / W, (y + 0.5f) / H);
                const float along = glm::dot(mid - w0, dir);
                if (wire > 0.0f && along > 2.0f * pixel && along < 1.6f - 2.0f * pixel &&
                    std::abs(glm::dot(mid - w0, side)) < 0.5f * pixel) {
                    ++wirePixels;
                    EXPECT_TRUE(flagged) << toString(shading) << " k " << k << ": wire pixel " << x << "," << y;
                }
                // Nothing is flagged two pixels or more from every edge and from the wire.
                bool near = false;
                for (int dy = -1; dy <= 1 && !near; ++dy)
                    for (int dx = -1; dx <= 1 && !near; ++dx) {
                        const int qx = std::clamp(x + dx, 0, W - 1), qy = std::clamp(y + dy, 0, H - 1);
                        const float sq = coverage(camera, qx, qy, W, H, inSquare);
                        near = (sq > 0.0f && sq < 1.0f) || coverage(camera, qx, qy, W, H, onWire) > 0.0f;
                    }
                if (!near) far += flagged;
            }
        EXPECT_GT(crossed, 100);
        EXPECT_GT(wirePixels, 40);
        EXPECT_EQ(far, 0) << toString(shading) << " k " << k;
    }
}

// A glowing unit square at the origin, in the plane z = 0.
Scene glowingSquare() {
    Scene scene;
    scene.materials = {emitter("glow", glm::vec3(0.5f))};
    addQuadZ(scene, 0.0f, -0.5f, 0.5f, -0.5f, 0.5f, 0);
    return scene;
}

// The subpixel Snapshot rasterises geometry at k x the render size, colour at that size or once
// per pixel, and runs the geometry raster and the subpixel pass, not the luminance chain; k
// outside [2, 4] is refused.
TEST_F(SubpixelTest, GraphRunsOnlyWhatTheMapNeeds) {
    const Scene scene = glowingSquare();
    const View view = viewDownZ({0.0f, 0.0f, 2.0f}, 50.0f);
    SnapshotRenderer renderer(context(), scene);
    SnapshotSettings settings;
    settings.map = passes::AamapSource::Subpixel;
    settings.subpixel = 3;
    settings.subpixelShading = passes::SubpixelShading::Sample;
    const SnapshotResult r = renderer.render(view, 20, 12, settings);
    EXPECT_EQ(r.snapshot.width(), 60);
    EXPECT_EQ(r.snapshot.height(), 36);
    // Shared shading: one shade per render pixel, the geometry still at 3 x.
    settings.subpixelShading = passes::SubpixelShading::Pixel;
    const SnapshotResult shared = renderer.render(view, 20, 12, settings);
    EXPECT_EQ(shared.snapshot.width(), 20);
    EXPECT_EQ(shared.snapshot.height(), 12);
    EXPECT_NE(shared.explain.find("60x36"), std::string::npos) << shared.explain;
    EXPECT_EQ(r.aamap.width(), 20);
    EXPECT_EQ(r.aamap.height(), 12);
    EXPECT_TRUE(r.laplacian.empty());
    EXPECT_TRUE(r.edges.empty());
    std::vector<std::string> ran;
    for (const PassTiming& p : r.passTimes) ran.push_back(p.pass);
    for (const char* pass : {"gbuffer", "geometry_buffer", "subpixel_geometry", "subpixel_map"})
        EXPECT_NE(std::find(ran.begin(), ran.end(), pass), ran.end()) << pass << "\n" << r.explain;
    for (const char* pass : {"luminance", "laplacian", "blur", "reduce", "geometric_edges"})
        EXPECT_EQ(std::find(ran.begin(), ran.end(), pass), ran.end()) << pass << "\n" << r.explain;
    settings.subpixel = 5;
    EXPECT_THROW(renderer.render(view, 20, 12, settings), std::invalid_argument);
    settings.subpixel = 1;
    EXPECT_THROW(renderer.render(view, 20, 12, settings), std::invalid_argument);
}

// A device whose images are smaller than k x the render falls back to the largest k that fits,
// with a warning; below k = 2, or a render larger than an image, is refused.
TEST_F(SubpixelTest, FallsBackToTheSamplesTheDevicesImagesHold) {
    const Scene scene = glowingSquare();
    const View view = viewDownZ({0.0f, 0.0f, 2.0f}, 50.0f);
    SnapshotRenderer renderer(context(), scene);
    SnapshotSettings settings;
    settings.map = passes::AamapSource::Subpixel;
    settings.subpixel = 4;
    const int limit = static_cast<int>(context().maxImageDimension2D());
    const int W = limit / 4 + 1;  // 4 W is one step too wide, 3 W fits
    ASSERT_LE(3 * W, limit);
    const SnapshotResult r = renderer.render(view, W, 2, settings);
    EXPECT_EQ(r.subpixel, 3);
    ASSERT_EQ(r.warnings.size(), 1u);
    EXPECT_NE(r.warnings[0].find("using 3"), std::string::npos) << r.warnings[0];
    EXPECT_EQ(r.aamap.width(), W);
    settings.subpixel = 2;
    EXPECT_EQ(renderer.render(view, 64, 2, settings).subpixel, 2);
    EXPECT_TRUE(renderer.render(view, 64, 2, settings).warnings.empty());
    EXPECT_THROW(renderer.render(view, limit / 2 + 1, 2, settings), std::invalid_argument);  // not even k = 2
    settings.map = passes::AamapSource::Luminance;
    settings.scale = 1.5f;  // the luminance map's raster: the largest scale that fits
    const SnapshotResult scaled = renderer.render(view, limit * 4 / 5, 2, settings);
    ASSERT_EQ(scaled.warnings.size(), 1u);
    EXPECT_NE(scaled.warnings[0].find("snapshot.scale"), std::string::npos) << scaled.warnings[0];
    EXPECT_LE(scaled.snapshot.width(), limit);
    EXPECT_EQ(scaled.aamap.width(), limit * 4 / 5);
    EXPECT_THROW(renderer.render(view, limit + 1, 1, settings), std::invalid_argument);  // no image that wide
}

}  // namespace
}  // namespace aamap::test
