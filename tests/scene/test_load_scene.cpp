#include <gtest/gtest.h>

#include "core/error.h"
#include "scene/lights.h"
#include "scene/load_scene.h"
#include "scene/mesh_orientation.h"
#include "tests/common/temp_dir.h"

namespace aamap {
namespace {

TEST(LoadScene, BuiltinSpecs) {
    EXPECT_EQ(loadScene("builtin:cornell").name, "cornell");
    EXPECT_EQ(loadScene("builtin:spheres-plane").name, "spheres-plane");
    EXPECT_THROW(loadScene("builtin:nope"), InputError);
}

TEST(LoadScene, ObjWithSiblingViewFile) {
    test::TempDir dir;
    dir.write("room.vf", "rview -vtv -vp 0 0 5 -vd 0 0 -1 -vu 0 1 0 -vh 40 -vv 30\n");
    const auto obj = dir.write("room.OBJ", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    const Scene s = loadScene(obj.string());
    EXPECT_EQ(s.mesh.triangles.size(), 1u);
    EXPECT_EQ(s.source, obj);
    ASSERT_EQ(s.views.size(), 1u);
    EXPECT_EQ(s.views[0].name, "room:0");
    EXPECT_FLOAT_EQ(s.views[0].verticalFovDeg, 30.0f);
}

TEST(LoadScene, UnknownFormatAndMissingFile) {
    try {
        loadScene("scene.xyz");
        FAIL();
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("unsupported scene format '.xyz'"), std::string::npos);
    }
    EXPECT_THROW(loadScene("/nonexistent/dir/scene.obj"), InputError);
    EXPECT_THROW(loadScene("/nonexistent/dir/scene.gltf"), InputError);
}

// A one-sided emitter wound clockwise as seen from where its normals point (as converters that
// tessellate rectangles write them): the light must face its normals, as in Mitsuba and pbrt.
TEST(LoadScene, TrianglesFaceWhereTheirVertexNormalsPoint) {
    test::TempDir dir;
    dir.write("lamp.mtl", "newmtl lamp\nKd 0 0 0\nKe 2 2 2\n");
    const auto obj = dir.write("lamp.obj",
                               "mtllib lamp.mtl\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvn 0 0 1\nusemtl lamp\n"
                               "f 1//1 3//1 2//1\nf 1//1 4//1 3//1\n");
    const Scene s = loadScene(obj.string());
    ASSERT_EQ(s.mesh.triangles.size(), 2u);
    for (std::uint32_t t = 0; t < 2; ++t) EXPECT_GT(triangleNormal(s.mesh, t).z, 0.99f) << "triangle " << t;
    const std::vector<AreaLight> lights = buildAreaLights(s, {});
    ASSERT_EQ(lights.size(), 1u);
    for (const PointLight& p : approximateAreaLight(s, lights[0], 5)) EXPECT_GT(p.normal.z, 0.99f);
}

TEST(MeshOrientation, ReversesOnlyTrianglesAgainstTheirNormals) {
    TriangleMesh mesh;
    mesh.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {2, 0, 0}, {2, 0, 0}, {2, 0, 0}};
    mesh.normals = {{0, 0, 1}, {0, 0, 1}, {0, 0, 1}, {0, 0, -1}, {0, 0, -1}, {0, 0, -1},
                    {0, 0, 1}, {0, 0, 1}, {0, 0, 1}};
    mesh.triangles = {{0, 1, 2}, {3, 4, 5}, {6, 7, 8}};  // agrees, disagrees, degenerate
    EXPECT_EQ(orientTrianglesToNormals(mesh), 1u);
    EXPECT_EQ(mesh.triangles[0], glm::uvec3(0, 1, 2));
    EXPECT_EQ(mesh.triangles[1], glm::uvec3(3, 5, 4));  // same vertices, reversed: faces -z now
    EXPECT_EQ(mesh.triangles[2], glm::uvec3(6, 7, 8));
    EXPECT_EQ(orientTrianglesToNormals(mesh), 0u) << "a second pass has nothing left to turn";

    mesh.normals = {glm::vec3(NAN), glm::vec3(NAN), glm::vec3(NAN), {}, {}, {}, {}, {}, {}};
    EXPECT_EQ(orientTrianglesToNormals(mesh), 0u) << "NaN or zero normals carry no orientation";
    mesh.normals.clear();
    EXPECT_EQ(orientTrianglesToNormals(mesh), 0u) << "without normals the winding decides";
}

}  // namespace
}  // namespace aamap
