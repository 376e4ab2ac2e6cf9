// Shadow cube maps in the Snapshot: the shadow edge of a box lies where the analytic projection
// from the light puts it, the passes exist only for lights, and occluders darken.
#include <cmath>

#include <fmt/format.h>
#include <glm/geometric.hpp>

#include "gpu_fixture.h"
#include "passes/snapshot.h"
#include "scene/camera.h"
#include "scene/lights.h"
#include "test_scenes.h"

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
    EXPECT_NE(r.explain.find("'shadow.cubes': 256x256 D32Float, 6 layers"), std::string::npos) << r.explain;
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

}  // namespace
}  // namespace aamap::test
