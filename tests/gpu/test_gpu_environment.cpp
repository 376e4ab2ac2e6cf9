// The Snapshot's lights at infinity against the tracer (passes/environment_lighting.h, the
// directional light kind of glsl/lights.glsl and its orthographic shadow map):
// - a constant sky on a convex white box: the SH ambient term gives a L, as the tracer does, and
//   the background is the sky's radiance;
// - a sky map black but for one small bright cell, over a floor with a box floating above it:
//   the Snapshot extracts the cell as a shadowed directional light, and its image shows the
//   tracer's shadow (the map importance-sampled, Direct mode): the same pixels shadowed and lit,
//   away from the shadow's edges (the map's texels and the bias blur them by a pixel or two), and
//   the same radiance on the lit ones;
// - the same with the scene's own directional light instead of a map.
#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

#include <glm/geometric.hpp>

#include "gpu_fixture.h"
#include "passes/snapshot.h"
#include "scene/camera.h"
#include "scene/lat_long.h"
#include "tracer/embree_scene.h"
#include "tracer/integrator.h"
#include "tracer/lights.h"

namespace aamap::test {
namespace {

constexpr int kSize = 64;

void addQuad(Scene& s, glm::vec3 p0, glm::vec3 a, glm::vec3 b, std::uint32_t material) {
    TriangleMesh& m = s.mesh;
    const auto base = static_cast<std::uint32_t>(m.positions.size());
    const glm::vec3 n = glm::normalize(glm::cross(a, b));
    for (const glm::vec3& p : {p0, p0 + a, p0 + a + b, p0 + b}) {
        m.positions.push_back(p);
        m.normals.push_back(n);
    }
    m.triangles.push_back({base, base + 1, base + 2});
    m.triangles.push_back({base, base + 2, base + 3});
    const auto object = static_cast<std::uint32_t>(m.objectIds.empty() ? 0 : m.objectIds.back() + 1);
    for (int i = 0; i < 2; ++i) {
        m.materialIds.push_back(material);
        m.objectIds.push_back(object);
    }
}

void addBox(Scene& s, glm::vec3 lo, glm::vec3 hi, std::uint32_t material) {
    const glm::vec3 d = hi - lo, X(d.x, 0, 0), Y(0, d.y, 0), Z(0, 0, d.z);
    addQuad(s, lo, Y, X, material);
    addQuad(s, lo + Z, X, Y, material);
    addQuad(s, lo, Z, Y, material);
    addQuad(s, lo + X, Y, Z, material);
    addQuad(s, lo, X, Z, material);
    addQuad(s, lo + Y, Z, X, material);
}

Scene withMaterial(float albedo) {
    Scene s;
    s.name = "environment";
    Material m;
    m.name = "grey";
    m.kd = glm::vec3(albedo);
    s.materials.push_back(m);
    return s;
}

View lookAt(glm::vec3 from, glm::vec3 to, float fov) {
    View v;
    v.position = from;
    v.direction = glm::normalize(to - from);
    v.up = {0, 1, 0};
    v.horizontalFovDeg = v.verticalFovDeg = fov;
    return v;
}

// The tracer's Direct radiance through each pixel centre, and whether the ray hit anything.
struct Traced {
    std::vector<glm::vec3> radiance;
    std::vector<bool> hit;
};
Traced trace(const Scene& scene, const View& view) {
    const EmbreeScene geometry(scene);
    const LightSet lights = buildLights(scene, geometry);
    const std::unique_ptr<Integrator> owned = makeIntegrator(geometry, lights, ShadingSettings{});
    const Integrator& integrator = *owned;
    const PinholeCamera camera = PinholeCamera::fromView(view);
    Traced t;
    for (int y = 0; y < kSize; ++y)
        for (int x = 0; x < kSize; ++x) {
            const glm::vec3 d = camera.direction((x + 0.5f) / kSize, (y + 0.5f) / kSize);
            RayCounts rays;
            const Sampler sampler(static_cast<std::uint64_t>(y * kSize + x), 0, 1);
            t.radiance.push_back(integrator.primary(camera.origin, d, sampler, rays));
            SurfaceHit hit;
            t.hit.push_back(integrator.intersect(camera.origin, d, hit, rays.primary));
        }
    return t;
}

class SnapshotEnvironment : public GpuTest {};

TEST_F(SnapshotEnvironment, ConstantSkyOnAConvexBoxIsAlbedoTimesSky) {
    Scene scene = withMaterial(0.6f);
    addBox(scene, {-0.5f, -0.4f, -0.3f}, {0.5f, 0.4f, 0.3f}, 0);
    EnvironmentLight sky;
    sky.scale = {0.5f, 1.0f, 2.0f};
    scene.environment = sky;
    const View view = lookAt({1.6f, 1.3f, 2.0f}, {0, 0, 0}, 45);
    SnapshotRenderer renderer(context(), scene);
    SnapshotSettings settings;
    settings.scale = 1.0f;
    const SnapshotResult r = renderer.render(view, kSize, kSize, settings);
    const Traced t = trace(scene, view);
    int surface = 0, background = 0;
    for (int i = 0; i < kSize * kSize; ++i) {
        if (!t.hit[static_cast<std::size_t>(i)]) {  // the background is the constant sky, exactly
            ++background;
            ASSERT_EQ(r.snapshot.at(i % kSize, i / kSize), t.radiance[static_cast<std::size_t>(i)]) << "pixel " << i;
            continue;
        }
        ++surface;
        const glm::vec3 got = r.snapshot.at(i % kSize, i / kSize), want = t.radiance[static_cast<std::size_t>(i)];
        for (int c = 0; c < 3; ++c) ASSERT_NEAR(got[c], want[c], 1e-3f * want[c]) << "pixel " << i << " channel " << c;
    }
    EXPECT_GT(surface, kSize * kSize / 8);
    EXPECT_GT(background, kSize * kSize / 8);
    EXPECT_EQ(r.shadowCubeMaps, 0);  // no lights to shadow: the ambient term alone, no shadow pass
}

enum class Sun { MapCell, DirectionalLight };

Scene floorAndBlocker(Sun sun) {
    constexpr int w = 512, h = 256, column = 44, row = 60;
    const glm::vec3 radiance(20000.0f, 15000.0f, 10000.0f);
    Scene scene = withMaterial(0.5f);
    addQuad(scene, {-3, 0, -3}, {0, 0, 6}, {6, 0, 0}, 0);
    addBox(scene, {-0.4f, 0.5f, -0.3f}, {0.3f, 0.8f, 0.4f}, 0);
    const glm::vec3 toSun = latlong::toDirection({(column + 0.5f) / w, (row + 0.5f) / h});
    if (sun == Sun::DirectionalLight) {
        DirectionalLight d;
        d.name = "sun";
        d.direction = -toSun;
        d.irradiance = radiance * static_cast<float>(latlong::pixelSolidAngle(row, w, h));
        scene.directionalLights.push_back(d);
        return scene;
    }
    EnvironmentLight env;
    env.name = "sun-map";
    env.mapWidth = w;
    env.mapHeight = h;
    env.map.assign(static_cast<std::size_t>(w) * h, glm::vec3(0.0f));
    env.map[static_cast<std::size_t>(row) * w + column] = radiance;
    scene.environment = env;
    return scene;
}

class SnapshotSun : public GpuTest, public ::testing::WithParamInterface<Sun> {};

TEST_P(SnapshotSun, ShowsTheTracersShadow) {
    const Scene scene = floorAndBlocker(GetParam());
    const View view = lookAt({0.5f, 2.5f, 2.5f}, {0, 0, 0}, 55);
    SnapshotRenderer renderer(context(), scene);
    SnapshotSettings settings;
    settings.scale = 1.0f;
    settings.environmentLights = 1;
    const SnapshotResult r = renderer.render(view, kSize, kSize, settings);
    EXPECT_EQ(r.shadowCubeMaps, 1);  // the one directional light's orthographic map
    EXPECT_NE(r.explain.find(GetParam() == Sun::MapCell ? "'sun-map#0'" : "'sun'"), std::string::npos) << r.explain;
    const Traced t = trace(scene, view);
    float peak = 0.0f;
    for (const glm::vec3& c : t.radiance) peak = std::max(peak, c.y);
    ASSERT_GT(peak, 0.0f);
    const auto lit = [&](int x, int y) { return t.radiance[static_cast<std::size_t>(y * kSize + x)].y > 1e-3f * peak; };
    const int margin = 2;
    int litCount = 0, shadowCount = 0;
    for (int y = margin; y < kSize - margin; ++y)
        for (int x = margin; x < kSize - margin; ++x) {
            bool uniform = true;
            for (int dy = -margin; dy <= margin && uniform; ++dy)
                for (int dx = -margin; dx <= margin && uniform; ++dx) uniform = lit(x + dx, y + dy) == lit(x, y);
            if (!uniform || !t.hit[static_cast<std::size_t>(y * kSize + x)]) continue;
            const glm::vec3 got = r.snapshot.at(x, y), want = t.radiance[static_cast<std::size_t>(y * kSize + x)];
            if (lit(x, y)) {
                ++litCount;
                for (int c = 0; c < 3; ++c) ASSERT_NEAR(got[c], want[c], 0.02f * want[c]) << "lit pixel " << x << "," << y;
            } else {
                ++shadowCount;
                ASSERT_LT(got.y, 1e-3f * peak) << "shadowed pixel " << x << "," << y;
            }
        }
    EXPECT_GT(litCount, kSize * kSize / 4);
    EXPECT_GT(shadowCount, kSize * kSize / 50);
}

INSTANTIATE_TEST_SUITE_P(Sky, SnapshotSun, ::testing::Values(Sun::MapCell, Sun::DirectionalLight),
                         [](const auto& info) { return info.param == Sun::MapCell ? "MapCell" : "DirectionalLight"; });

}  // namespace
}  // namespace aamap::test
