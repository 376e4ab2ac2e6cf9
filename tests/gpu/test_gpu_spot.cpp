// A spot light in the Snapshot agrees with the tracer's direct light: the same cone, the same
// falloff, on a plane with nothing to shadow it; alone, beside an isotropic and a lobed point
// light, and after eight others: the G-buffer's shader is specialised for the kinds in the list
// and holds the first LIGHTING_INLINE_LIGHTS lights as constants, reading the rest from its
// uniform buffer (glsl/lights.glsl), and each way must shade alike.
#include <algorithm>
#include <cmath>
#include <string>

#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>

#include "gpu_fixture.h"
#include "passes/snapshot.h"
#include "scene/camera.h"
#include "scene/lights.h"
#include "tracer/embree_scene.h"
#include "tracer/integrator.h"
#include "tracer/lights.h"

namespace aamap::test {
namespace {

constexpr float kPi = 3.14159265358979f;

enum class Lights { SpotAlone, SpotIsotropicAndLobe, AfterEightOthers };

// A grey plane z = 0 (facing +z) under a tilted spot (inner 15, outer 35 degrees), seen from above;
// then an isotropic light and a lobed one (the point sample of an area light), and for
// AfterEightOthers, eight dim isotropic lights before all three.
Scene spotOnPlane(Lights which) {
    Scene scene;
    scene.name = "spot";
    Material grey;
    grey.name = "grey";
    grey.kd = glm::vec3(0.7f, 0.6f, 0.5f);
    scene.materials.push_back(grey);
    scene.mesh.positions = {{-3, -3, 0}, {3, -3, 0}, {3, 3, 0}, {-3, 3, 0}};
    scene.mesh.normals.assign(4, {0, 0, 1});
    scene.mesh.triangles = {{0, 1, 2}, {0, 2, 3}};
    scene.mesh.materialIds = {0, 0};
    scene.mesh.objectIds = {0, 0};
    PointLight spot;
    spot.name = "spot";
    spot.position = {0.2f, -0.1f, 1.5f};
    spot.intensity = {12.0f, 9.0f, 6.0f};
    spot.spotDirection = glm::normalize(glm::vec3(0.3f, 0.15f, -1.0f));
    spot.cosInner = std::cos(glm::radians(15.0f));
    spot.cosOuter = std::cos(glm::radians(35.0f));
    if (which == Lights::AfterEightOthers)
        for (int k = 0; k < 8; ++k) {
            PointLight dim;
            dim.name = "dim" + std::to_string(k);
            dim.position = {-2.0f + 0.5f * static_cast<float>(k), 2.0f - 0.3f * static_cast<float>(k), 2.5f};
            dim.intensity = glm::vec3(0.05f + 0.01f * static_cast<float>(k));
            scene.pointLights.push_back(dim);
        }
    scene.pointLights.push_back(spot);
    if (which != Lights::SpotAlone) {
        PointLight isotropic;
        isotropic.name = "isotropic";
        isotropic.position = {-1.5f, 1.0f, 1.2f};
        isotropic.intensity = {1.5f, 2.0f, 2.5f};
        PointLight lobe;
        lobe.name = "lobe";
        lobe.position = {1.4f, 1.6f, 0.8f};
        lobe.intensity = {3.0f, 2.0f, 1.0f};
        lobe.normal = glm::normalize(glm::vec3(-0.5f, 0.0f, -1.0f));
        scene.pointLights.push_back(isotropic);
        scene.pointLights.push_back(lobe);
    }
    View view;
    view.position = {0.4f, 0.1f, 3.0f};
    view.direction = {0, 0, -1};
    view.up = {0, 1, 0};
    view.horizontalFovDeg = view.verticalFovDeg = 70.0f;
    scene.views.push_back(view);
    return scene;
}

class SpotShading : public GpuTest, public ::testing::WithParamInterface<Lights> {};

TEST_P(SpotShading, AgreesWithTheDirectLight) {
    const Scene scene = spotOnPlane(GetParam());
    const View& view = scene.views[0];
    SnapshotRenderer renderer(context(), scene);
    SnapshotSettings settings;
    settings.scale = 1.0f;
    const SnapshotResult r = renderer.render(view, 64, 64, settings);
    ASSERT_EQ(r.snapshot.width(), 64);

    const EmbreeScene geometry(scene);
    const LightSet lights = buildLights(scene, geometry);
    const std::unique_ptr<Integrator> owned = makeIntegrator(geometry, lights, ShadingSettings{});
    const Integrator& integrator = *owned;
    const PinholeCamera camera = PinholeCamera::fromView(view);
    // Past LightSet::kFewLights the tracer samples lights instead of summing them, so there the
    // reference is the sum itself: kd / pi * I * emissionFactor * cos / d^2 over the lights.
    const bool tracerSumsLights = !lights.many();
    ASSERT_EQ(tracerSumsLights, GetParam() != Lights::AfterEightOthers);
    const auto analytic = [&](const glm::vec3& hit) {
        glm::vec3 sum(0.0f);
        for (const PointLight& l : scene.pointLights) {
            const glm::vec3 toLight = l.position - hit;
            const float d2 = glm::dot(toLight, toLight);
            const glm::vec3 wi = toLight / std::sqrt(d2);
            sum += scene.materials[0].kd / kPi * l.intensity * emissionFactor(l, -wi) * std::max(wi.z, 0.0f) / d2;
        }
        return sum;
    };

    // Both sides evaluate kd / pi * I * falloff * cos / d^2 in float at the same point (the ray
    // through the pixel centre meets the plane where the raster's interpolated position is, to
    // float rounding, ~1e-6 relative). The steepest term is the falloff, whose slope in the cone
    // cosine is at most 2 / (cosInner - cosOuter) ~ 13; so the two agree to ~1e-5 of the peak.
    // Tolerance: 1e-4 relative plus 2e-4 of the peak radiance.
    float peak = 0.0f;
    std::vector<glm::vec3> traced(64 * 64);
    for (int y = 0; y < 64; ++y)
        for (int x = 0; x < 64; ++x) {
            const glm::vec3 d = camera.direction((x + 0.5f) / 64.0f, (y + 0.5f) / 64.0f);
            RayCounts rays;
            const Sampler sampler(static_cast<std::uint64_t>(y * 64 + x), 0, 1);
            traced[static_cast<std::size_t>(y * 64 + x)] =
                tracerSumsLights ? integrator.primary(camera.origin, d, sampler, rays)
                                 : analytic(camera.origin + (-camera.origin.z / d.z) * d);
            peak = std::max(peak, traced[static_cast<std::size_t>(y * 64 + x)].r);
        }
    ASSERT_GT(peak, 0.0f);
    int dark = 0, band = 0, full = 0;
    const PointLight& spot = scene.pointLights[GetParam() == Lights::AfterEightOthers ? 8 : 0];
    ASSERT_EQ(spot.name, "spot");
    for (int y = 0; y < 64; ++y)
        for (int x = 0; x < 64; ++x) {
            const glm::vec3 want = traced[static_cast<std::size_t>(y * 64 + x)];
            const glm::vec3 got = r.snapshot.at(x, y);
            for (int c = 0; c < 3; ++c)
                ASSERT_NEAR(got[c], want[c], 1e-4f * want[c] + 2e-4f * peak) << "pixel " << x << "," << y << " channel " << c;
            // Which part of the cone the pixel sees (to make sure every part is exercised).
            const glm::vec3 d = camera.direction((x + 0.5f) / 64.0f, (y + 0.5f) / 64.0f);
            const glm::vec3 hit = camera.origin + (-camera.origin.z / d.z) * d;
            const float c = glm::dot(glm::normalize(hit - spot.position), spot.spotDirection);
            if (c <= spot.cosOuter) ++dark;
            else if (c >= spot.cosInner) ++full;
            else ++band;
        }
    EXPECT_GT(dark, 100);
    EXPECT_GT(band, 100);
    EXPECT_GT(full, 100);
}

INSTANTIATE_TEST_SUITE_P(Lights, SpotShading,
                         ::testing::Values(Lights::SpotAlone, Lights::SpotIsotropicAndLobe, Lights::AfterEightOthers),
                         [](const ::testing::TestParamInfo<Lights>& info) {
                             switch (info.param) {
                                 case Lights::SpotAlone: return "SpotAlone";
                                 case Lights::SpotIsotropicAndLobe: return "SpotIsotropicAndLobe";
                                 default: return "AfterEightOthers";
                             }
                         });

}  // namespace
}  // namespace aamap::test
