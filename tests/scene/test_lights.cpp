#include <set>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include "scene/builtin_scenes.h"
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

}  // namespace
}  // namespace aamap
