// The Snapshot end to end on a scene built in code: the raster puts geometry exactly where the
// tracer's camera rays would find it, shading has its analytic value, and the aamap flags edges.
#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>

#include "gpu_fixture.h"
#include "passes/cpu_aamap.h"
#include "passes/snapshot.h"
#include "scene/builtin_scenes.h"
#include "scene/camera.h"
#include "scene/lights.h"
#include "tests/common/image_compare.h"
#include "tests/common/test_scenes.h"

namespace aamap::test {
namespace {

constexpr float kPi = 3.14159265358979f;

// An axis-aligned rectangle [x0,x1] x [y0,y1] in the plane z = 0, facing +z.
void addQuad(Scene& scene, float x0, float x1, float y0, float y1, float z, glm::vec3 normal, std::uint32_t material) {
    const auto base = static_cast<std::uint32_t>(scene.mesh.positions.size());
    scene.mesh.positions.insert(scene.mesh.positions.end(),
                                {{x0, y0, z}, {x1, y0, z}, {x1, y1, z}, {x0, y1, z}});
    scene.mesh.normals.insert(scene.mesh.normals.end(), 4, normal);
    if (normal.z > 0) {
        scene.mesh.triangles.insert(scene.mesh.triangles.end(), {{base, base + 1, base + 2}, {base, base + 2, base + 3}});
    } else {
        scene.mesh.triangles.insert(scene.mesh.triangles.end(), {{base, base + 2, base + 1}, {base, base + 3, base + 2}});
    }
    scene.mesh.materialIds.insert(scene.mesh.materialIds.end(), 2, material);
    scene.mesh.objectIds.insert(scene.mesh.objectIds.end(), 2, material);
}

// An off-centre quad and an asymmetric, shifted view, so that any flip or offset shows.
Scene quadScene() {
    Scene scene;
    scene.name = "quad";
    Material grey;
    grey.name = "grey";
    grey.kd = glm::vec3(0.8f);
    scene.materials.push_back(grey);
    addQuad(scene, -0.3f, 1.0f, -1.0f, 0.5f, 0.0f, {0, 0, 1}, 0);
    PointLight light;
    light.name = "bulb";
    light.position = {0.0f, 0.0f, 2.0f};
    light.intensity = glm::vec3(10.0f);
    scene.pointLights.push_back(light);
    return scene;
}

View quadView() {
    View view;
    view.position = {0.1f, -0.05f, 3.0f};
    view.direction = {0, 0, -1};
    view.up = {0, 1, 0};
    view.horizontalFovDeg = 50.0f;
    view.verticalFovDeg = 40.0f;
    view.shiftX = 0.05f;
    view.shiftY = -0.03f;
    return view;
}

class SnapshotGraph : public GpuTest {};  // the suite names the feature a failure is in

TEST_F(SnapshotGraph, RasterAgreesWithCameraRays) {
    const Scene scene = quadScene();
    const View view = quadView();
    SnapshotRenderer renderer(context(), scene);
    SnapshotSettings settings;
    settings.scale = 1.5f;
    const SnapshotResult r = renderer.render(view, 64, 48, settings);
    ASSERT_EQ(r.snapshot.width(), 96);
    ASSERT_EQ(r.snapshot.height(), 72);
    ASSERT_EQ(r.laplacian.width(), 96);
    ASSERT_EQ(r.aamap.width(), 64);
    ASSERT_EQ(r.aamap.height(), 48);
    EXPECT_FALSE(r.deviceName.empty());
    EXPECT_FALSE(r.explain.empty());
    // Shadow cube maps for the light, the raster (which writes the grey too: no mirror), the chain.
    ASSERT_EQ(r.passTimes.size(), 5u);
    EXPECT_EQ(r.passTimes.front().pass, "shadow");
    EXPECT_EQ(r.passTimes[1].pass, "gbuffer");
    EXPECT_EQ(r.passTimes[2].pass, "laplacian");
    EXPECT_EQ(r.passTimes.back().pass, "reduce");

    // Every snapshot pixel: the tracer's ray through the pixel centre hits the quad iff the raster
    // covered the pixel; skip rays that pass within a hair of the quad's border.
    const PinholeCamera camera = PinholeCamera::fromView(view);
    int covered = 0, checked = 0;
    for (int y = 0; y < r.snapshot.height(); ++y) {
        for (int x = 0; x < r.snapshot.width(); ++x) {
            const float u = (x + 0.5f) / r.snapshot.width(), v = (y + 0.5f) / r.snapshot.height();
            const glm::vec3 d = camera.direction(u, v);
            const float t = -camera.origin.z / d.z;
            const glm::vec3 hit = camera.origin + t * d;
            const float margin = std::min({std::fabs(hit.x + 0.3f), std::fabs(hit.x - 1.0f), std::fabs(hit.y + 1.0f),
                                           std::fabs(hit.y - 0.5f)});
            if (margin < 1e-3f) continue;
            const bool inside = hit.x > -0.3f && hit.x < 1.0f && hit.y > -1.0f && hit.y < 0.5f;
            const bool lit = r.snapshot.at(x, y).g > 0.0f;
            ASSERT_EQ(inside, lit) << "pixel " << x << "," << y << " hit " << hit.x << "," << hit.y;
            covered += inside;
            ++checked;
        }
    }
    EXPECT_GT(covered, checked / 4);
    EXPECT_LT(covered, checked * 3 / 4);

    // Shading: Lambert from the point light, kd/pi * I * cos / d^2, at the hit point of a ray.
    const int px = 40, py = 30;
    const glm::vec3 d = camera.direction((px + 0.5f) / 96.0f, (py + 0.5f) / 72.0f);
    const glm::vec3 hit = camera.origin + (-camera.origin.z / d.z) * d;
    const glm::vec3 toLight = scene.pointLights[0].position - hit;
    const float cosine = toLight.z / glm::length(toLight);
    const float expected = 0.8f / kPi * 10.0f * cosine / glm::dot(toLight, toLight);
    EXPECT_NEAR(r.snapshot.at(px, py).r, expected, 1e-4f * expected);

    // Background corner, flat interior and the quad's edge in the aamap.
    EXPECT_EQ(r.snapshot.at(0, 0), glm::vec3(0.0f));
    EXPECT_EQ(r.aamap.at(0, 0), 0.0f);
    EXPECT_EQ(r.aamap.at(30, 24), 0.0f);
    float edgeMax = 0.0f;
    for (int x = 0; x < 64; ++x) edgeMax = std::max(edgeMax, r.aamap.at(x, 24));
    EXPECT_GT(edgeMax, 0.5f);
}

TEST_F(SnapshotGraph, WithoutDebugImagesOnlyTheAamapComesBack) {
    const Scene scene = quadScene();
    SnapshotRenderer renderer(context(), scene);
    SnapshotSettings settings;
    settings.scale = 1.3f;  // 83 x 52 for 64 x 40: footprints of unequal width
    const SnapshotResult full = renderer.render(quadView(), 64, 40, settings);
    settings.keepDebugImages = false;
    const SnapshotResult lean = renderer.render(quadView(), 64, 40, settings);
    EXPECT_EQ(full.snapshot.width(), 83);
    EXPECT_EQ(full.snapshot.height(), 52);
    EXPECT_TRUE(lean.snapshot.empty());
    EXPECT_TRUE(lean.laplacian.empty());
    EXPECT_EQ(lean.aamap, full.aamap);  // deterministic, and independent of what is read back
    for (float v : lean.aamap.pixels()) {
        ASSERT_GE(v, 0.0f);
        ASSERT_LE(v, 1.0f);
    }
    EXPECT_GT(lean.totalSeconds, 0.0);
}

TEST_F(SnapshotGraph, AreaLightBecomesLobesAndEmitterShowsItsRadiance) {
    Scene scene;
    Material floor, lamp;
    floor.name = "floor";
    floor.kd = glm::vec3(0.5f);
    lamp.name = "lamp";
    lamp.kd = glm::vec3(0.0f);
    lamp.ke = glm::vec3(4.0f, 3.0f, 2.0f);
    scene.materials = {floor, lamp};
    addQuad(scene, -2.0f, 2.0f, -2.0f, 2.0f, 0.0f, {0, 0, 1}, 0);   // floor at z = 0, facing up (+z)
    addQuad(scene, -0.2f, 0.2f, -0.2f, 0.2f, 1.0f, {0, 0, -1}, 1);  // lamp at z = 1, facing down
    scene.areaLights = buildAreaLights(scene);
    ASSERT_EQ(scene.areaLights.size(), 1u);

    View view;  // from above, looking down past the lamp at the floor point below its centre
    view.position = {0.0f, -1.5f, 3.0f};
    view.direction = glm::normalize(glm::vec3(0.0f, 0.5f, -1.0f));
    view.up = {0, 0, 1};
    view.horizontalFovDeg = view.verticalFovDeg = 60.0f;
    SnapshotRenderer renderer(context(), scene);
    SnapshotSettings settings;
    settings.areaLightSamples = 5;
    const SnapshotResult r = renderer.render(view, 40, 40, settings);

    // The lamp faces away from this camera: its back shows black; the floor below it is lit.
    // Below the lamp centre (0,0,0), with k lobes of radiance*area/k each, the irradiance is close
    // to that of the area light: E ~ L * A / d^2 (small light), so radiance kd/pi * E.
    float brightest = 0.0f;
    for (const glm::vec3& c : r.snapshot.pixels()) brightest = std::max(brightest, c.r);
    const float area = 0.4f * 0.4f;
    const float expectedBelow = 0.5f / kPi * 4.0f * area / 1.0f;
    EXPECT_NEAR(brightest, expectedBelow, 0.1f * expectedBelow);  // the lobes sit off-centre

    // Seen from below, the emitter shows exactly its Ke.
    View below;
    below.position = {0.0f, 0.0f, 0.5f};
    below.direction = {0, 0, 1};
    below.up = {0, 1, 0};
    below.horizontalFovDeg = below.verticalFovDeg = 20.0f;
    const SnapshotResult up = renderer.render(below, 16, 16, settings);
    const glm::vec3 centre = up.snapshot.at(up.snapshot.width() / 2, up.snapshot.height() / 2);
    EXPECT_EQ(centre, glm::vec3(4.0f, 3.0f, 2.0f));
}

// A glossy floor shows the tracer's highlight: kd / pi plus the modified Phong lobe
// ks (ns + 2) / (2 pi) cos^ns(alpha) about the view's mirror direction, with kd + ks scaled to 1.
TEST_F(SnapshotGraph, GlossyMaterialsShowTheTracersHighlight) {
    Scene scene;
    Material glossy;
    glossy.name = "glossy";
    glossy.kd = glm::vec3(0.6f);
    glossy.ks = glm::vec3(0.6f);  // kd + ks = 1.2: both scaled by 1 / 1.2, as the tracer does
    glossy.ns = 40.0f;
    scene.materials = {glossy};
    addQuad(scene, -3.0f, 3.0f, -3.0f, 3.0f, 0.0f, {0, 0, 1}, 0);
    PointLight light;
    light.position = {0.0f, 0.0f, 3.0f};
    light.intensity = glm::vec3(9.0f);
    scene.pointLights.push_back(light);
    const glm::vec3 eye(0.0f, 0.0f, 2.0f);
    constexpr float kFov = 60.0f;
    SnapshotRenderer renderer(context(), scene);
    const SnapshotResult r = renderer.render(viewDownZ(eye, kFov), 32, 32, SnapshotSettings{});
    const int w = static_cast<int>(r.snapshot.width()), h = static_cast<int>(r.snapshot.height());
    const float kd = 0.6f / 1.2f, ks = 0.6f / 1.2f;
    const float halfWidth = std::tan(glm::radians(kFov * 0.5f)) * eye.z;  // of the floor in view
    for (const int px : {w / 2, w / 2 + w / 16, w / 2 + w / 8, w / 2 + w / 4}) {
        const int py = h / 2;
        const glm::vec3 p(((px + 0.5f) / w * 2.0f - 1.0f) * halfWidth, (1.0f - (py + 0.5f) / h * 2.0f) * halfWidth, 0.0f);
        const glm::vec3 toLight = light.position - p, wo = glm::normalize(eye - p);
        const glm::vec3 wi = glm::normalize(toLight), n(0, 0, 1);
        const glm::vec3 mirror = glm::reflect(-wo, n);
        const float lobe = std::pow(std::max(glm::dot(mirror, wi), 0.0f), glossy.ns);
        const float f = kd / kPi + ks * (glossy.ns + 2.0f) / (2.0f * kPi) * lobe;
        const float expected = f * 9.0f * wi.z / glm::dot(toLight, toLight);
        EXPECT_NEAR(r.snapshot.at(px, py).g, expected, 2e-3f * expected + 1e-5f) << "pixel " << px;
    }
}

// The G-buffer writes the grey of step 1 itself when no mirror composite follows it; the aamap
// built on it must be the CPU chain's on the snapshot colour the same run read back (the Cornell
// box: shadows from the area light's samples, emitter, coloured walls).
TEST_F(SnapshotGraph, ChainOnTheGBuffersGreyMatchesTheCpuChainOnItsColour) {
    const Scene scene = builtinScene("cornell");
    SnapshotRenderer renderer(context(), scene);
    SnapshotSettings settings;
    settings.scale = 1.5f;
    const SnapshotResult r = renderer.render(scene.views.at(0), 80, 64, settings);
    for (const PassTiming& t : r.passTimes) EXPECT_NE(t.pass, "luminance");
    ASSERT_EQ(r.snapshot.width(), 120);
    const cpu::AamapImages expected = cpu::buildAamap(r.snapshot, 80, 64, settings.filter, cpu::Mode::Scalar);
    // The filter tests' tolerance (tests/gpu/test_gpu_filters.cpp): the GPU Laplacian rounds its
    // 24 differences in float.
    constexpr float kTolerance = 1e-5f;
    EXPECT_LE(maxAbsDiff(r.laplacian, expected.laplacian), kTolerance);
    EXPECT_LE(maxAbsDiff(r.aamap, expected.aamap), kTolerance);
    int flagged = 0;
    for (float v : r.aamap.pixels()) flagged += v > 0.0f;
    EXPECT_GT(flagged, 100);  // the box's edges and shadows are there to compare
}

}  // namespace
}  // namespace aamap::test
