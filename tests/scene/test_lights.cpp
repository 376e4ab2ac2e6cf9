#include <cmath>
#include <set>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include <fstream>

#include "core/error.h"
#include "core/image_io.h"
#include "scene/builtin_scenes.h"
#include "scene/gltf_loader.h"
#include "tests/common/temp_dir.h"
#include "scene/light_file.h"
#include "scene/lights.h"

namespace aamap {
namespace {

TEST(ApproximateAreaLight, IntensitiesSumToRadianceTimesAreaAndPointsLieOnTheLight) {
    const Scene s = builtinScene("cornell");
    const AreaLight& light = s.areaLights.at(0);
    for (int k : {1, 2, 5, 16, 100}) {
        const auto points = approximateAreaLight(s, light, k);
        ASSERT_EQ(points.size(), static_cast<std::size_t>(k));
        glm::vec3 sum(0.0f);
        std::set<std::tuple<float, float, float>> distinct;
        for (const PointLight& p : points) {
            sum += p.intensity;
            EXPECT_NEAR(p.position.y, 0.5483f, 1e-6f);
            EXPECT_GE(p.position.x, 0.213f - 1e-6f);
            EXPECT_LE(p.position.x, 0.343f + 1e-6f);
            EXPECT_GE(p.position.z, 0.227f - 1e-6f);
            EXPECT_LE(p.position.z, 0.332f + 1e-6f);
            EXPECT_NEAR(p.normal.y, -1.0f, 1e-6f);
            distinct.insert({p.position.x, p.position.y, p.position.z});
        }
        EXPECT_EQ(distinct.size(), points.size()) << "k=" << k;
        const glm::vec3 expected = light.radiance * light.area;
        EXPECT_NEAR(sum.x, expected.x, 1e-4f * expected.x);
        EXPECT_NEAR(sum.z, expected.z, 1e-4f * expected.z);
    }
}

TEST(ApproximateAreaLight, DeterministicAndSpreadOverBothTriangles) {
    const Scene s = builtinScene("cornell");
    const auto a = approximateAreaLight(s, s.areaLights[0], 5);
    const auto b = approximateAreaLight(s, s.areaLights[0], 5);
    ASSERT_EQ(a.size(), b.size());
    for (std::size_t i = 0; i < a.size(); ++i) EXPECT_EQ(a[i].position, b[i].position);
    // The mean of 5 points should be near the light's centre, not bunched in one corner.
    glm::vec3 mean(0.0f);
    for (const auto& p : a) mean += p.position / 5.0f;
    EXPECT_NEAR(mean.x, 0.278f, 0.02f);
    EXPECT_NEAR(mean.z, 0.2795f, 0.02f);
    EXPECT_THROW(approximateAreaLight(s, s.areaLights[0], 0), std::invalid_argument);
}

TEST(BuildAreaLights, GroupsByObjectAndMaterialAndSkipsZeroArea) {
    Scene s;
    s.materials = {{.name = "wall"}, {.name = "lamp", .ke = glm::vec3(2.0f)}};
    s.mesh.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {2, 0, 0}};
    s.mesh.normals.assign(4, {0, 0, 1});
    s.mesh.triangles = {{0, 1, 2}, {0, 1, 2}, {0, 1, 2}, {0, 1, 3}};  // the last has zero area
    s.mesh.materialIds = {1, 0, 1, 1};
    s.mesh.objectIds = {0, 0, 1, 1};
    const std::vector<std::string> names = {"first"};
    const auto lights = buildAreaLights(s, names);
    ASSERT_EQ(lights.size(), 2u);
    EXPECT_EQ(lights[0].name, "first/lamp");
    EXPECT_EQ(lights[1].name, "object1/lamp");
    EXPECT_FLOAT_EQ(lights[0].area, 0.5f);
    EXPECT_EQ(lights[1].triangles, std::vector<std::uint32_t>{2});
    EXPECT_EQ(lights[0].radiance, glm::vec3(2.0f));
}

TEST(SceneBounds, EmptyAndSimple) {
    Scene s;
    const Bounds empty = sceneBounds(s);
    EXPECT_EQ(empty.lo, glm::vec3(0.0f));
    s.mesh.positions = {{1, -2, 3}, {-1, 5, 0}};
    const Bounds b = sceneBounds(s);
    EXPECT_EQ(b.lo, glm::vec3(-1, -2, 0));
    EXPECT_EQ(b.hi, glm::vec3(1, 5, 3));
    EXPECT_EQ(b.centre(), glm::vec3(0, 1.5f, 1.5f));
}

// ---- Lights from a light file (scene/light_file.h): quads and disks become emissive geometry ----

constexpr double kPi = 3.14159265358979323846;

// The emitted power of an area light, pi L A, with A summed over its actual triangles (double).
glm::dvec3 emittedPower(const Scene& s, const AreaLight& light, double* area = nullptr) {
    double a = 0.0;
    for (std::uint32_t t : light.triangles) {
        const glm::uvec3 tri = s.mesh.triangles[t];
        const glm::dvec3 p0(s.mesh.positions[tri.x]), p1(s.mesh.positions[tri.y]), p2(s.mesh.positions[tri.z]);
        a += 0.5 * glm::length(glm::cross(p1 - p0, p2 - p0));
    }
    if (area) *area = a;
    return kPi * a * glm::dvec3(light.radiance);
}

LightSpec quadSpec() {
    LightSpec q;
    q.type = LightType::Quad;
    q.name = "panel";
    q.position = {1, 2, 3};
    q.normal = {0, -2, 0};
    q.up = {0, 0, 1};
    q.size = {0.5, 0.25};
    q.unit = EmissionUnit::Power;
    q.emission = {100, 50, 25};
    return q;
}

TEST(LightFileLights, QuadBecomesAnAreaLightWithTheGivenPowerFacingItsNormal) {
    Scene s = builtinScene("cornell");
    const std::size_t trianglesBefore = s.mesh.triangles.size(), areasBefore = s.areaLights.size();
    const LightSpec q = quadSpec();
    addLights(s, std::span(&q, 1));
    ASSERT_EQ(s.areaLights.size(), areasBefore + 1);
    ASSERT_EQ(s.mesh.triangles.size(), trianglesBefore + 2);
    ASSERT_EQ(s.mesh.normals.size(), s.mesh.positions.size());
    ASSERT_EQ(s.mesh.materialIds.size(), s.mesh.triangles.size());
    ASSERT_EQ(s.mesh.objectIds.size(), s.mesh.triangles.size());
    const AreaLight& light = s.areaLights.back();
    EXPECT_EQ(light.name, "panel");
    double area = 0.0;
    const glm::dvec3 power = emittedPower(s, light, &area);
    EXPECT_NEAR(area, 0.125, 1e-7);
    EXPECT_NEAR(light.area, 0.125f, 1e-6f);
    EXPECT_NEAR(power.x, 100.0, 1e-4);
    EXPECT_NEAR(power.y, 50.0, 1e-4);
    EXPECT_NEAR(power.z, 25.0, 1e-4);
    for (std::uint32_t t : light.triangles) {
        EXPECT_NEAR(triangleNormal(s.mesh, t).y, -1.0f, 1e-6f);  // front (winding) faces the normal
        EXPECT_EQ(s.materials[s.mesh.materialIds[t]].ke, light.radiance);
        for (int k = 0; k < 3; ++k) {
            const glm::vec3 p = s.mesh.positions[s.mesh.triangles[t][k]];
            EXPECT_NEAR(std::abs(p.x - 1.0f), 0.25f, 1e-6f);    // the size[0] side runs across up
            EXPECT_NEAR(std::abs(p.z - 3.0f), 0.125f, 1e-6f);   // size[1] along up
            EXPECT_EQ(p.y, 2.0f);
        }
    }
    // The Snapshot's k-point approximation sums to the light's on-axis intensity L A.
    glm::vec3 sum(0.0f);
    for (const PointLight& p : approximateAreaLight(s, light, 5)) sum += p.intensity;
    EXPECT_NEAR(sum.x, 100.0f / kPi, 1e-3f);
}

TEST(LightFileLights, DiskPowerIsExactForAnyTessellation) {
    for (int segments : {3, 4, 7, 32, 500}) {
        Scene s;
        LightSpec d;
        d.type = LightType::Disk;
        d.name = "disk";
        d.position = {0.5, 3, -1};
        d.normal = {1, 1, 0};
        d.radius = 0.4;
        d.segments = segments;
        d.unit = EmissionUnit::Power;
        d.emission = {60, 30, 15};
        addLights(s, std::span(&d, 1));
        ASSERT_EQ(s.areaLights.size(), 1u);
        const AreaLight& light = s.areaLights[0];
        ASSERT_EQ(light.triangles.size(), static_cast<std::size_t>(segments));
        double area = 0.0;
        const glm::dvec3 power = emittedPower(s, light, &area);
        EXPECT_NEAR(area, kPi * 0.16, 1e-6 * kPi * 0.16) << segments;
        EXPECT_NEAR(power.x, 60.0, 1e-5 * 60.0) << segments;
        EXPECT_NEAR(power.z, 15.0, 1e-5 * 15.0) << segments;
        const glm::vec3 n = glm::normalize(glm::vec3(1, 1, 0));
        for (std::uint32_t t : light.triangles) {
            EXPECT_NEAR(glm::dot(triangleNormal(s.mesh, t), n), 1.0f, 1e-5f) << segments;
            for (int k = 0; k < 3; ++k) {  // in the disk's plane, within the rim radius
                const glm::vec3 p = s.mesh.positions[s.mesh.triangles[t][k]] - glm::vec3(0.5f, 3.0f, -1.0f);
                EXPECT_NEAR(glm::dot(p, n), 0.0f, 1e-5f);
                EXPECT_LE(glm::length(p), diskRimRadius(0.4, segments) * (1 + 1e-5));
            }
        }
    }
    // The rim approaches the radius as the fan gets finer.
    EXPECT_NEAR(diskRimRadius(1.0, 4096), 1.0, 1e-6);
    EXPECT_GT(diskRimRadius(1.0, 8), 1.0);
}

TEST(LightFileLights, RadianceIsKeptAsGivenAndPointsAndSpotsGetIntensity) {
    Scene s;
    std::vector<LightSpec> specs(4);
    specs[0] = quadSpec();
    specs[0].unit = EmissionUnit::Radiance;
    specs[0].emission = {2, 3, 4};
    specs[1].type = LightType::Point;
    specs[1].name = "bulb";
    specs[1].unit = EmissionUnit::Power;
    specs[1].emission = {4 * kPi, 8 * kPi, 0};
    specs[2].type = LightType::Spot;
    specs[2].name = "spot";
    specs[2].direction = {0, 0, -3};
    specs[2].innerAngle = 10;
    specs[2].outerAngle = 30;
    specs[2].unit = EmissionUnit::Power;
    specs[2].emission = {1, 1, 1};
    specs[3].type = LightType::Point;
    specs[3].normal = {0, 0, 2};
    specs[3].emission = {5, 5, 5};
    addLights(s, specs);
    ASSERT_EQ(s.areaLights.size(), 1u);
    EXPECT_EQ(s.areaLights[0].radiance, glm::vec3(2, 3, 4));
    ASSERT_EQ(s.pointLights.size(), 3u);
    EXPECT_NEAR(s.pointLights[0].intensity.x, 1.0f, 1e-6f);  // 4 pi I = power
    EXPECT_NEAR(s.pointLights[0].intensity.y, 2.0f, 1e-6f);
    const PointLight& spot = s.pointLights[1];
    EXPECT_EQ(spot.spotDirection, glm::vec3(0, 0, -1));
    EXPECT_NEAR(spot.cosInner, std::cos(10.0 * kPi / 180.0), 1e-7);
    EXPECT_NEAR(spot.cosOuter, std::cos(30.0 * kPi / 180.0), 1e-7);
    EXPECT_NEAR(spot.intensity.x * emittingSolidAngle(spot), 1.0, 1e-6);
    EXPECT_EQ(s.pointLights[2].normal, glm::vec3(0, 0, 1));
    EXPECT_EQ(emissionFactor(s.pointLights[2], {0, 0, 1}), 1.0f);
    EXPECT_EQ(emissionFactor(s.pointLights[2], {0, 0, -1}), 0.0f);
    EXPECT_EQ(emissionFactor(spot, {0, 0, -1}), 1.0f);
    EXPECT_EQ(emissionFactor(spot, {1, 0, 0}), 0.0f);

    LightSpec bad = quadSpec();
    bad.normal = {0, 0, 0};
    EXPECT_THROW(addLights(s, std::span(&bad, 1)), std::invalid_argument);
}

// The lights at infinity from a light file: a DirectionalLight with a unit direction, and the
// environment: constant (the radiance is the scale, no map) or an EXR map with its scale and
// orientation; a second environment is refused.
TEST(LightFileLights, DirectionalAndEnvironmentBecomeTheScenesLightsAtInfinity) {
    test::TempDir dir;
    ImageRGB map(4, 2, glm::vec3(0.5f));
    map.at(3, 1) = glm::vec3(8.0f, 4.0f, 2.0f);
    writeExr(dir.path() / "sky.exr", map);

    std::vector<LightSpec> specs(2);
    specs[0].type = LightType::Directional;
    specs[0].name = "sun";
    specs[0].direction = {0, -2, 0};
    specs[0].unit = EmissionUnit::Irradiance;
    specs[0].emission = {3, 2, 1};
    specs[1].type = LightType::Environment;
    specs[1].name = "sky";
    specs[1].map = (dir.path() / "sky.exr").string();
    specs[1].scale = 2.0;
    specs[1].rotation = 90.0;
    Scene s;
    addLights(s, specs);
    ASSERT_EQ(s.directionalLights.size(), 1u);
    EXPECT_EQ(s.directionalLights[0].direction, glm::vec3(0, -1, 0));
    EXPECT_EQ(s.directionalLights[0].irradiance, glm::vec3(3, 2, 1));
    ASSERT_TRUE(s.environment.has_value());
    const EnvironmentLight& env = *s.environment;
    EXPECT_EQ(env.name, "sky");
    EXPECT_EQ(env.scale, glm::vec3(2.0f));
    ASSERT_EQ(env.mapWidth, 4);
    ASSERT_EQ(env.mapHeight, 2);
    EXPECT_EQ(env.map[7], glm::vec3(8.0f, 4.0f, 2.0f));
    EXPECT_EQ(env.map[0], glm::vec3(0.5f));
    // 90 degrees about +Y (right-handed): world -Z is the map's +X.
    const glm::vec3 local = env.toLocal * glm::vec3(0, 0, -1);
    EXPECT_NEAR(glm::length(local - glm::vec3(1, 0, 0)), 0.0f, 1e-6f);

    // A second environment, and a map that is not an image.
    LightSpec constant;
    constant.type = LightType::Environment;
    constant.name = "grey";
    constant.unit = EmissionUnit::Radiance;
    constant.emission = {0.2, 0.2, 0.2};
    EXPECT_THROW(addLights(s, std::span<const LightSpec>(&constant, 1)), std::invalid_argument);
    Scene fresh;
    addLights(fresh, std::span<const LightSpec>(&constant, 1));
    ASSERT_TRUE(fresh.environment.has_value());
    EXPECT_EQ(fresh.environment->scale, glm::vec3(0.2f));
    EXPECT_TRUE(fresh.environment->map.empty());
    LightSpec broken = specs[1];
    std::ofstream(dir.path() / "broken.exr") << "not an EXR";
    broken.map = (dir.path() / "broken.exr").string();
    Scene other;
    EXPECT_THROW(addLights(other, std::span<const LightSpec>(&broken, 1)), InputError);
    EXPECT_FALSE(other.environment.has_value());  // nothing half-added
}

TEST(GltfSpotLight, KeepsItsConeAlongTheNodesMinusZ) {
    const test::TempDir dir;
    // The node turns -Z to -Y (a quarter turn about x) and sits at (1, 2, 3).
    const auto file = dir.write("spot.gltf", R"({
  "asset": {"version": "2.0"},
  "extensionsUsed": ["KHR_lights_punctual"],
  "extensions": {"KHR_lights_punctual": {"lights": [
    {"type": "spot", "name": "stage", "color": [1, 0.5, 0.25], "intensity": 8,
     "spot": {"innerConeAngle": 0.2, "outerConeAngle": 0.6}}]}},
  "scene": 0, "scenes": [{"nodes": [0]}],
  "nodes": [{"translation": [1, 2, 3], "rotation": [-0.70710678, 0, 0, 0.70710678],
             "extensions": {"KHR_lights_punctual": {"light": 0}}}]
})");
    const Scene s = loadGltf(file);
    ASSERT_EQ(s.pointLights.size(), 1u);
    const PointLight& p = s.pointLights[0];
    EXPECT_EQ(p.name, "stage");
    EXPECT_NEAR(glm::length(p.position - glm::vec3(1, 2, 3)), 0.0f, 1e-6f);
    EXPECT_NEAR(p.intensity.y, 4.0f, 1e-6f);
    EXPECT_NEAR(p.spotDirection.y, -1.0f, 1e-6f);
    EXPECT_NEAR(p.cosInner, std::cos(0.2f), 1e-7f);
    EXPECT_NEAR(p.cosOuter, std::cos(0.6f), 1e-7f);
    EXPECT_EQ(p.normal, glm::vec3(0.0f));
    EXPECT_EQ(emissionFactor(p, {0, -1, 0}), 1.0f);
    EXPECT_EQ(emissionFactor(p, glm::normalize(glm::vec3(1, -1, 0))), 0.0f);  // 45 degrees > 0.6 rad
}

// The log's phrase counts every kind of light, and a scene with none of any kind is a warning.
TEST(DescribeLights, CountsEveryKindAndWarnsOnlyWithoutAny) {
    Scene scene;
    scene.name = "empty";
    EXPECT_EQ(describeLights(scene), "no lights");
    ASSERT_TRUE(unlitSceneWarning(scene).has_value());
    EXPECT_NE(unlitSceneWarning(scene)->find("'empty' has no lights"), std::string::npos);
    scene.directionalLights.emplace_back();
    EXPECT_EQ(describeLights(scene), "1 directional light");
    EXPECT_FALSE(unlitSceneWarning(scene).has_value());
    scene.pointLights.resize(2);
    EXPECT_EQ(describeLights(scene), "2 point and 1 directional lights");
    scene.environment.emplace();
    EXPECT_EQ(describeLights(scene), "2 point and 1 directional lights and an environment map");
    Scene sky;
    sky.environment.emplace();
    EXPECT_EQ(describeLights(sky), "an environment map");
    EXPECT_FALSE(unlitSceneWarning(sky).has_value());
}

}  // namespace
}  // namespace aamap
