// Shadow cube maps in the Snapshot: the shadow edge of a box lies where the analytic projection
// from the light puts it, the passes exist only for lights, and occluders darken.
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <glm/geometric.hpp>

#include "gpu_fixture.h"
#include "passes/snapshot.h"
#include "scene/camera.h"
#include "scene/lights.h"
#include "tests/common/test_scenes.h"

namespace aamap::test {
namespace {

// An axis-aligned quad: `axis` is its normal axis (0 x, 1 y, 2 z), at coordinate `at`, spanning
// [a0,a1] x [b0,b1] in the other two axes (cyclic order), facing +axis or -axis.
void addQuad(Scene& scene, int axis, float at, float a0, float a1, float b0, float b1, bool positive) {
    const int u = (axis + 1) % 3, v = (axis + 2) % 3;
    auto point = [&](float a, float b) {
        glm::vec3 p(0.0f);
        p[axis] = at;
        p[u] = a;
        p[v] = b;
        return p;
    };
    const auto base = static_cast<std::uint32_t>(scene.mesh.positions.size());
    scene.mesh.positions.insert(scene.mesh.positions.end(), {point(a0, b0), point(a1, b0), point(a1, b1), point(a0, b1)});
    glm::vec3 n(0.0f);
    n[axis] = positive ? 1.0f : -1.0f;
    scene.mesh.normals.insert(scene.mesh.normals.end(), 4, n);
    if (positive)
        scene.mesh.triangles.insert(scene.mesh.triangles.end(), {{base, base + 1, base + 2}, {base, base + 2, base + 3}});
    else
        scene.mesh.triangles.insert(scene.mesh.triangles.end(), {{base, base + 2, base + 1}, {base, base + 3, base + 2}});
    scene.mesh.materialIds.insert(scene.mesh.materialIds.end(), 2, 0u);
    scene.mesh.objectIds.insert(scene.mesh.objectIds.end(), 2, 0u);
}

constexpr float kHalf = 0.25f, kHeight = 0.5f;   // the box: [-0.25,0.25]^2 x [0,0.5]
const glm::vec3 kLight{-0.5f, 0.0f, 2.0f};

// A floor z = 0 with (optionally) a box on it, lit by one point light up and to the left.
Scene boxScene(bool withBox, bool withLight = true) {
    Scene scene;
    scene.name = "box";
    Material grey;
    grey.name = "grey";
    grey.kd = glm::vec3(0.8f);
    scene.materials.push_back(grey);
    addQuad(scene, 2, 0.0f, -2.0f, 2.0f, -2.0f, 2.0f, true);
    if (withBox) {
        addQuad(scene, 2, kHeight, -kHalf, kHalf, -kHalf, kHalf, true);  // top
        addQuad(scene, 0, kHalf, -kHalf, kHalf, 0.0f, kHeight, true);    // +x side (y, z)
        addQuad(scene, 0, -kHalf, -kHalf, kHalf, 0.0f, kHeight, false);
        addQuad(scene, 1, kHalf, 0.0f, kHeight, -kHalf, kHalf, true);    // +y side (z, x)
        addQuad(scene, 1, -kHalf, 0.0f, kHeight, -kHalf, kHalf, false);
    }
    if (withLight) {
        PointLight light;
        light.name = "bulb";
        light.position = kLight;
        light.intensity = glm::vec3(10.0f);
        scene.pointLights.push_back(light);
    }
    return scene;
}

// Straight down from above the shadow's far edge: the floor maps linearly onto the image.
View topView() { return viewDownZ({0.5f, 0.0f, 3.0f}, 40.0f); }

// The box scene lit by a 0.4 x 0.4 emissive quad at z = 1.5 facing down, its only light.
Scene boxUnderLamp() {
    Scene scene = boxScene(true, false);
    Material lamp;
    lamp.name = "lamp";
    lamp.ke = glm::vec3(5.0f);
    scene.materials.push_back(lamp);
    addQuad(scene, 2, 1.5f, -0.2f, 0.2f, -0.2f, 0.2f, false);  // facing down
    scene.mesh.materialIds.back() = scene.mesh.materialIds[scene.mesh.materialIds.size() - 2] = 1;
    scene.mesh.objectIds.back() = scene.mesh.objectIds[scene.mesh.objectIds.size() - 2] = 1;
    scene.areaLights = buildAreaLights(scene);
    return scene;
}

int countPass(const SnapshotResult& r, const std::string& name) {
    int n = 0;
    for (const PassTiming& t : r.passTimes) n += t.pass == name;
    return n;
}

class SnapshotShadows : public GpuTest {};  // the suite names the feature a failure is in

TEST_F(SnapshotShadows, ShadowEdgeLiesOnTheAnalyticProjection) {
    const Scene scene = boxScene(true);
    SnapshotRenderer renderer(context(), scene);
    SnapshotSettings settings;
    settings.scale = 1.0f;
    settings.shadows.resolution = 1024;
    const int size = 160;
    const SnapshotResult r = renderer.render(topView(), size, size, settings);
    ASSERT_EQ(r.snapshot.width(), size);

    // The box's top edge x = +0.25 at height 0.5, projected from the light onto z = 0.
    const float s = kLight.z / (kLight.z - kHeight);
    const float edgeX = kLight.x + (kHalf - kLight.x) * s;  // 0.5
    const PinholeCamera camera = PinholeCamera::fromView(topView());
    for (int y : {size / 2 - 10, size / 2, size / 2 + 10}) {  // rows through the shadow
        int expected = -1, measured = -1;
        float lit = 0.0f;
        for (int x = 0; x < size; ++x) {
            const glm::vec3 d = camera.direction((x + 0.5f) / size, (y + 0.5f) / size);
            const glm::vec3 hit = camera.origin + (-camera.origin.z / d.z) * d;
            if (expected < 0 && hit.x > edgeX) expected = x;
            if (hit.x > edgeX) lit = std::max(lit, r.snapshot.at(x, y).r);
        }
        ASSERT_GT(expected, 0);
        // From the box's side of the shadow, the first pixel brighter than half the lit floor.
        for (int x = 0; x < size; ++x) {
            const glm::vec3 d = camera.direction((x + 0.5f) / size, (y + 0.5f) / size);
            const glm::vec3 hit = camera.origin + (-camera.origin.z / d.z) * d;
            if (hit.x <= kHalf + 0.02f) continue;  // the box (and its top) lies left of the shadow
            if (r.snapshot.at(x, y).r > 0.5f * lit) {
                measured = x;
                break;
            }
        }
        EXPECT_GT(lit, 0.0f);
        EXPECT_NEAR(measured, expected, 1) << "row " << y;
        // And inside the shadow, the floor is black (the only light is blocked).
        EXPECT_EQ(r.snapshot.at(expected - 4, y).r, 0.0f) << "row " << y;
    }
}

// Shadow maps by need (passes/view_budget.h): a wider texel allowed gives the light fewer texels,
// and its shadow edge stays within that many pixels of the analytic one; 0 gives the resolution.
TEST_F(SnapshotShadows, ShadowFacesByNeedKeepTheEdgeWithinTheirTexel) {
    const Scene scene = boxScene(true);
    SnapshotRenderer renderer(context(), scene);
    SnapshotSettings settings;
    settings.scale = 1.0f;
    const int size = 160;
    const float s = kLight.z / (kLight.z - kHeight);
    const float edgeX = kLight.x + (kHalf - kLight.x) * s;
    const PinholeCamera camera = PinholeCamera::fromView(topView());
    int previous = 1 << 30;
    for (const float texelPixels : {0.0f, 1.0f, 4.0f}) {
        settings.shadows.texelPixels = texelPixels;
        const SnapshotResult r = renderer.render(topView(), size, size, settings);
        ASSERT_EQ(r.shadowFaceSizes.size(), 1u);
        const int faceSize = r.shadowFaceSizes[0];
        if (texelPixels == 0.0f) {
            EXPECT_EQ(faceSize, settings.shadows.resolution);
        }
        EXPECT_LE(faceSize, previous);
        previous = faceSize;
        EXPECT_NE(r.explain.find("'bulb' " + std::to_string(faceSize)), std::string::npos) << r.explain;
        const int y = size / 2;
        int expected = -1, measured = -1;
        float lit = 0.0f;
        for (int x = 0; x < size; ++x) {
            const glm::vec3 d = camera.direction((x + 0.5f) / size, (y + 0.5f) / size);
            const glm::vec3 hit = camera.origin + (-camera.origin.z / d.z) * d;
            if (expected < 0 && hit.x > edgeX) expected = x;
            if (hit.x > edgeX) lit = std::max(lit, r.snapshot.at(x, y).r);
        }
        for (int x = 0; x < size && measured < 0; ++x) {
            const glm::vec3 d = camera.direction((x + 0.5f) / size, (y + 0.5f) / size);
            const glm::vec3 hit = camera.origin + (-camera.origin.z / d.z) * d;
            if (hit.x > kHalf + 0.02f && r.snapshot.at(x, y).r > 0.5f * lit) measured = x;
        }
        EXPECT_NEAR(measured, expected, std::max(1.0f, texelPixels) + 1.0f) << "at " << texelPixels;
    }
    EXPECT_LT(previous, settings.shadows.resolution);  // 4 pixels per texel: fewer texels
}

TEST_F(SnapshotShadows, ShadowPassesOnlyForLights) {
    SnapshotSettings settings;
    {
        SnapshotRenderer renderer(context(), boxScene(true, false));
        const SnapshotResult r = renderer.render(topView(), 32, 32, settings);
        EXPECT_EQ(countPass(r, "shadow"), 0);
        EXPECT_EQ(r.shadowCubeMaps, 0);
        EXPECT_EQ(r.explain.find("shadow"), std::string::npos) << r.explain;
    }
    SnapshotRenderer renderer(context(), boxScene(true));
    const SnapshotResult r = renderer.render(topView(), 32, 32, settings);
    EXPECT_EQ(countPass(r, "shadow"), 1);
    EXPECT_EQ(r.shadowCubeMaps, 1);
    // The array is as large as the light's faces, which a 32-pixel view needs fewer of (by need).
    ASSERT_EQ(r.shadowFaceSizes.size(), 1u);
    EXPECT_LE(r.shadowFaceSizes[0], settings.shadows.resolution);
    EXPECT_NE(r.explain.find(fmt::format("'shadow.cubes': {0}x{0} D32Float, 6 layers", r.shadowFaceSizes[0])),
              std::string::npos)
        << r.explain;
    EXPECT_NE(r.explain.find("for 1 light: 'bulb'"), std::string::npos) << r.explain;
    EXPECT_EQ(r.passTimes.front().pass, "shadow");  // ordered before the G-buffer that samples it

    settings.shadows.enabled = false;
    const SnapshotResult off = renderer.render(topView(), 32, 32, settings);
    EXPECT_EQ(countPass(off, "shadow"), 0);
}

TEST_F(SnapshotShadows, AreaLightSamplesEachGetACubeMap) {
    const Scene scene = boxUnderLamp();
    ASSERT_EQ(scene.areaLights.size(), 1u);
    SnapshotRenderer renderer(context(), scene);
    SnapshotSettings settings;
    settings.areaLightSolidAngle = 0.0f;  // every area light gets areaLightSamples
    for (int k : {1, 3, 5}) {
        settings.areaLightSamples = k;
        const SnapshotResult r = renderer.render(topView(), 32, 32, settings);
        EXPECT_EQ(countPass(r, "shadow"), 1);
        EXPECT_EQ(r.shadowCubeMaps, k);
        EXPECT_NE(r.explain.find(fmt::format("{} layers", 6 * k)), std::string::npos) << r.explain;
    }
}

// The shading pipelines are specialised for the light list (glsl/lights.glsl) and rebuilt when it
// changes: a renderer that went through other sample counts draws what a fresh one draws.
TEST_F(SnapshotShadows, ChangingTheLightSamplesAndBackGivesTheFreshSnapshot) {
    const Scene scene = boxUnderLamp();
    SnapshotSettings settings;
    settings.scale = 1.0f;
    settings.areaLightSolidAngle = 0.0f;  // the sample counts as given
    SnapshotRenderer reused(context(), scene);
    std::vector<float> firstAamap;
    SnapshotResult last;
    for (int k : {5, 12, 2, 5}) {  // 12: past the lights held as constants
        settings.areaLightSamples = k;
        last = reused.render(topView(), 48, 48, settings);
        if (firstAamap.empty()) firstAamap = last.aamap.pixels();
    }
    SnapshotRenderer fresh(context(), scene);
    settings.areaLightSamples = 5;
    const SnapshotResult want = fresh.render(topView(), 48, 48, settings);
    EXPECT_EQ(last.snapshot, want.snapshot);
    EXPECT_EQ(last.aamap, want.aamap);
    EXPECT_EQ(firstAamap, want.aamap.pixels());
    int lit = 0;
    for (const glm::vec3& c : want.snapshot.pixels()) lit += c.r > 0.0f;
    EXPECT_GT(lit, 48 * 48 / 2);
}

TEST_F(SnapshotShadows, OccluderDarkensTheSurface) {
    SnapshotSettings settings;
    settings.scale = 1.0f;
    const View view = topView();
    SnapshotRenderer open(context(), boxScene(false));
    SnapshotRenderer boxed(context(), boxScene(true));
    const SnapshotResult a = open.render(view, 64, 64, settings);
    const SnapshotResult b = boxed.render(view, 64, 64, settings);
    settings.shadows.enabled = false;
    const SnapshotResult c = boxed.render(view, 64, 64, settings);
    // A floor point in the box's shadow: x = 0.4, y = 0 (between the box at 0.25 and the edge at 0.5).
    const PinholeCamera camera = PinholeCamera::fromView(view);
    int px = 0;
    for (int x = 0; x < 64; ++x) {
        const glm::vec3 d = camera.direction((x + 0.5f) / 64.0f, 0.5f);
        if (camera.origin.x + (-camera.origin.z / d.z) * d.x < 0.4f) px = x;
    }
    const float unshadowed = a.snapshot.at(px, 32).r;
    EXPECT_GT(unshadowed, 0.0f);
    EXPECT_LT(b.snapshot.at(px, 32).r, 0.1f * unshadowed);
    EXPECT_NEAR(c.snapshot.at(px, 32).r, unshadowed, 1e-4f * unshadowed);  // shadows off: as if no box
    // Lit floor far from the box looks the same with or without the box: no acne.
    EXPECT_NEAR(b.snapshot.at(60, 32).r, a.snapshot.at(60, 32).r, 1e-5f);
    EXPECT_NEAR(b.snapshot.at(60, 5).r, a.snapshot.at(60, 5).r, 1e-5f);
}

// The view culls (passes/view_budget.h): a caster outside the frustum still shadows the floor in
// view, and the G-buffer draws only what the frustum holds.
TEST_F(SnapshotShadows, CasterOutsideTheViewStillShadowsIt) {
    SnapshotSettings settings;
    settings.scale = 1.0f;
    // Straight down on the floor right of the box: x in [0.42, 1.58] at z = 0, and the box (x <=
    // 0.25) is outside the frustum at every height; its shadow reaches x = 0.5.
    const View view = viewDownZ({1.0f, 0.0f, 1.0f}, 60.0f);
    SnapshotRenderer boxed(context(), boxScene(true));
    SnapshotRenderer open(context(), boxScene(false));
    const SnapshotResult b = boxed.render(view, 64, 64, settings);
    const SnapshotResult a = open.render(view, 64, 64, settings);
    EXPECT_NE(b.explain.find("opaque triangles in the view frustum"), std::string::npos) << b.explain;
    EXPECT_NE(b.explain.find("2 of 12 opaque triangles"), std::string::npos) << b.explain;  // the floor alone
    const PinholeCamera camera = PinholeCamera::fromView(view);
    int shadowed = -1, lit = -1;
    for (int x = 0; x < 64; ++x) {
        const glm::vec3 d = camera.direction((x + 0.5f) / 64.0f, 0.5f);
        const float floorX = camera.origin.x + (-camera.origin.z / d.z) * d.x;
        if (floorX > 0.43f && floorX < 0.47f) shadowed = x;
        if (floorX > 0.9f && floorX < 1.1f) lit = x;
    }
    ASSERT_GE(shadowed, 0);
    ASSERT_GE(lit, 0);
    const float unshadowed = a.snapshot.at(shadowed, 32).r;
    EXPECT_GT(unshadowed, 0.0f);
    EXPECT_LT(b.snapshot.at(shadowed, 32).r, 0.1f * unshadowed);
    EXPECT_NEAR(b.snapshot.at(lit, 32).r, a.snapshot.at(lit, 32).r, 1e-5f);
}

// Area-light samples by need: the lamp gets fewer than the cap when it looks small over the
// region in view, every sample its cube map, and a solid angle per sample of 0 gives the cap.
TEST_F(SnapshotShadows, AreaLightSamplesFollowTheSolidAngle) {
    const Scene scene = boxUnderLamp();
    SnapshotRenderer renderer(context(), scene);
    SnapshotSettings settings;
    settings.areaLightSamples = 16;
    settings.areaLightSolidAngle = 0.05f;
    // The 0.4 x 0.4 lamp at z = 1.5 over the floor: about 0.16 / 1.5^2 = 0.07 sr below it, less
    // beside it, so a few samples, not 16.
    const SnapshotResult r = renderer.render(topView(), 32, 32, settings);
    ASSERT_EQ(r.areaLightSamples.size(), 1u);
    EXPECT_GE(r.areaLightSamples[0], 1);
    EXPECT_LE(r.areaLightSamples[0], 4);
    EXPECT_EQ(r.shadowCubeMaps, r.areaLightSamples[0]);
    EXPECT_NE(r.explain.find("area-light samples"), std::string::npos) << r.explain;
    // A smaller solid angle per sample: more samples, up to the cap.
    settings.areaLightSolidAngle = 0.001f;
    EXPECT_EQ(renderer.render(topView(), 32, 32, settings).areaLightSamples[0], 16);
    settings.areaLightSolidAngle = 0.0f;
    settings.areaLightSamples = 5;
    EXPECT_EQ(renderer.render(topView(), 32, 32, settings).shadowCubeMaps, 5);
}

// --- Soft shadows of area-light samples ------------------------------------------------------
// A square lamp (side kLampSide, facing down at height kLampHeight, centred at x = kLampX) over a
// floor z = 0, and optionally an opaque plate at height kPlateHeight over x < 0: the plate's edge
// x = 0 casts a penumbra on the floor. Every plane is horizontal, so similar triangles give it
// exactly: lamp point x_L shadows floor points x < -x_L h / (H - h), a band of width
// side * h / (H - h) around -kLampX h / (H - h), across which the visible part of the lamp grows
// linearly (the edge runs along the lamp's side).
constexpr float kLampSide = 0.4f, kLampHeight = 1.5f, kLampX = -0.6f, kPlateHeight = 0.5f;
constexpr float kShadowScale = kPlateHeight / (kLampHeight - kPlateHeight);
constexpr float kPenumbraWidth = kLampSide * kShadowScale;   // 0.2
constexpr float kPenumbraCentre = -kLampX * kShadowScale;    // 0.3

Scene lampOverPlate(bool withPlate) {
    Scene scene;
    scene.name = "lamp over plate";
    Material grey;
    grey.name = "grey";
    grey.kd = glm::vec3(0.8f);
    scene.materials.push_back(grey);
    addQuad(scene, 2, 0.0f, -2.0f, 2.0f, -2.0f, 2.0f, true);
    if (withPlate) addQuad(scene, 2, kPlateHeight, -2.0f, 0.0f, -2.0f, 2.0f, true);
    Material lamp;
    lamp.name = "lamp";
    lamp.ke = glm::vec3(5.0f);
    scene.materials.push_back(lamp);
    const float h = 0.5f * kLampSide;
    addQuad(scene, 2, kLampHeight, kLampX - h, kLampX + h, -h, h, false);  // facing down
    scene.mesh.materialIds.back() = scene.mesh.materialIds[scene.mesh.materialIds.size() - 2] = 1;
    scene.mesh.objectIds.back() = scene.mesh.objectIds[scene.mesh.objectIds.size() - 2] = 1;
    scene.areaLights = buildAreaLights(scene);
    return scene;
}

// Straight down onto the penumbra; the plate (x < 0) stays out of the picture's middle rows.
View penumbraView() { return viewDownZ({kPenumbraCentre, 0.0f, 2.0f}, 15.0f); }

// Per pixel of the middle row: the floor's x, and the snapshot's red (grey scene, white lamp).
struct FloorRow {
    std::vector<float> x, value;
};

FloorRow middleRow(const SnapshotResult& r, const View& view) {
    const PinholeCamera camera = PinholeCamera::fromView(view);
    const int w = r.snapshot.width(), h = r.snapshot.height();
    FloorRow row;
    for (int x = 0; x < w; ++x) {
        const glm::vec3 d = camera.direction((x + 0.5f) / w, 0.5f);
        row.x.push_back(camera.origin.x + (-camera.origin.z / d.z) * d.x);
        row.value.push_back(r.snapshot.at(x, h / 2).r);
    }
    return row;
}

// The floor's x where the visibility (shadowed / open) first reaches `level`, linearly
// interpolated between pixels; NaN if it never does.
float crossing(const FloorRow& row, const std::vector<float>& visibility, float level) {
    for (std::size_t i = 1; i < visibility.size(); ++i)
        if (visibility[i - 1] < level && visibility[i] >= level) {
            const float t = (level - visibility[i - 1]) / (visibility[i] - visibility[i - 1]);
            return row.x[i - 1] + t * (row.x[i] - row.x[i - 1]);
        }
    return std::nanf("");
}

struct PenumbraProfile {
    FloorRow row;
    std::vector<float> visibility;  // shadowed / open floor, per pixel of the row
};

PenumbraProfile penumbraProfile(VulkanContext& context, bool soft, int samples) {
    SnapshotSettings settings;
    settings.scale = 1.0f;
    settings.areaLightSamples = samples;
    settings.areaLightSolidAngle = 0.0f;  // exactly `samples`: the filter's penumbra per sample count
    settings.shadows.softShadows = soft;
    const int size = 160;
    SnapshotRenderer shadowed(context, lampOverPlate(true));
    SnapshotRenderer open(context, lampOverPlate(false));
    const SnapshotResult a = shadowed.render(penumbraView(), size, size, settings);
    const SnapshotResult b = open.render(penumbraView(), size, size, settings);
    PenumbraProfile p{middleRow(a, penumbraView()), {}};
    const FloorRow lit = middleRow(b, penumbraView());
    for (std::size_t i = 0; i < p.row.value.size(); ++i)
        p.visibility.push_back(lit.value[i] > 0.0f ? p.row.value[i] / lit.value[i] : 0.0f);
    return p;
}

// The largest rise of the visibility from one pixel to the next, and the largest fall.
std::pair<float, float> largestSteps(const std::vector<float>& v) {
    float rise = 0.0f, fall = 0.0f;
    for (std::size_t i = 1; i < v.size(); ++i) {
        rise = std::max(rise, v[i] - v[i - 1]);
        fall = std::max(fall, v[i - 1] - v[i]);
    }
    return {rise, fall};
}

TEST_F(SnapshotShadows, AreaLightPenumbraIsASmoothRampOfTheAnalyticWidth) {
    // One sample: its patch is the whole lamp, and the kernel is the similar triangles' width (up
    // to where the filter's grid puts the edge, a fraction of a kernel). More: each patch's
    // penumbra is narrower, spread by where the samples sit; the triangular van der Corput points
    // keep nearer the lamp's middle than a tiling would, so the ramp comes out up to a third
    // narrower.
    for (const auto& [samples, tolerance] : {std::pair{1, 0.3f}, std::pair{5, 0.35f}, std::pair{16, 0.35f}}) {
        const PenumbraProfile soft = penumbraProfile(context(), true, samples);
        ASSERT_GT(soft.row.x.front(), 0.0f) << "the plate is in view";
        ASSERT_LT(soft.row.x.front(), kPenumbraCentre - kPenumbraWidth);
        ASSERT_GT(soft.row.x.back(), kPenumbraCentre + kPenumbraWidth);
        // Umbra left, full light right.
        EXPECT_LT(soft.visibility.front(), 0.01f) << samples << " samples";
        EXPECT_GT(soft.visibility.back(), 0.99f) << samples << " samples";
        // A ramp: never darker to the right, and no step of a whole light sample (1/5).
        const auto [rise, fall] = largestSteps(soft.visibility);
        EXPECT_LE(fall, 1e-3f) << "not monotone, " << samples << " samples";
        EXPECT_LT(rise, 0.05f) << "a staircase, " << samples << " samples";
        // 10-90 % width: the analytic ramp is linear over kPenumbraWidth, so 0.8 of it.
        const float x10 = crossing(soft.row, soft.visibility, 0.1f), x90 = crossing(soft.row, soft.visibility, 0.9f);
        const float analytic = 0.8f * kPenumbraWidth;
        EXPECT_NEAR(x90 - x10, analytic, tolerance * analytic)
            << samples << " samples: 10 % at " << x10 << ", 90 % at " << x90;
        EXPECT_NEAR(0.5f * (x10 + x90), kPenumbraCentre, 0.25f * kPenumbraWidth) << samples << " samples";
        if (std::getenv("AAMAP_DUMP_PENUMBRA"))
            fmt::print("{} samples: 10-90 % width {}, analytic {}, largest rise {}\n", samples, x90 - x10, analytic, rise);
    }
    // Hard shadows from five samples: a staircase of steps of about a fifth.
    const PenumbraProfile hard = penumbraProfile(context(), false, 5);
    EXPECT_GT(largestSteps(hard.visibility).first, 0.15f);
}

TEST_F(SnapshotShadows, PointLightShadowIsTheSameWithSoftShadowsOnOrOff) {
    const Scene scene = boxScene(true);
    SnapshotSettings settings;
    settings.scale = 1.0f;
    SnapshotRenderer renderer(context(), scene);
    settings.shadows.softShadows = false;
    const SnapshotResult hard = renderer.render(topView(), 96, 96, settings);
    settings.shadows.softShadows = true;
    const SnapshotResult soft = renderer.render(topView(), 96, 96, settings);
    EXPECT_EQ(hard.snapshot, soft.snapshot);  // no patch: the point light keeps its lookup
    EXPECT_EQ(hard.aamap, soft.aamap);
}

// Acne: an unoccluded plane must look as if shadows were off. The floor, or a plane tilted by
// 60 degrees about y (its normal leaning towards the light), each alone under the lamp (soft
// shadows) or under a point light at the lamp's centre (hard ones).
TEST_F(SnapshotShadows, UnoccludedPlanesHaveNoAcne) {
    for (bool tilted : {false, true})
        for (bool lamp : {true, false}) {
            Scene scene;
            scene.name = "acne";
            Material grey;
            grey.name = "grey";
            grey.kd = glm::vec3(0.8f);
            scene.materials.push_back(grey);
            if (!tilted) {
                addQuad(scene, 2, 0.0f, -2.0f, 2.0f, -2.0f, 2.0f, true);
            } else {
                const auto base = static_cast<std::uint32_t>(scene.mesh.positions.size());
                const float c = 0.5f, s = std::sqrt(3.0f) / 2.0f;  // cos, sin 60 degrees
                const glm::vec3 centre{0.3f, 0.0f, 0.0f}, along{c, 0.0f, s}, across{0.0f, 1.0f, 0.0f};
                for (glm::vec2 k : {glm::vec2(-1, -1), glm::vec2(1, -1), glm::vec2(1, 1), glm::vec2(-1, 1)})
                    scene.mesh.positions.push_back(centre + 0.6f * (k.x * along + k.y * across));
                scene.mesh.normals.insert(scene.mesh.normals.end(), 4, glm::vec3(-s, 0.0f, c));
                scene.mesh.triangles.insert(scene.mesh.triangles.end(),
                                            {{base, base + 2, base + 1}, {base, base + 3, base + 2}});
                scene.mesh.materialIds.insert(scene.mesh.materialIds.end(), 2, 0u);
                scene.mesh.objectIds.insert(scene.mesh.objectIds.end(), 2, 0u);
            }
            if (lamp) {
                Material emitter;
                emitter.name = "lamp";
                emitter.ke = glm::vec3(5.0f);
                scene.materials.push_back(emitter);
                const float h = 0.5f * kLampSide;
                addQuad(scene, 2, kLampHeight, kLampX - h, kLampX + h, -h, h, false);
                scene.mesh.materialIds.back() = scene.mesh.materialIds[scene.mesh.materialIds.size() - 2] = 1;
                scene.areaLights = buildAreaLights(scene);
            } else {
                PointLight bulb;
                bulb.name = "bulb";
                bulb.position = {kLampX, 0.0f, kLampHeight};
                bulb.intensity = glm::vec3(1.0f);
                scene.pointLights.push_back(bulb);
            }
            SnapshotRenderer renderer(context(), scene);
            SnapshotSettings settings;
            settings.scale = 1.0f;
            const View view = viewDownZ({0.3f, 0.0f, 3.0f}, 20.0f);  // inside the tilted plane
            const SnapshotResult shadowed = renderer.render(view, 96, 96, settings);
            settings.shadows.enabled = false;
            const SnapshotResult unshadowed = renderer.render(view, 96, 96, settings);
            float worst = 0.0f;
            int lit = 0;
            for (int y = 0; y < 96; ++y)
                for (int x = 0; x < 96; ++x) {
                    const float a = shadowed.snapshot.at(x, y).r, b = unshadowed.snapshot.at(x, y).r;
                    if (b <= 0.0f) continue;
                    ++lit;
                    worst = std::max(worst, std::abs(a - b) / b);
                }
            EXPECT_GT(lit, 96 * 96 / 2);
            EXPECT_LT(worst, 1e-3f) << (tilted ? "tilted plane, " : "floor, ") << (lamp ? "lamp" : "point light");
        }
}

}  // namespace
}  // namespace aamap::test
