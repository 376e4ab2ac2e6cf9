#include <cmath>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>
#include <stb_image_write.h>

#include "core/error.h"
#include "scene/lights.h"
#include "scene/obj_loader.h"
#include "tests/common/temp_dir.h"

namespace aamap {
namespace {

using test::TempDir;

float totalArea(const Scene& s) {
    float a = 0;
    for (std::uint32_t t = 0; t < s.mesh.triangles.size(); ++t) a += triangleArea(s.mesh, t);
    return a;
}

// Loads `obj` and expects an InputError at file:line:col whose message contains `what`.
void expectObjError(const TempDir& dir, const std::string& obj, int line, int column, const std::string& what,
                    const std::string& fileName = "bad.obj") {
    const auto path = dir.write("bad.obj", obj);
    try {
        loadObj(path);
        FAIL() << "no error for:\n" << obj;
    } catch (const InputError& e) {
        EXPECT_EQ(e.file().filename(), fileName) << e.what();
        EXPECT_EQ(e.line(), line) << e.what();
        if (column >= 0) {
            EXPECT_EQ(e.column(), column) << e.what();
        }
        EXPECT_NE(std::string(e.what()).find(what), std::string::npos) << e.what();
    }
}

const char* kQuad = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n";

TEST(ObjLoader, QuadIsTwoTrianglesWithFlatNormals) {
    TempDir dir;
    const Scene s = loadObj(dir.write("quad.obj", std::string(kQuad) + "f 1 2 3 4\n"));
    ASSERT_EQ(s.mesh.triangles.size(), 2u);
    EXPECT_FLOAT_EQ(totalArea(s), 1.0f);
    ASSERT_EQ(s.mesh.normals.size(), s.mesh.positions.size());
    for (const glm::vec3& n : s.mesh.normals) EXPECT_NEAR(n.z, 1.0f, 1e-6f);  // counter-clockwise -> +z
    EXPECT_TRUE(s.mesh.uvs.empty());
    ASSERT_EQ(s.materials.size(), 1u);
    EXPECT_EQ(s.materials[0].name, "default");
    EXPECT_EQ(s.name, "quad");
}

TEST(ObjLoader, NegativeIndicesCrlfAndTabs) {
    TempDir dir;
    const Scene s = loadObj(dir.write("crlf.obj", "v\t0 0 0\r\nv\t1  0\t0\r\nv 1 1 0\r\nv 0 1 0\r\nf\t-4 -3 -2 -1\r\n"));
    ASSERT_EQ(s.mesh.triangles.size(), 2u);
    EXPECT_FLOAT_EQ(totalArea(s), 1.0f);
}

TEST(ObjLoader, PositionUvFacesAndFlippedV) {
    TempDir dir;
    const Scene s = loadObj(dir.write("uv.obj", std::string(kQuad) + "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nf 1/1 2/2 3/3 4/4\n"));
    ASSERT_EQ(s.mesh.uvs.size(), s.mesh.positions.size());
    for (std::size_t i = 0; i < s.mesh.positions.size(); ++i) {
        // OBJ v = 0 is the bottom of the image; the scene's v = 0 is the top row.
        EXPECT_FLOAT_EQ(s.mesh.uvs[i].x, s.mesh.positions[i].x);
        EXPECT_FLOAT_EQ(s.mesh.uvs[i].y, 1.0f - s.mesh.positions[i].y);
    }
}

TEST(ObjLoader, PentagonAndConcavePolygons) {
    TempDir dir;
    // An L-shaped hexagon (concave) of area 3 and a convex pentagon.
    const Scene s = loadObj(dir.write("poly.obj",
                                      "v 0 0 0\nv 2 0 0\nv 2 1 0\nv 1 1 0\nv 1 2 0\nv 0 2 0\nf 1 2 3 4 5 6\n"
                                      "v 0 0 1\nv 1 0 1\nv 1.5 0.5 1\nv 1 1 1\nv 0 1 1\nf 7 8 9 10 11\n"));
    EXPECT_EQ(s.mesh.triangles.size(), 4u + 3u);
    EXPECT_NEAR(totalArea(s), 3.0f + 1.25f, 1e-5f);
    for (std::uint32_t t = 0; t < s.mesh.triangles.size(); ++t) EXPECT_GT(triangleNormal(s.mesh, t).z, 0.99f);
}

TEST(ObjLoader, FileNormalsAreUsedWhenPresent) {
    TempDir dir;
    const Scene s = loadObj(dir.write("n.obj", std::string(kQuad) + "vn 0 0 2\nvn 0 1 1\nf 1//1 2//1 3//2\nf 1 3 4\n"));
    ASSERT_EQ(s.mesh.triangles.size(), 2u);
    const glm::uvec3 smooth = s.mesh.triangles[0];
    EXPECT_NEAR(s.mesh.normals[smooth.x].z, 1.0f, 1e-6f);  // normalised
    EXPECT_NEAR(s.mesh.normals[smooth.z].y, std::sqrt(0.5f), 1e-6f);
    const glm::uvec3 flat = s.mesh.triangles[1];
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(s.mesh.normals[flat[k]].z, 1.0f, 1e-6f);
}

TEST(ObjLoader, DegenerateTrianglesAreSkippedAndCounted) {
    TempDir dir;
    ObjLoadReport report;
    const Scene s = loadObj(dir.write("d.obj", std::string(kQuad) + "v 2 0 0\nf 1 2 3\nf 1 2 5\nf 1 1 2\n"), &report);
    EXPECT_EQ(s.mesh.triangles.size(), 1u);
    EXPECT_EQ(report.degenerateTriangles, 2u);
    bool warned = false;
    for (const auto& w : report.warnings) warned = warned || w.find("2 zero-area") != std::string::npos;
    EXPECT_TRUE(warned);
}

TEST(ObjLoader, MaterialsKindsAndAreaLightsPerShape) {
    TempDir dir;
    dir.write("m.mtl",
              "newmtl white\nKd 0.5 0.6 0.7\nKs 0.1 0.2 0.3\nNs 20\n"
              "newmtl mirror\r\nillum 3\r\nnewmtl mirror5\nillum 5\nnewmtl glass\nillum 7\nNi 1.33\n"
              "newmtl lamp\nKd 0 0 0\nKe 10 10 10\n");
    const Scene s = loadObj(dir.write("m.obj", std::string("mtllib m.mtl\n") + kQuad +
                                                   "g a\nusemtl white\nf 1 2 3\nusemtl lamp\nf 1 3 4\n"
                                                   "g b\nusemtl lamp\nf 1 2 3 4\nusemtl glass\nf 1 2 3\n"));
    ASSERT_EQ(s.materials.size(), 5u);
    EXPECT_EQ(s.materials[0].kd, glm::vec3(0.5f, 0.6f, 0.7f));
    EXPECT_EQ(s.materials[0].ks, glm::vec3(0.1f, 0.2f, 0.3f));
    EXPECT_FLOAT_EQ(s.materials[0].ns, 20.0f);
    EXPECT_EQ(s.materials[0].kind, MaterialKind::Diffuse);
    EXPECT_EQ(s.materials[1].kind, MaterialKind::Mirror);
    EXPECT_EQ(s.materials[2].kind, MaterialKind::Mirror);
    EXPECT_EQ(s.materials[3].kind, MaterialKind::Glass);
    EXPECT_FLOAT_EQ(s.materials[3].ior, 1.33f);
    EXPECT_EQ(s.materials[4].ke, glm::vec3(10.0f));

    ASSERT_EQ(s.mesh.triangles.size(), 5u);
    EXPECT_EQ(s.mesh.objectIds, (std::vector<std::uint32_t>{0, 0, 1, 1, 1}));
    ASSERT_EQ(s.areaLights.size(), 2u);  // one per (shape, emissive material)
    EXPECT_EQ(s.areaLights[0].name, "a/lamp");
    EXPECT_FLOAT_EQ(s.areaLights[0].area, 0.5f);
    EXPECT_EQ(s.areaLights[0].triangles.size(), 1u);
    EXPECT_EQ(s.areaLights[1].name, "b/lamp");
    EXPECT_FLOAT_EQ(s.areaLights[1].area, 1.0f);
    EXPECT_EQ(s.areaLights[1].radiance, glm::vec3(10.0f));
}

// Every colour of an MTL material keeps its three channels apart.
TEST(ObjLoader, MaterialColoursKeepTheirChannels) {
    TempDir dir;
    dir.write("c.mtl", "newmtl lamp\nKd 0.1 0.2 0.3\nKs 0.4 0.5 0.6\nKe 7 8 9\n");
    const Scene s = loadObj(dir.write("c.obj", std::string("mtllib c.mtl\n") + kQuad + "usemtl lamp\nf 1 2 3\n"));
    ASSERT_EQ(s.materials.size(), 1u);
    EXPECT_EQ(s.materials[0].kd, glm::vec3(0.1f, 0.2f, 0.3f));
    EXPECT_EQ(s.materials[0].ks, glm::vec3(0.4f, 0.5f, 0.6f));
    EXPECT_EQ(s.materials[0].ke, glm::vec3(7.0f, 8.0f, 9.0f));
}

TEST(ObjLoader, MissingTextureWarnsAndKeepsKd) {
    TempDir dir;
    dir.write("t.mtl", "newmtl tex\nKd 0.2 0.3 0.4\nmap_Kd nothere.png\n");
    ObjLoadReport report;
    const Scene s = loadObj(dir.write("t.obj", std::string("mtllib t.mtl\nusemtl tex\n") + kQuad + "f 1 2 3\n"), &report);
    ASSERT_EQ(s.materials.size(), 1u);
    EXPECT_EQ(s.materials[0].diffuseTexture, -1);
    EXPECT_EQ(s.materials[0].kd, glm::vec3(0.2f, 0.3f, 0.4f));
    EXPECT_TRUE(s.textures.empty());
    bool named = false;
    for (const auto& w : report.warnings) named = named || w.find("nothere.png") != std::string::npos;
    EXPECT_TRUE(named);
}

TEST(ObjLoader, TextureCaseMismatchBackslashAndSrgbDecoding) {
    TempDir dir;
    const unsigned char pixels[] = {255, 0, 0, 255, 128, 128, 128, 64};  // 2x1 RGBA
    std::filesystem::create_directories(dir.path() / "Maps");
    ASSERT_NE(stbi_write_png((dir.path() / "Maps" / "Wood.PNG").string().c_str(), 2, 1, 4, pixels, 8), 0);
    dir.write("t.mtl", "newmtl a\nmap_Kd maps\\wood.png\nnewmtl b\nmap_Kd ./maps/WOOD.png\n");
    const Scene s = loadObj(dir.write("t.obj", std::string("mtllib t.mtl\n") + kQuad + "usemtl a\nf 1 2 3\nusemtl b\nf 1 3 4\n"));
    ASSERT_EQ(s.textures.size(), 1u);  // both materials share one decoded texture
    EXPECT_EQ(s.materials[0].diffuseTexture, 0);
    EXPECT_EQ(s.materials[1].diffuseTexture, 0);
    const Texture& t = s.textures[0];
    ASSERT_EQ(t.width, 2);
    ASSERT_EQ(t.height, 1);
    ASSERT_EQ(t.rgba.size(), 8u);
    EXPECT_FLOAT_EQ(t.rgba[0], 1.0f);
    EXPECT_FLOAT_EQ(t.rgba[1], 0.0f);
    EXPECT_NEAR(t.rgba[4], 0.2158605f, 1e-5f);  // sRGB 128 -> linear
    EXPECT_NEAR(t.rgba[7], 64.0f / 255.0f, 1e-6f);  // alpha stays linear
}

TEST(ObjLoader, MissingFileAndMissingMtl) {
    TempDir dir;
    try {
        loadObj(dir.path() / "none.obj");
        FAIL();
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("none.obj"), std::string::npos);
    }
    ObjLoadReport report;
    const Scene s = loadObj(dir.write("m.obj", std::string("mtllib gone.mtl\nusemtl x\n") + kQuad + "f 1 2 3\n"), &report);
    EXPECT_EQ(s.mesh.triangles.size(), 1u);
    bool named = false;
    for (const auto& w : report.warnings) named = named || w.find("gone.mtl") != std::string::npos;
    EXPECT_TRUE(named);
}

TEST(ObjLoader, BadInputNamesFileLineAndColumn) {
    TempDir dir;
    expectObjError(dir, "v 0 0 0\nv 1 0 0\nv 1 x 0\n", 3, 5, "'x' is not a number");
    expectObjError(dir, "v 0 0 0\r\nv 1 0 nan\r\n", 2, 7, "not finite");
    expectObjError(dir, "v 0 0 0\nv 1 0 inf\n", 2, 7, "not finite");
    expectObjError(dir, "v 0 0\n", 1, 1, "needs 3 numbers");
    expectObjError(dir, "vn 0 0 1e999\n", 1, 8, "not finite");
    expectObjError(dir, std::string(kQuad) + "f 1 2 9\n", 5, 7, "vertex index 9 is out of range");
    expectObjError(dir, std::string(kQuad) + "f 1 2 0\n", 5, 7, "index 0");
    expectObjError(dir, std::string(kQuad) + "f -1 -2 -5\n", 5, 9, "relative vertex index -5");
    expectObjError(dir, std::string(kQuad) + "f 1/1 2/1 3/1\n", 5, 3, "texture coordinate index 1 is out of range");
    expectObjError(dir, std::string(kQuad) + "f 1 2\n", 5, 1, "at least 3 vertices");
    expectObjError(dir, std::string(kQuad) + "f 1 2 3a\n", 5, 7, "not an integer");
    expectObjError(dir, std::string(kQuad) + "f 1/2/3/4 2 3\n", 5, 3, "more than 3 indices");
}

TEST(ObjLoader, BadMtlNamesTheMtlFile) {
    TempDir dir;
    dir.write("bad.mtl", "newmtl a\nKd 0.5 0.5 0.5\nNs abc\n");
    try {
        loadObj(dir.write("ok.obj", std::string("mtllib bad.mtl\n") + kQuad + "f 1 2 3\n"));
        FAIL();
    } catch (const InputError& e) {
        EXPECT_EQ(e.file().filename(), "bad.mtl");
        EXPECT_EQ(e.line(), 3);
        EXPECT_EQ(e.column(), 4);
    }
}

TEST(ObjLoader, ForwardReferencesAreAllowed) {
    TempDir dir;
    const Scene s = loadObj(dir.write("fwd.obj", std::string("f 1 2 3\n") + kQuad));
    EXPECT_EQ(s.mesh.triangles.size(), 1u);
}

}  // namespace
}  // namespace aamap
