// Mitsuba's .serialized meshes: files written here by a small writer of the format (zlib-compressed
// streams, single or double precision, optional normals and uvs, the end-of-file table of mesh
// offsets), loaded through the Mitsuba loader and checked against the mesh written.
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>
#include <unistd.h>
#include <zlib.h>

#include "core/error.h"
#include "scene/mitsuba_loader.h"
#include "scene/mitsuba_serialized.h"

namespace aamap {
namespace {
namespace fs = std::filesystem;

struct Mesh {
    std::vector<glm::vec3> positions;
    std::vector<glm::vec3> normals;
    std::vector<glm::vec2> uvs;
    std::vector<glm::uvec3> triangles;
    bool doublePrecision = false;
};

template <typename T>
void put(std::string& out, T v) {
    out.append(reinterpret_cast<const char*>(&v), sizeof v);
}

template <typename V>
void putReals(std::string& out, const std::vector<V>& values, bool dp) {
    for (const V& v : values)
        for (int k = 0; k < V::length(); ++k) dp ? put<double>(out, v[k]) : put<float>(out, v[k]);
}

std::string compress(const std::string& raw) {
    uLongf size = compressBound(raw.size());
    std::string out(size, '\0');
    EXPECT_EQ(compress2(reinterpret_cast<Bytef*>(out.data()), &size, reinterpret_cast<const Bytef*>(raw.data()),
                        raw.size(), 6),
              Z_OK);
    out.resize(size);
    return out;
}

// A version-4 file of these meshes: per mesh the header and its zlib stream, then the offsets.
std::string serialized(const std::vector<Mesh>& meshes) {
    std::string file;
    std::vector<std::uint64_t> offsets;
    for (const Mesh& m : meshes) {
        offsets.push_back(file.size());
        put<std::uint16_t>(file, 0x041C);
        put<std::uint16_t>(file, 4);
        std::string raw;
        const std::uint32_t flags = (m.normals.empty() ? 0 : 0x1) | (m.uvs.empty() ? 0 : 0x2) |
                                    (m.doublePrecision ? 0x2000 : 0x1000);
        put(raw, flags);
        raw += "mesh";
        raw += '\0';
        put<std::uint64_t>(raw, m.positions.size());
        put<std::uint64_t>(raw, m.triangles.size());
        putReals(raw, m.positions, m.doublePrecision);
        putReals(raw, m.normals, m.doublePrecision);
        putReals(raw, m.uvs, m.doublePrecision);
        for (const glm::uvec3& t : m.triangles)
            for (int k = 0; k < 3; ++k) put<std::uint32_t>(raw, t[k]);
        file += compress(raw);
    }
    for (std::uint64_t o : offsets) put(file, o);
    put<std::uint32_t>(file, static_cast<std::uint32_t>(meshes.size()));
    return file;
}

// A unit quad in z = 0 (two triangles), and a tilted triangle.
Mesh quad() {
    Mesh m;
    m.positions = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
    m.triangles = {{0, 1, 2}, {0, 2, 3}};
    return m;
}
Mesh triangle() {
    Mesh m;
    m.positions = {{0, 0, 0}, {2, 0, 0}, {0, 0, 2}};
    m.triangles = {{0, 2, 1}};  // faces +Y
    return m;
}

class Serialized : public ::testing::Test {
protected:
    fs::path dir = fs::temp_directory_path() / ("aamap_serialized_" + std::to_string(::getpid()));
    void SetUp() override { fs::create_directories(dir); }
    void TearDown() override {
        std::error_code ec;
        fs::remove_all(dir, ec);
    }
    void writeFile(const std::string& name, const std::string& bytes) const {
        std::ofstream(dir / name, std::ios::binary) << bytes;
    }
    Scene load(const std::string& shapeBody) {
        std::ofstream(dir / "scene.xml") << "<scene version=\"3.0.0\"><shape type=\"serialized\">"
                                            "<string name=\"filename\" value=\"m.serialized\"/>"
                                         << shapeBody << "</shape></scene>";
        return loadMitsuba(dir / "scene.xml");
    }
    std::string error(const std::string& shapeBody) {
        try {
            load(shapeBody);
        } catch (const InputError& e) {
            return e.what();
        }
        ADD_FAILURE() << "loaded; expected an InputError";
        return {};
    }
};

TEST_F(Serialized, SinglePrecisionWithNormalsAndUvs) {
    Mesh m = quad();
    m.normals.assign(4, {0, 0, 1});
    m.normals[2] = glm::normalize(glm::vec3(1, 0, 1));
    m.uvs = {{0, 0}, {1, 0}, {1, 1}, {0.25f, 0.75f}};
    writeFile("m.serialized", serialized({m}));
    const Scene s = load("");
    ASSERT_EQ(s.mesh.triangles.size(), 2u);
    ASSERT_EQ(s.mesh.uvs.size(), s.mesh.positions.size());
    // The second triangle's corners are the written vertices 0, 2, 3 with their attributes.
    const glm::uvec3 t = s.mesh.triangles[1];
    EXPECT_EQ(s.mesh.positions[t.z], glm::vec3(0, 1, 0));
    EXPECT_EQ(s.mesh.uvs[t.z], glm::vec2(0.25f, 0.75f));
    EXPECT_NEAR(glm::distance(s.mesh.normals[t.y], m.normals[2]), 0.0f, 1e-6f);
    EXPECT_EQ(s.mesh.normals[t.x], glm::vec3(0, 0, 1));
}

TEST_F(Serialized, DoublePrecisionWithoutNormalsGetsSmoothNormals) {
    // A bent strip: the shared edge's vertices take the mean of the two faces' normals, as Mitsuba
    // computes normals for a mesh that brings none.
    Mesh m;
    m.doublePrecision = true;
    m.positions = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0, 1, 1}, {1, 1, 1}};
    m.triangles = {{0, 1, 2}, {0, 2, 3}, {3, 2, 5}, {3, 5, 4}};
    writeFile("m.serialized", serialized({m}));
    const Scene s = load("");
    ASSERT_EQ(s.mesh.triangles.size(), 4u);
    EXPECT_TRUE(s.mesh.uvs.empty());
    const glm::vec3 bend = glm::normalize(glm::vec3(0, -1, 1));
    for (std::size_t i = 0; i < s.mesh.positions.size(); ++i) {
        const glm::vec3 p = s.mesh.positions[i];
        if (p.y == 0.0f) {
            EXPECT_NEAR(glm::distance(s.mesh.normals[i], glm::vec3(0, 0, 1)), 0.0f, 1e-6f) << i;
        } else if (p.z == 0.0f) {
            EXPECT_NEAR(glm::distance(s.mesh.normals[i], bend), 0.0f, 1e-6f) << i;
        }
    }
    // face_normals keeps the facets.
    const Scene flat = load(R"(<boolean name="face_normals" value="true"/>)");
    for (const glm::vec3& n : flat.mesh.normals) EXPECT_TRUE(n == glm::vec3(0, 0, 1) || n == glm::vec3(0, -1, 0)) << n.x;
}

TEST_F(Serialized, ShapeIndexPicksTheSecondMeshThroughTheOffsetTable) {
    Mesh dp = triangle();
    dp.doublePrecision = true;
    writeFile("m.serialized", serialized({quad(), dp}));
    const Scene first = load("");
    EXPECT_EQ(first.mesh.triangles.size(), 2u);
    const Scene second = load(R"(<integer name="shape_index" value="1"/>
<transform name="to_world"><translate x="10"/></transform>)");
    ASSERT_EQ(second.mesh.triangles.size(), 1u);
    const glm::uvec3 t = second.mesh.triangles[0];
    EXPECT_EQ(second.mesh.positions[t.x], glm::vec3(10, 0, 0));
    EXPECT_EQ(second.mesh.positions[t.y], glm::vec3(10, 0, 2));
    EXPECT_EQ(second.mesh.positions[t.z], glm::vec3(12, 0, 0));
    EXPECT_NEAR(glm::distance(second.mesh.normals[t.x], glm::vec3(0, 1, 0)), 0.0f, 1e-6f);
    // flip_normals turns the front: winding and normals both.
    const Scene flipped = load(R"(<integer name="shape_index" value="1"/><boolean name="flip_normals" value="true"/>)");
    const glm::uvec3 f = flipped.mesh.triangles[0];
    const glm::vec3 c = glm::cross(flipped.mesh.positions[f.y] - flipped.mesh.positions[f.x],
                                   flipped.mesh.positions[f.z] - flipped.mesh.positions[f.x]);
    EXPECT_LT(c.y, 0.0f);
    EXPECT_NEAR(glm::distance(flipped.mesh.normals[f.x], glm::vec3(0, -1, 0)), 0.0f, 1e-6f);
    EXPECT_NE(error(R"(<integer name="shape_index" value="2"/>)").find("shape_index 2 is out of range"),
              std::string::npos);
}

TEST_F(Serialized, BadFilesAreInputErrorsNamingTheFile) {
    const std::string good = serialized({quad()});
    const auto expectError = [&](const std::string& bytes, const std::string& what) {
        writeFile("m.serialized", bytes);
        const std::string message = error("");
        EXPECT_NE(message.find("m.serialized"), std::string::npos) << message;
        EXPECT_NE(message.find(what), std::string::npos) << message;
    };
    expectError(good.substr(0, good.size() / 2), "truncated");
    expectError(good.substr(0, 3), "truncated");
    std::string magic = good;
    magic[0] = 'X';
    expectError(magic, "bad magic");
    std::string garbage = good;
    garbage[4] = '\0';  // the zlib header's compression method
    expectError(garbage, "cannot be inflated");
    Mesh wrong = quad();
    wrong.triangles[1].z = 9;
    expectError(serialized({wrong}), "uses vertex 9 of 4");
    // Parsing every prefix never crashes: each is a mesh or an InputError.
    for (std::size_t n = 0; n < good.size(); ++n) {
        try {
            mitsuba::parseSerialized(std::as_bytes(std::span<const char>(good.data(), n)), "p.serialized", 0, false);
        } catch (const InputError&) {
        }
    }
}

}  // namespace
}  // namespace aamap
