// Glass in the Snapshot (passes/gbuffer.h, "Glass"): the camera sees what lies behind it, as the
// tracer does (a dielectric has no diffuse lobe), blended with a Fresnel-weighted reflection
// estimate, so silhouettes show; and it still casts shadows, as it stops the tracer's shadow rays.
#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>

#include "gpu_fixture.h"
#include "passes/snapshot.h"
#include "tests/common/test_scenes.h"

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
    EXPECT_TRUE(px >= 0 && py >= 0 && px < static_cast<int>(r.snapshot.width()) &&
                py < static_cast<int>(r.snapshot.height()))
        << "(" << x << ", " << y << ") is outside the view";
    return r.snapshot.at(std::clamp(px, 0, static_cast<int>(r.snapshot.width()) - 1),
                         std::clamp(py, 0, static_cast<int>(r.snapshot.height()) - 1));
}

SnapshotResult snapshotOf(VulkanContext& context, const Scene& scene) {
    SnapshotRenderer renderer(context, scene);
    return renderer.render(topView(), 64, 64, SnapshotSettings{});
}

class SnapshotGlass : public GpuTest {};  // the suite names the feature a failure is in

// Schlick's Fresnel reflectance for index `ior` at cosine `c` to the normal.
float schlick(float ior, float c) {
    const float f0 = (ior - 1.0f) * (ior - 1.0f) / ((ior + 1.0f) * (ior + 1.0f));
    return f0 + (1.0f - f0) * std::pow(1.0f - c, 5.0f);
}

// The pane's reflection estimate at its centre (0, 0, 0.5), normal +z: a white Lambert surface's
// radiance under the point light, E / pi.
glm::vec3 paneReflected() {
    const glm::vec3 toLight = glm::vec3(3.0f, 0.0f, 2.0f) - glm::vec3(0.0f, 0.0f, 0.5f);
    const float d2 = glm::dot(toLight, toLight);
    const float cosine = toLight.z / std::sqrt(d2);
    return glm::vec3(20.0f * cosine / d2 / 3.14159265f);
}

Scene withoutPane(Scene scene) {
    const std::size_t keep = 4;  // the floor's and the square's triangles
    scene.mesh.triangles.resize(keep);
    scene.mesh.materialIds.resize(keep);
    scene.mesh.objectIds.resize(keep);
    return scene;
}

TEST_F(SnapshotGlass, GlassShowsWhatIsBehindItFresnelWeightedAndStillCastsShadows) {
    const Scene scene = paneScene(MaterialKind::Glass);
    const SnapshotResult glass = snapshotOf(context(), scene);
    const SnapshotResult opaque = snapshotOf(context(), paneScene(MaterialKind::Diffuse));
    const SnapshotResult bare = snapshotOf(context(), withoutPane(scene));
    // Through the pane, seen face-on: (1 - F) x the red square + F x the reflection estimate, F
    // about 4 % (ior 1.5); the diffuse pane shows white instead.
    const float f = schlick(1.5f, 1.0f);
    const glm::vec3 expected = (1.0f - f) * at(bare, 0.0f, 0.0f) + f * paneReflected();
    const glm::vec3 throughGlass = at(glass, 0.0f, 0.0f);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(throughGlass[c], expected[c], 2e-3f * (1.0f + expected[c])) << c;
    EXPECT_GT(throughGlass.r, 0.9f * at(bare, 0.0f, 0.0f).r);
    EXPECT_GT(at(opaque, 0.0f, 0.0f).g, 10.0f * throughGlass.g);
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

// Only the pane (floor and square removed): the camera's opaque draw has nothing to draw, the
// pane shows its reflection estimate over the black background, and the shadow pass still draws
// it; no crash, no validation message.
TEST_F(SnapshotGlass, GlassOnlySceneDrawsThePaneOverTheBackground) {
    Scene scene = paneScene(MaterialKind::Glass);
    scene.mesh.triangles.erase(scene.mesh.triangles.begin(), scene.mesh.triangles.begin() + 4);
    scene.mesh.materialIds.erase(scene.mesh.materialIds.begin(), scene.mesh.materialIds.begin() + 4);
    scene.mesh.objectIds.erase(scene.mesh.objectIds.begin(), scene.mesh.objectIds.begin() + 4);
    const SnapshotResult paneOnly = snapshotOf(context(), scene);
    EXPECT_TRUE(hasShadowPass(paneOnly));
    const glm::vec3 centre = at(paneOnly, 0.0f, 0.0f);
    EXPECT_NEAR(centre.g, schlick(1.5f, 1.0f) * paneReflected().g, 2e-3f);
    EXPECT_EQ(at(paneOnly, 1.0f, 1.0f), glm::vec3(0.0f)) << "outside the pane, inside the view: the background";
}

// A glass sphere in front of a uniformly lit wall: its silhouette is in the aamap (Fresnel -> 1 at
// grazing angles), while the same wall without the sphere flags nothing there.
TEST_F(SnapshotGlass, AGlassSpheresSilhouetteIsInTheMap) {
    Scene scene;
    scene.name = "glass-sphere";
    Material wall, glassMaterial;
    wall.kd = glm::vec3(0.5f);
    glassMaterial.kind = MaterialKind::Glass;
    glassMaterial.ior = 1.5f;
    scene.materials = {wall, glassMaterial};
    addQuadZ(scene, 0.0f, -4.0f, 4.0f, -4.0f, 4.0f, 0);
    PointLight light;  // far above the camera: the wall is lit almost uniformly
    light.position = {0.0f, 0.0f, 40.0f};
    light.intensity = glm::vec3(1600.0f * 3.14159265f);
    scene.pointLights.push_back(light);
    const Scene empty = scene;
    constexpr float kRadius = 0.8f, kSphereZ = 1.0f;
    addSphere(scene, {0.0f, 0.0f, kSphereZ}, kRadius, 48, 24, 1, 1);

    const View view = topView();
    constexpr int kSize = 96;
    SnapshotRenderer withSphere(context(), scene), without(context(), empty);
    const SnapshotResult sphere = withSphere.render(view, kSize, kSize, SnapshotSettings{});
    const SnapshotResult plain = without.render(view, kSize, kSize, SnapshotSettings{});

    // The silhouette seen from the camera: the circle where the view ray grazes the sphere, at
    // angle asin(r / d) from the axis (the sphere's centre lies on it).
    const float d = kCameraHeight - kSphereZ;
    const float angle = std::asin(kRadius / d);
    const float radiusPx = std::tan(angle) / std::tan(glm::radians(kFovDeg) * 0.5f) * 0.5f * kSize;
    int onSilhouette = 0, flagged = 0, flaggedWithout = 0;
    for (int k = 0; k < 360; k += 3) {
        const float a = glm::radians(static_cast<float>(k));
        const int x = static_cast<int>(0.5f * kSize + radiusPx * std::cos(a));
        const int y = static_cast<int>(0.5f * kSize + radiusPx * std::sin(a));
        ++onSilhouette;
        flagged += sphere.aamap.at(x, y) > 0.0f ? 1 : 0;
        flaggedWithout += plain.aamap.at(x, y) > 0.0f ? 1 : 0;
    }
    EXPECT_GE(flagged, onSilhouette * 95 / 100) << "of " << onSilhouette << " silhouette pixels";
    EXPECT_EQ(flaggedWithout, 0);
}

}  // namespace
}  // namespace aamap::test
