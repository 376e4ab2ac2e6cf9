// The scene's mirrors as planes (scene/mirror_planes.h): plane clustering, curved groups,
// reflection matrices and projected coverage. CPU only.
#include "scene/mirror_planes.h"

#include <cmath>
#include <set>
#include <utility>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "scene/camera.h"
#include "tests/common/mirror_scenes.h"
#include "tests/common/test_scenes.h"

namespace aamap::test {
namespace {

TEST(MirrorGeometry, PlanarGroupsAndCurvedOnes) {
    Scene s = mirrorScene(MaterialKind::Mirror);
    MirrorGroups g = findPlanarMirrors(s);
    ASSERT_EQ(g.planar.size(), 1u);
    EXPECT_EQ(g.planar[0].name, "object 0/mirror");
    EXPECT_NEAR(std::fabs(g.planar[0].normal.z), 1.0f, 1e-6f);
    EXPECT_NEAR(g.planar[0].offset, 0.0f, 1e-6f);
    EXPECT_EQ(g.planar[0].reflectance, kReflectance);
    EXPECT_TRUE(g.curved.empty());
    // Bend one corner of the mirror out of its plane: its two triangles are two planes now.
    s.mesh.positions[2].z = 0.3f;
    g = findPlanarMirrors(s);
    ASSERT_EQ(g.planar.size(), 2u);
    EXPECT_EQ(g.planar[0].name, "object 0/mirror plane 1");
    EXPECT_EQ(g.planar[0].triangles.size() + g.planar[1].triangles.size(), 2u);
    EXPECT_TRUE(g.curved.empty());
    // The reflection matrix maps a point to its mirror image.
    const glm::vec4 p = reflectionMatrix({0, 0, 1}, 0.5f) * glm::vec4(1, 2, 3, 1);
    EXPECT_NEAR(p.z, -2.0f, 1e-6f);
    EXPECT_NEAR(p.x, 1.0f, 1e-6f);
}

// A sliver along the mirror's edge, whose vertices lie in the mirror plane (within the offset
// tolerance) but whose normal tilts by 17 degrees, is part of the mirror, not a plane of its own.
TEST(MirrorGeometry, ASliverInTheMirrorPlaneIsPartOfIt) {
    Scene s = mirrorScene(MaterialKind::Mirror);
    addPolygon(s, {{2, -2, 0}, {2, 2, 0}, {2.001f, 0, 3e-4f}}, 0, 0);
    const MirrorGroups g = findPlanarMirrors(s);
    ASSERT_EQ(g.planar.size(), 1u);
    EXPECT_EQ(g.planar[0].name, "object 0/mirror");
    EXPECT_EQ(g.planar[0].triangles, (std::vector<std::uint32_t>{0, 1, 4}));
    EXPECT_NEAR(std::fabs(g.planar[0].normal.z), 1.0f, 1e-4f);
    EXPECT_TRUE(g.curved.empty());
}

// A framed mirror is its big plane plus one plane per bevel strip, the big one first.
TEST(MirrorGeometry, AFramedMirrorIsFivePlanes) {
    const Scene s = framedMirrorScene();
    const MirrorGroups g = findPlanarMirrors(s);
    ASSERT_EQ(g.planar.size(), 5u);
    EXPECT_TRUE(g.curved.empty());
    EXPECT_EQ(g.planar[0].name, "object 0/mirror plane 1");
    EXPECT_EQ(g.planar[0].triangles, (std::vector<std::uint32_t>{0, 1}));
    EXPECT_NEAR(std::fabs(g.planar[0].normal.z), 1.0f, 1e-6f);
    EXPECT_NEAR(g.planar[0].offset, 0.0f, 1e-6f);
    for (std::size_t k = 1; k < 5; ++k) {
        EXPECT_EQ(g.planar[k].triangles.size(), 2u) << k;
        EXPECT_NEAR(std::fabs(g.planar[k].normal.z), std::sqrt(0.5f), 1e-5f) << k;  // 45 degrees back
        EXPECT_NEAR(std::fabs(g.planar[k].offset), 2.0f * std::sqrt(0.5f), 1e-5f) << k;
    }
    // The same twice gives the same planes in the same order.
    const MirrorGroups again = findPlanarMirrors(s);
    for (std::size_t k = 0; k < 5; ++k) EXPECT_EQ(again.planar[k].triangles, g.planar[k].triangles);
}

// Each face of a mirrored cube is a plane: 6 planes of 2 triangles, one per face normal.
TEST(MirrorGeometry, AMirroredCubeIsSixPlanes) {
    Scene s = mirrorScene(MaterialKind::Mirror);
    s.mesh = {};
    addCube(s, 0, 7);
    const MirrorGroups g = findPlanarMirrors(s);
    ASSERT_EQ(g.planar.size(), 6u);
    EXPECT_TRUE(g.curved.empty());
    std::set<std::pair<int, int>> faces;  // (axis, sign of the offset)
    for (const PlanarMirror& m : g.planar) {
        EXPECT_EQ(m.triangles.size(), 2u);
        EXPECT_EQ(m.name.rfind("object 7/mirror plane ", 0), 0u) << m.name;
        int axis = 0;
        for (int k = 1; k < 3; ++k)
            if (std::fabs(m.normal[k]) > std::fabs(m.normal[axis])) axis = k;
        EXPECT_NEAR(std::fabs(m.normal[axis]), 1.0f, 1e-6f);
        EXPECT_NEAR(std::fabs(m.offset), 1.0f, 1e-6f);
        faces.insert({axis, (m.offset > 0.0f) == (m.normal[axis] > 0.0f) ? 1 : -1});
    }
    EXPECT_EQ(faces.size(), 6u);
}

// A tessellated sphere is many small planes: curved, no plane accepted. A cylinder's flat caps
// hold a quarter of its area each: two planes, and its sides stay curved.
TEST(MirrorGeometry, TessellatedCurvesStayCurved) {
    Scene s = mirrorScene(MaterialKind::Mirror);
    s.mesh = {};
    addSphere(s, glm::vec3(0.0f), 1.0f, 12, 6, 0, 3);
    MirrorGroups g = findPlanarMirrors(s);
    EXPECT_TRUE(g.planar.empty());
    ASSERT_EQ(g.curved.size(), 1u);
    EXPECT_EQ(g.curved[0].triangles.size(), s.mesh.triangles.size());
    EXPECT_EQ(g.curved[0].planes, 0u);
    EXPECT_EQ(g.curved[0].describe(), fmt::format("object 3/mirror: {} triangles curved", s.mesh.triangles.size()));

    s.mesh = {};
    const int sides = 24;
    std::vector<glm::vec3> ring;
    for (int k = 0; k < sides; ++k) {
        const float phi = 6.28318531f * k / sides;
        ring.push_back({std::cos(phi), 0.0f, std::sin(phi)});
    }
    const glm::vec3 up(0, 1, 0);
    for (int k = 0; k < sides; ++k) {
        const glm::vec3 a = ring[k], b = ring[(k + 1) % sides];
        addPolygon(s, {a, b, b + up, a + up}, 0, 4);  // a side facet
        addPolygon(s, {glm::vec3(0.0f), b, a}, 0, 4);  // the bottom cap, fanned from its centre
        addPolygon(s, {up, a + up, b + up}, 0, 4);     // the top cap
    }
    g = findPlanarMirrors(s);
    ASSERT_EQ(g.planar.size(), 2u);
    for (const PlanarMirror& m : g.planar) {
        EXPECT_EQ(m.triangles.size(), static_cast<std::size_t>(sides));
        EXPECT_NEAR(std::fabs(m.normal.y), 1.0f, 1e-6f);
    }
    ASSERT_EQ(g.curved.size(), 1u);
    EXPECT_EQ(g.curved[0].describe(), "object 4/mirror: 2 planes reflected, 48 triangles curved");
}

// Bad input never crashes: out-of-range indices, degenerate and non-finite triangles are no plane.
TEST(MirrorGeometry, BadTrianglesAreSkipped) {
    Scene s = mirrorScene(MaterialKind::Mirror);
    s.mesh.triangles.push_back({0, 1, 99});
    s.mesh.triangles.push_back({0, 0, 1});
    s.mesh.positions.push_back(glm::vec3(NAN));
    s.mesh.triangles.push_back({0, 1, static_cast<std::uint32_t>(s.mesh.positions.size() - 1)});
    s.mesh.materialIds.resize(s.mesh.triangles.size(), 0);
    s.mesh.objectIds.resize(s.mesh.triangles.size(), 0);
    const MirrorGroups g = findPlanarMirrors(s);
    ASSERT_EQ(g.planar.size(), 1u);
    EXPECT_EQ(g.planar[0].triangles, (std::vector<std::uint32_t>{0, 1}));
    EXPECT_TRUE(g.curved.empty());
    EXPECT_EQ(projectedPixels(s.mesh.positions, s.mesh.triangles, {4, 5, 6, 99}, glm::mat4(1.0f), 0.1f,
                                      {64, 64}),
              0.0);
}

// Projected coverage: a square filling the middle quarter of a 90-degree view covers a quarter of
// the pixels; one crossing the eye's plane counts its part in front; one behind counts nothing.
TEST(MirrorGeometry, ProjectedPixelsOfAQuad) {
    const View v = viewDownZ({0, 0, 0}, 90.0f);
    const PinholeCamera camera = PinholeCamera::fromView(v);
    const glm::mat4 viewProj = camera.projectionMatrix(0.01f, 100.0f) * camera.viewMatrix();
    Scene s;
    addPolygon(s, {{-0.5f, -0.5f, -1}, {0.5f, -0.5f, -1}, {0.5f, 0.5f, -1}, {-0.5f, 0.5f, -1}}, 0, 0);
    const std::vector<std::uint32_t> both{0, 1};
    glm::vec4 ndc;
    EXPECT_NEAR(projectedPixels(s.mesh.positions, s.mesh.triangles, both, viewProj, 0.01f, {64, 32}, &ndc),
                64.0 * 32.0 / 4.0, 1e-2);
    for (int k = 0; k < 4; ++k) EXPECT_NEAR(std::fabs(ndc[k]), 0.5f, 1e-5f) << "the quad's NDC bounds, " << k;
    EXPECT_LT(ndc.x, ndc.z);
    EXPECT_LT(ndc.y, ndc.w);
    // A floor under the eye reaching from behind it to far ahead: clipped to the view, at most all pixels.
    s.mesh = {};
    addPolygon(s, {{-50, -1, 50}, {50, -1, 50}, {50, -1, -50}, {-50, -1, -50}}, 0, 0);
    const double floor = projectedPixels(s.mesh.positions, s.mesh.triangles, both, viewProj, 0.01f, {64, 64});
    EXPECT_GT(floor, 0.4 * 64 * 64);
    EXPECT_LE(floor, 0.5 * 64 * 64 + 1e-3);  // the lower half of the image at most
    s.mesh = {};
    addPolygon(s, {{-0.5f, -0.5f, 1}, {0.5f, -0.5f, 1}, {0.5f, 0.5f, 1}, {-0.5f, 0.5f, 1}}, 0, 0);
    EXPECT_EQ(projectedPixels(s.mesh.positions, s.mesh.triangles, both, viewProj, 0.01f, {64, 64}, &ndc), 0.0);
    EXPECT_GT(ndc.x, ndc.z) << "nothing in view: empty bounds";
}

}  // namespace
}  // namespace aamap::test
