#include <cmath>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include "core/error.h"
#include "scene/builtin_scenes.h"
#include "scene/camera.h"
#include "scene/lights.h"

namespace aamap {
namespace {

glm::vec3 centroid(const TriangleMesh& m, std::uint32_t t) {
    const glm::uvec3 i = m.triangles[t];
    return (m.positions[i.x] + m.positions[i.y] + m.positions[i.z]) / 3.0f;
}

// Every vertex normal agrees with its triangle's winding.
void expectConsistentWinding(const Scene& s) {
    const TriangleMesh& m = s.mesh;
    ASSERT_EQ(m.normals.size(), m.positions.size());
    ASSERT_EQ(m.materialIds.size(), m.triangles.size());
    ASSERT_EQ(m.objectIds.size(), m.triangles.size());
    for (std::uint32_t t = 0; t < m.triangles.size(); ++t) {
        const glm::vec3 g = triangleNormal(m, t);
        ASSERT_GT(glm::length(g), 0.5f) << "degenerate triangle " << t;
        for (int k = 0; k < 3; ++k) {
            EXPECT_NEAR(glm::length(m.normals[m.triangles[t][k]]), 1.0f, 1e-5f);
            EXPECT_GT(glm::dot(g, m.normals[m.triangles[t][k]]), 0.5f) << "triangle " << t;
        }
    }
}

TEST(Cornell, GeometryAndMaterials) {
    const Scene s = builtinScene("cornell");
    EXPECT_EQ(s.name, "cornell");
    EXPECT_EQ(s.mesh.triangles.size(), 32u);  // 5 walls, 2 x 5 block faces, the light: 16 quads
    expectConsistentWinding(s);
    for (std::uint32_t id : s.mesh.materialIds) {
        ASSERT_LT(id, s.materials.size());
        EXPECT_EQ(s.materials[id].kind, MaterialKind::Diffuse);
    }
    const Bounds b = sceneBounds(s);
    EXPECT_NEAR(b.lo.x, 0.0f, 1e-6f);
    EXPECT_NEAR(b.hi.x, 0.556f, 1e-6f);
    EXPECT_NEAR(b.hi.y, 0.5488f, 1e-6f);
    EXPECT_NEAR(b.hi.z, 0.5592f, 1e-6f);
}

TEST(Cornell, NormalsFaceTheVisibleInterior) {
    const Scene s = builtinScene("cornell");
    const glm::vec3 room(0.278f, 0.2744f, 0.2796f);
    const glm::vec3 shortCentre(0.1855f, 0.0825f, 0.1685f), tallCentre(0.3685f, 0.165f, 0.3515f);
    for (std::uint32_t t = 0; t < s.mesh.triangles.size(); ++t) {
        const glm::vec3 n = triangleNormal(s.mesh, t), c = centroid(s.mesh, t);
        switch (s.mesh.objectIds[t]) {
            case 5: EXPECT_GT(glm::dot(n, c - shortCentre), 0.0f) << t; break;
            case 6: EXPECT_GT(glm::dot(n, c - tallCentre), 0.0f) << t; break;
            case 7: EXPECT_LT(n.y, -0.999f); break;  // the light faces down
            default: EXPECT_GT(glm::dot(n, room - c), 0.0f) << t;
        }
    }
    // The back wall faces the camera.
    const glm::vec3 eye = s.views.at(0).position;
    for (std::uint32_t t = 0; t < s.mesh.triangles.size(); ++t) {
        if (s.mesh.objectIds[t] == 2) {
            EXPECT_GT(glm::dot(triangleNormal(s.mesh, t), eye - centroid(s.mesh, t)), 0.0f);
        }
    }
}

TEST(Cornell, LightAndDefaultView) {
    const Scene s = builtinScene("cornell");
    ASSERT_EQ(s.areaLights.size(), 1u);
    const AreaLight& light = s.areaLights[0];
    EXPECT_EQ(light.name, "light");
    EXPECT_EQ(light.triangles.size(), 2u);
    EXPECT_NEAR(light.area, 0.130f * 0.105f, 1e-7f);
    EXPECT_GT(light.radiance.x, 0.0f);

    ASSERT_EQ(s.views.size(), 1u);
    const View& v = s.views[0];
    EXPECT_NEAR(v.horizontalFovDeg, 39.3076f, 1e-3f);
    EXPECT_NEAR(v.verticalFovDeg, 39.3076f, 1e-3f);
    EXPECT_NEAR(v.position.x, 0.278f, 1e-6f);
    EXPECT_NEAR(v.position.z, -0.8f, 1e-6f);
    // The red wall (x ~ 0.55) is on the left of the image.
    const PinholeCamera cam = PinholeCamera::fromView(v);
    EXPECT_GT(glm::dot(cam.right, glm::vec3(-1, 0, 0)), 0.999f);
}

TEST(Cornell, FloorUnderTheLightHasRadianceAboutPointSix) {
    const Scene s = builtinScene("cornell");
    const AreaLight& light = s.areaLights[0];
    const glm::vec3 p(0.278f, 0.0f, 0.2795f), n(0, 1, 0);
    const float kd = s.materials[0].kd.x;
    glm::vec3 e(0.0f);
    for (const PointLight& pl : approximateAreaLight(s, light, 4096)) {
        const glm::vec3 d = pl.position - p;
        const float r2 = glm::dot(d, d);
        const glm::vec3 w = d / std::sqrt(r2);
        e += pl.intensity * std::max(0.0f, glm::dot(pl.normal, -w)) * std::max(0.0f, glm::dot(n, w)) / r2;
    }
    const glm::vec3 radiance = kd / 3.14159265f * e;
    EXPECT_NEAR(radiance.x, 0.6f, 0.01f);
    EXPECT_NEAR(radiance.y, 0.6f, 0.01f);
}

TEST(SpheresPlane, SpheresFaceOutwardAndLightExists) {
    const Scene s = builtinScene("spheres-plane");
    expectConsistentWinding(s);
    ASSERT_EQ(s.areaLights.size(), 1u);
    EXPECT_NEAR(s.areaLights[0].area, 1.0f, 1e-5f);
    ASSERT_EQ(s.views.size(), 1u);
    const glm::vec3 centres[] = {{-1.2f, 0.5f, 0.0f}, {0.0f, 0.5f, -0.3f}, {1.2f, 0.5f, 0.0f}};
    int kinds[3] = {0, 0, 0};
    for (std::uint32_t t = 0; t < s.mesh.triangles.size(); ++t) {
        const std::uint32_t obj = s.mesh.objectIds[t];
        if (obj >= 1 && obj <= 3) {
            EXPECT_GT(glm::dot(triangleNormal(s.mesh, t), centroid(s.mesh, t) - centres[obj - 1]), 0.0f);
            kinds[obj - 1] = static_cast<int>(s.materials[s.mesh.materialIds[t]].kind);
        }
    }
    EXPECT_EQ(kinds[1], static_cast<int>(MaterialKind::Mirror));
    EXPECT_EQ(kinds[2], static_cast<int>(MaterialKind::Glass));
}

TEST(Builtin, UnknownNameListsKnownScenes) {
    try {
        builtinScene("teapot");
        FAIL();
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("teapot"), std::string::npos);
        EXPECT_NE(std::string(e.what()).find("cornell"), std::string::npos);
    }
}

}  // namespace
}  // namespace aamap
