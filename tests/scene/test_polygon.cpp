#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include "scene/polygon.h"

namespace aamap {
namespace {

float area(const std::vector<glm::vec3>& p, const std::vector<std::array<int, 3>>& tris, glm::vec3 normal) {
    float a = 0;
    for (const auto& t : tris) {
        const float signedArea = 0.5f * glm::dot(glm::cross(p[t[1]] - p[t[0]], p[t[2]] - p[t[0]]), normal);
        EXPECT_GT(signedArea, 0.0f) << "triangle wound against the polygon";
        a += signedArea;
    }
    return a;
}

TEST(TriangulatePolygon, ConvexQuadUsesTheShorterDiagonal) {
    const std::vector<glm::vec3> p = {{0, 0, 0}, {4, 0, 0}, {4.5f, 1, 0}, {0.5f, 1, 0}};
    const auto tris = triangulatePolygon(p);
    ASSERT_EQ(tris.size(), 2u);
    EXPECT_EQ(tris[0], (std::array{0, 1, 3}));  // 1-3 is shorter than 0-2
    EXPECT_NEAR(area(p, tris, {0, 0, 1}), 4.0f, 1e-5f);
}

TEST(TriangulatePolygon, ConcaveShapesInAnyPlaneAndOrientation) {
    // A "C" shape (8 vertices, area 9 - 2) in the xz-plane, wound counter-clockwise about +y.
    const std::vector<glm::vec3> p = {{0, 0, 0}, {0, 0, 3}, {3, 0, 3}, {3, 0, 2}, {1, 0, 2}, {1, 0, 1}, {3, 0, 1}, {3, 0, 0}};
    const auto tris = triangulatePolygon(p);
    ASSERT_EQ(tris.size(), 6u);
    EXPECT_NEAR(area(p, tris, {0, 1, 0}), 7.0f, 1e-5f);
    // A concave quad (dart).
    const std::vector<glm::vec3> dart = {{0, 0, 0}, {2, 1, 0}, {0, 2, 0}, {1, 1, 0}};
    EXPECT_NEAR(area(dart, triangulatePolygon(dart), {0, 0, 1}), 1.0f, 1e-5f);
}

TEST(TriangulatePolygon, DegenerateInputFallsBackToAFan) {
    const std::vector<glm::vec3> line = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {3, 0, 0}};
    EXPECT_EQ(triangulatePolygon(line).size(), 2u);
    EXPECT_TRUE(triangulatePolygon(std::vector<glm::vec3>{{0, 0, 0}, {1, 0, 0}}).empty());
}

}  // namespace
}  // namespace aamap
