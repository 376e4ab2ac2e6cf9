// Every pair of Snapshot features in one small procedural scene, under the validation layer:
// planar and curved mirrors, glass, an environment map, soft shadows of an area light, textures,
// a directional light and a spot light. Each pair must compile into one render graph (the two
// mirror composites both update the snapshot: versioned resources), keep the passes each feature
// needs, and give a finite snapshot and an aamap in [0, 1].
#include <cmath>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <glm/geometric.hpp>

#include "gpu_fixture.h"
#include "passes/mirror_probes.h"
#include "passes/snapshot.h"
#include "passes/snapshot_graph.h"
#include "scene/lights.h"
#include "tests/common/test_scenes.h"

namespace aamap::test {
namespace {

enum class Feature { PlanarMirror, CurvedMirror, Glass, EnvironmentMap, SoftShadows, Textures, Directional, Spot };
constexpr Feature kFeatures[] = {Feature::PlanarMirror, Feature::CurvedMirror, Feature::Glass,
                                 Feature::EnvironmentMap, Feature::SoftShadows, Feature::Textures,
                                 Feature::Directional,  Feature::Spot};

const char* name(Feature f) {
    switch (f) {
        case Feature::PlanarMirror: return "PlanarMirror";
        case Feature::CurvedMirror: return "CurvedMirror";
        case Feature::Glass: return "Glass";
        case Feature::EnvironmentMap: return "EnvironmentMap";
        case Feature::SoftShadows: return "SoftShadows";
        case Feature::Textures: return "Textures";
        case Feature::Directional: return "Directional";
        case Feature::Spot: return "Spot";
    }
    return "?";
}

std::uint32_t addMaterial(Scene& s, Material m) {
    s.materials.push_back(std::move(m));
    return static_cast<std::uint32_t>(s.materials.size() - 1);
}

Material material(const char* n, MaterialKind kind, glm::vec3 kd, glm::vec3 ks = glm::vec3(0.0f)) {
    Material m;
    m.name = n;
    m.kind = kind;
    m.kd = kd;
    m.ks = ks;
    return m;
}

// The floor z = 0 under a camera looking down -z, lit by a point light; then each feature adds
// what it needs, in view.
Scene sceneWith(Feature a, Feature b) {
    auto has = [&](Feature f) { return a == f || b == f; };
    Scene s;
    s.name = fmt::format("{}+{}", name(a), name(b));
    Material floor = material("floor", MaterialKind::Diffuse, glm::vec3(0.7f));
    if (has(Feature::Textures)) {
        Texture checker;
        checker.width = checker.height = 8;
        for (int i = 0; i < 64; ++i) {
            const float v = ((i % 8) + (i / 8)) % 2 ? 1.0f : 0.1f;
            checker.rgba.insert(checker.rgba.end(), {v, v, v, 1.0f});
        }
        s.textures.push_back(std::move(checker));
        floor.diffuseTexture = 0;
    }
    addQuadZ(s, 0.0f, -2.0f, 2.0f, -2.0f, 2.0f, addMaterial(s, floor));
    // A box-like blocker so that every light casts a shadow edge on the floor.
    addQuadZ(s, 0.6f, -0.3f, 0.3f, -0.3f, 0.3f, addMaterial(s, material("blocker", MaterialKind::Diffuse, {0.8f, 0.3f, 0.2f})));
    PointLight bulb;
    bulb.name = "bulb";
    bulb.position = {0.4f, 0.5f, 3.0f};
    bulb.intensity = glm::vec3(6.0f);
    s.pointLights.push_back(bulb);

    if (has(Feature::PlanarMirror))
        addQuadZ(s, 0.3f, -1.8f, -0.6f, 0.6f, 1.8f,
                 addMaterial(s, material("plane-mirror", MaterialKind::Mirror, glm::vec3(0.0f), glm::vec3(0.8f))));
    if (has(Feature::CurvedMirror)) {
        const std::uint32_t m = addMaterial(s, material("ball", MaterialKind::Mirror, glm::vec3(0.0f), glm::vec3(0.9f)));
        addSphere(s, {1.0f, -1.0f, 0.5f}, 0.5f, 16, 8, m, m);
    }
    if (has(Feature::Glass))
        addQuadZ(s, 1.0f, -1.2f, -0.2f, -1.6f, -0.6f,
                 addMaterial(s, material("pane", MaterialKind::Glass, glm::vec3(0.0f), glm::vec3(1.0f))));
    if (has(Feature::SoftShadows)) {
        // A lamp above the scene, facing down (its quad wound towards -z).
        const std::uint32_t m = addMaterial(s, [] {
            Material lamp = material("lamp", MaterialKind::Diffuse, glm::vec3(0.0f));
            lamp.ke = glm::vec3(4.0f);
            return lamp;
        }());
        const auto base = static_cast<std::uint32_t>(s.mesh.positions.size());
        s.mesh.positions.insert(s.mesh.positions.end(), {{-0.5f, -0.5f, 2.5f}, {0.5f, -0.5f, 2.5f}, {0.5f, 0.5f, 2.5f}, {-0.5f, 0.5f, 2.5f}});
        s.mesh.normals.insert(s.mesh.normals.end(), 4, glm::vec3(0, 0, -1));
        s.mesh.triangles.insert(s.mesh.triangles.end(), {{base, base + 2, base + 1}, {base, base + 3, base + 2}});
        s.mesh.materialIds.insert(s.mesh.materialIds.end(), 2, m);
        s.mesh.objectIds.insert(s.mesh.objectIds.end(), 2, m);
        s.areaLights = buildAreaLights(s);
    }
    if (has(Feature::EnvironmentMap)) {
        EnvironmentLight env;
        env.name = "sky";
        env.mapWidth = 16;
        env.mapHeight = 8;
        env.map.assign(16 * 8, glm::vec3(0.2f, 0.3f, 0.5f));
        env.map[2 * 16 + 5] = glm::vec3(400.0f);  // a sun: extracted as a shadowed light
        s.environment = env;
    }
    if (has(Feature::Directional)) {
        DirectionalLight sun;
        sun.name = "sun";
        sun.direction = glm::normalize(glm::vec3(0.3f, 0.2f, -1.0f));
        sun.irradiance = glm::vec3(2.0f);
        s.directionalLights.push_back(sun);
    }
    if (has(Feature::Spot)) {
        PointLight spot;
        spot.name = "spot";
        spot.position = {-0.5f, -0.5f, 2.0f};
        spot.intensity = glm::vec3(8.0f);
        spot.spotDirection = {0, 0, -1};
        spot.cosInner = std::cos(0.3f);
        spot.cosOuter = std::cos(0.5f);
        s.pointLights.push_back(spot);
    }
    // Texture coordinates for every vertex once a texture is there (the mesh has all or none).
    if (has(Feature::Textures))
        for (const glm::vec3& p : s.mesh.positions) s.mesh.uvs.push_back(0.5f * glm::vec2(p.x + 2.0f, p.y + 2.0f));
    return s;
}

bool kept(const SnapshotResult& r, const std::string& pass) {
    for (const PassTiming& t : r.passTimes)
        if (t.pass == pass) return true;
    return false;
}

class SnapshotFeaturePairs : public GpuTest {};

TEST_F(SnapshotFeaturePairs, EveryPairComposesInOneGraph) {
    constexpr int kSize = 48;
    const View view = viewDownZ({0.05f, -0.1f, 4.0f}, 60.0f);
    int pairs = 0;
    for (std::size_t i = 0; i < std::size(kFeatures); ++i)
        for (std::size_t j = i + 1; j < std::size(kFeatures); ++j) {
            const Feature a = kFeatures[i], b = kFeatures[j];
            auto has = [&](Feature f) { return a == f || b == f; };
            const Scene scene = sceneWith(a, b);
            SCOPED_TRACE(scene.name);
            SnapshotRenderer renderer(context(), scene);
            SnapshotSettings settings;
            settings.scale = 1.0f;
            settings.areaLightSolidAngle = 0.0f;  // every area light gets areaLightSamples
            SnapshotResult r;
            ASSERT_NO_THROW(r = renderer.render(view, kSize, kSize, settings));
            ++pairs;

            // The passes each feature needs are kept, together.
            EXPECT_EQ(kept(r, passes::kMirrorCompositePass), has(Feature::PlanarMirror)) << r.explain;
            EXPECT_EQ(kept(r, passes::kMirrorProbeCompositePass), has(Feature::CurvedMirror)) << r.explain;
            // The grey comes from a luminance pass exactly when something changes the snapshot
            // after the opaque draw (a composite, glass blended over it).
            EXPECT_EQ(kept(r, passes::kLuminancePass),
                      has(Feature::PlanarMirror) || has(Feature::CurvedMirror) || has(Feature::Glass))
                << r.explain;
            EXPECT_TRUE(kept(r, passes::kShadowPass));
            // One shadow map per light sample: the bulb, 5 lamp samples, the sky's sun, the
            // directional light and the spot.
            const int lights = 1 + (has(Feature::SoftShadows) ? settings.areaLightSamples : 0) +
                               (has(Feature::EnvironmentMap) ? settings.environmentLights : 0) +
                               (has(Feature::Directional) ? 1 : 0) + (has(Feature::Spot) ? 1 : 0);
            EXPECT_EQ(r.shadowCubeMaps, lights) << r.explain;
            if (has(Feature::Glass)) {
                EXPECT_NE(r.explain.find("glass triangles"), std::string::npos) << r.explain;
                // --explain says why the luminance pass is there: glass too, not only a mirror.
                EXPECT_NE(r.explain.find("a mirror composite or glass"), std::string::npos) << r.explain;
            }

            ASSERT_EQ(r.snapshot.width(), kSize);
            ASSERT_EQ(r.aamap.width(), kSize);
            float brightest = 0.0f;
            for (int y = 0; y < kSize; ++y)
                for (int x = 0; x < kSize; ++x) {
                    const glm::vec3 c = r.snapshot.at(x, y);
                    for (int k = 0; k < 3; ++k) ASSERT_TRUE(std::isfinite(c[k]) && c[k] >= 0.0f) << x << "," << y;
                    brightest = std::max(brightest, c.y);
                    const float m = r.aamap.at(x, y);
                    ASSERT_TRUE(m >= 0.0f && m <= 1.0f) << x << "," << y << ": " << m;
                }
            EXPECT_GT(brightest, 0.0f);
        }
    EXPECT_EQ(pairs, 28);
}

// Under a constant sky, each mirror in the two-mirror scene shows what it shows alone: the planar
// composite's pixels are the sky times the reflectance, exactly as without the curved mirror, and
// the probe composite lights the sphere as without the planar one (the composites touch disjoint
// pixels; each reads the version the other left).
TEST_F(SnapshotFeaturePairs, BothMirrorCompositesShowInTheSnapshot) {
    constexpr int kSize = 48;
    const glm::vec3 eye(0.05f, -0.1f, 4.0f);
    const View view = viewDownZ(eye, 60.0f);
    SnapshotSettings settings;
    settings.scale = 1.0f;
    const glm::vec3 sky(0.5f, 0.6f, 0.7f);
    auto underSky = [&](Scene s) {
        EnvironmentLight env;
        env.name = "sky";
        env.scale = sky;
        s.environment = env;
        return s;
    };
    // Pixels whose view ray crosses the plane z inside [x0, x1] x [y0, y1] and pass `test`.
    auto count = [&](const SnapshotResult& r, float z, float x0, float x1, float y0, float y1, auto test) {
        const float half = (eye.z - z) * std::tan(glm::radians(30.0f));
        int n = 0;
        for (int y = 0; y < kSize; ++y)
            for (int x = 0; x < kSize; ++x) {
                const float wx = eye.x + ((x + 0.5f) / kSize * 2.0f - 1.0f) * half;
                const float wy = eye.y + (1.0f - (y + 0.5f) / kSize * 2.0f) * half;
                if (wx > x0 && wx < x1 && wy > y0 && wy < y1 && test(r.snapshot.at(x, y))) ++n;
            }
        return n;
    };
    const glm::vec3 reflectedSky = 0.8f * sky;
    auto isReflectedSky = [&](glm::vec3 c) { return glm::length(c - reflectedSky) < 1e-3f; };
    auto isLit = [](glm::vec3 c) { return c.y > 1e-3f; };

    SnapshotRenderer both(context(), underSky(sceneWith(Feature::PlanarMirror, Feature::CurvedMirror)));
    SnapshotRenderer planar(context(), underSky(sceneWith(Feature::PlanarMirror, Feature::Textures)));
    SnapshotRenderer curved(context(), underSky(sceneWith(Feature::CurvedMirror, Feature::Textures)));
    const SnapshotResult rb = both.render(view, kSize, kSize, settings);
    const SnapshotResult rp = planar.render(view, kSize, kSize, settings);
    const SnapshotResult rc = curved.render(view, kSize, kSize, settings);

    const int planarBoth = count(rb, 0.3f, -1.6f, -0.8f, 0.8f, 1.6f, isReflectedSky);
    EXPECT_GT(planarBoth, 20);
    EXPECT_EQ(planarBoth, count(rp, 0.3f, -1.6f, -0.8f, 0.8f, 1.6f, isReflectedSky));
    const int curvedBoth = count(rb, 1.0f, 0.8f, 1.2f, -1.2f, -0.8f, isLit);
    const int curvedAlone = count(rc, 1.0f, 0.8f, 1.2f, -1.2f, -0.8f, isLit);
    EXPECT_GT(curvedAlone, 4);
    EXPECT_EQ(curvedBoth, curvedAlone);
    EXPECT_NE(rb.dot.find(" v2"), std::string::npos) << "the snapshot's two composites make versions 1 and 2";
}

}  // namespace
}  // namespace aamap::test
