// Glass in the Snapshot (passes/gbuffer.h, "Glass"): the camera sees through it, as the tracer
// does (a dielectric has no diffuse lobe), and it still casts shadows, as it stops the tracer's
// shadow rays. The same scene with the glass material made diffuse shows the pane instead.
#include <cmath>

#include <glm/geometric.hpp>

#include "gpu_fixture.h"
#include "passes/snapshot.h"
#include "test_scenes.h"

namespace aamap::test {
namespace {

constexpr float kCameraHeight = 3.0f;
constexpr float kFovDeg = 50.0f;

// A grey floor z = 0, a red square on it at the centre, and a pane of `paneKind` at z = 0.5 over
// [-0.5, 0.5]^2 between the camera (straight above) and the square. The light, up and to the
// right, puts the pane's shadow on the floor at x in [-1.67, -0.33]: the red square stays lit.
Scene paneScene(MaterialKind paneKind) {
    Scene scene;
    scene.name = "pane";
    Material grey, red, pane;
    grey.kd = glm::vec3(0.8f);
    red.kd = {0.8f, 0.0f, 0.0f};
    pane.kind = paneKind;
    pane.kd = glm::vec3(1.0f);  // ignored by the tracer for glass
    pane.ks = glm::vec3(1.0f);
    scene.materials = {grey, red, pane};
    addQuadZ(scene, 0.0f, -2.0f, 2.0f, -2.0f, 2.0f, 0);
    addQuadZ(scene, 0.001f, -0.25f, 0.25f, -0.25f, 0.25f, 1);
    addQuadZ(scene, 0.5f, -0.5f, 0.5f, -0.5f, 0.5f, 2);
    PointLight light;
    light.position = {3.0f, 0.0f, 2.0f};
    light.intensity = glm::vec3(20.0f);
    scene.pointLights.push_back(light);
    return scene;
}

View topView() { return viewDownZ({0.0f, 0.0f, kCameraHeight}, kFovDeg); }

// The snapshot's colour where the camera sees the floor point (x, y, 0) (unless something is in
// front of it).
glm::vec3 at(const SnapshotResult& r, float x, float y) {
    const float t = std::tan(glm::radians(kFovDeg) * 0.5f) * kCameraHeight;
    const int px = static_cast<int>((x / t + 1.0f) * 0.5f * static_cast<float>(r.snapshot.width()));
    const int py = static_cast<int>((1.0f - y / t) * 0.5f * static_cast<float>(r.snapshot.height()));
    return r.snapshot.at(px, py);
}

SnapshotResult snapshotOf(VulkanContext& context, const Scene& scene) {
    SnapshotRenderer renderer(context, scene);
    return renderer.render(topView(), 64, 64, SnapshotSettings{});
}

class SnapshotGlass : public GpuTest {};  // the suite names the feature a failure is in

TEST_F(SnapshotGlass, GlassIsSeenThroughAndStillCastsShadows) {
    const SnapshotResult glass = snapshotOf(context(), paneScene(MaterialKind::Glass));
    const SnapshotResult opaque = snapshotOf(context(), paneScene(MaterialKind::Diffuse));
    // Through the pane: the red square, as without any pane; the diffuse pane shows white instead.
    const glm::vec3 throughGlass = at(glass, 0.0f, 0.0f), throughDiffuse = at(opaque, 0.0f, 0.0f);
    EXPECT_GT(throughGlass.r, 0.05f);
    EXPECT_LT(throughGlass.g, 1e-6f);
    EXPECT_GT(throughDiffuse.g, 0.05f);
    // Floor seen beside the pane: in its shadow at x = -1 (the light is at x = 3), lit at x = 1.
    const glm::vec3 shadowed = at(glass, -1.0f, 0.0f), lit = at(glass, 1.0f, 0.0f);
    EXPECT_GT(lit.g, 0.05f);
    EXPECT_LT(shadowed.g, 0.01f * lit.g);
    EXPECT_FLOAT_EQ(at(opaque, -1.0f, 0.0f).g, shadowed.g);  // the same shadow either way
}

bool hasShadowPass(const SnapshotResult& r) {
    for (const PassTiming& p : r.passTimes)
        if (p.pass == "shadow") return true;
    return false;
}

// Only the pane (floor and square removed): nothing for the camera to draw, so the snapshot is
// black, while the shadow pass still draws the pane; no crash, no validation message.
TEST_F(SnapshotGlass, GlassOnlySceneDrawsNothingForTheCameraButItsShadowPass) {
    Scene scene = paneScene(MaterialKind::Glass);
    scene.mesh.triangles.erase(scene.mesh.triangles.begin(), scene.mesh.triangles.begin() + 4);
    scene.mesh.materialIds.erase(scene.mesh.materialIds.begin(), scene.mesh.materialIds.begin() + 4);
    scene.mesh.objectIds.erase(scene.mesh.objectIds.begin(), scene.mesh.objectIds.begin() + 4);
    const SnapshotResult paneOnly = snapshotOf(context(), scene);
    EXPECT_TRUE(hasShadowPass(paneOnly));
    for (const glm::vec3& c : paneOnly.snapshot.pixels()) ASSERT_EQ(c, glm::vec3(0.0f));
}

}  // namespace
}  // namespace aamap::test
