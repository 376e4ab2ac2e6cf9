#include "scene/mitsuba_shapes.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include <assimp/Importer.hpp>
#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <fmt/format.h>
#include <glm/geometric.hpp>
#include <glm/matrix.hpp>

#include "core/error.h"
#include "scene/mitsuba_serialized.h"
#include "scene/obj_loader.h"
#include "scene/texture_loader.h"

namespace aamap::mitsuba {
namespace fs = std::filesystem;

namespace {

constexpr float kPi = std::numbers::pi_v<float>;

fs::path meshFile(const Element& shape) {
    const std::string name = stringProperty(shape, "filename", "");
    if (name.empty()) fail(shape, fmt::format("{} shape has no filename", shape.type()));
    const auto path = resolveCaseInsensitive(shape.file.parent_path(), name);
    if (!path) fail(shape, fmt::format("mesh file '{}' not found", (shape.file.parent_path() / name).string()));
    return *path;
}

ShapeMesh objMesh(const Element& shape) {
    const fs::path path = meshFile(shape);
    Scene s;
    try {
        s = loadObj(path);
    } catch (const InputError& e) {
        if (e.line() > 0) throw;  // inside the OBJ: its own file:line
        fail(shape, fmt::format("mesh '{}': {}", path.string(), e.what()));
    }
    ShapeMesh m;
    m.positions = std::move(s.mesh.positions);
    m.normals = std::move(s.mesh.normals);
    m.uvs = std::move(s.mesh.uvs);
    m.triangles = std::move(s.mesh.triangles);
    return m;
}

ShapeMesh plyMesh(const Element& shape) {
    const fs::path path = meshFile(shape);
    Assimp::Importer importer;
    const aiScene* scene = importer.ReadFile(path.string(), aiProcess_Triangulate | aiProcess_SortByPType);
    if (scene == nullptr) fail(shape, fmt::format("mesh '{}': {}", path.string(), importer.GetErrorString()));
    ShapeMesh m;
    for (unsigned i = 0; i < scene->mNumMeshes; ++i) {
        const aiMesh* mesh = scene->mMeshes[i];
        if (!(mesh->mPrimitiveTypes & aiPrimitiveType_TRIANGLE)) continue;  // points and lines
        const auto base = static_cast<std::uint32_t>(m.positions.size());
        for (unsigned v = 0; v < mesh->mNumVertices; ++v) {
            const aiVector3D& p = mesh->mVertices[v];
            if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
                fail(shape, fmt::format("mesh '{}': vertex {} is not finite", path.string(), v));
            m.positions.emplace_back(p.x, p.y, p.z);
            if (mesh->HasNormals()) m.normals.emplace_back(mesh->mNormals[v].x, mesh->mNormals[v].y, mesh->mNormals[v].z);
            if (mesh->HasTextureCoords(0))
                m.uvs.emplace_back(mesh->mTextureCoords[0][v].x, 1.0f - mesh->mTextureCoords[0][v].y);
        }
        for (unsigned f = 0; f < mesh->mNumFaces; ++f) {
            const aiFace& face = mesh->mFaces[f];
            if (face.mNumIndices != 3) continue;
            for (unsigned k = 0; k < 3; ++k)
                if (face.mIndices[k] >= mesh->mNumVertices)
                    fail(shape, fmt::format("mesh '{}': face {} uses vertex {} of {}", path.string(), f, face.mIndices[k],
                                            mesh->mNumVertices));
            m.triangles.emplace_back(base + face.mIndices[0], base + face.mIndices[1], base + face.mIndices[2]);
        }
    }
    // Meshes with and without normals or uvs mixed: drop the attribute rather than misalign it.
    if (m.normals.size() != m.positions.size()) m.normals.clear();
    if (m.uvs.size() != m.positions.size()) m.uvs.clear();
    return m;
}

ShapeMesh serializedMesh(const Element& shape) {
    const fs::path path = meshFile(shape);
    const int index = integerProperty(shape, "shape_index", 0);
    if (index < 0) fail(shape, fmt::format("shape_index {} is negative", index));
    try {
        return readSerialized(path, index, booleanProperty(shape, "face_normals", false));
    } catch (const InputError& e) {
        fail(shape, fmt::format("mesh '{}': {}", path.string(), e.problem()));
    }
}

// uv of the corners corner, +du, +du+dv, +dv, with v = 0 at the image's top.
const glm::vec2 kQuadUv[4] = {{0, 1}, {1, 1}, {1, 0}, {0, 0}};
// Mitsuba's rectangle: uv = (x, y) / 2 + 1/2 of the local point, and Mitsuba's v = 0 is the image's
// top row as aamap's is, so local (-1, -1) shows the image's top-left texel.
const glm::vec2 kRectangleUv[4] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};

void quad(ShapeMesh& m, glm::vec3 corner, glm::vec3 du, glm::vec3 dv, const glm::vec2 (&uv)[4] = kQuadUv) {
    const auto base = static_cast<std::uint32_t>(m.positions.size());
    const glm::vec3 n = glm::normalize(glm::cross(du, dv));
    const glm::vec3 p[4] = {corner, corner + du, corner + du + dv, corner + dv};
    for (int i = 0; i < 4; ++i) {
        m.positions.push_back(p[i]);
        m.normals.push_back(n);
        m.uvs.push_back(uv[i]);
    }
    m.triangles.emplace_back(base, base + 1, base + 2);
    m.triangles.emplace_back(base, base + 2, base + 3);
}

ShapeMesh rectangle() {
    ShapeMesh m;
    quad(m, {-1, -1, 0}, {2, 0, 0}, {0, 2, 0}, kRectangleUv);
    return m;
}

ShapeMesh cube() {
    ShapeMesh m;
    for (int axis = 0; axis < 3; ++axis) {
        for (float side : {-1.0f, 1.0f}) {
            glm::vec3 n(0.0f), u(0.0f), v(0.0f);
            n[axis] = side;
            u[(axis + 1) % 3] = 2.0f;
            v[(axis + 2) % 3] = 2.0f;
            if (side < 0.0f) std::swap(u, v);  // counter-clockwise seen from outside
            quad(m, n - 0.5f * (u + v), u, v);
        }
    }
    return m;
}

ShapeMesh disk() {
    const int n = circleSegments(kTessellationError);
    // Radius of the n-gon with the disk's area pi.
    const float r = std::sqrt(kPi / (0.5f * n * std::sin(2.0f * kPi / n)));
    ShapeMesh m;
    m.positions.push_back({0, 0, 0});
    m.normals.push_back({0, 0, 1});
    m.uvs.push_back({0.5f, 0.5f});
    for (int i = 0; i < n; ++i) {
        const float a = 2.0f * kPi * i / n;
        m.positions.push_back({r * std::cos(a), r * std::sin(a), 0});
        m.normals.push_back({0, 0, 1});
        m.uvs.push_back({0.5f + 0.5f * std::cos(a), 0.5f - 0.5f * std::sin(a)});
        m.triangles.emplace_back(0, 1 + i, 1 + (i + 1) % n);
    }
    return m;
}

ShapeMesh sphere(const Element& shape) {
    const glm::vec3 centre = pointProperty(shape, "center", glm::vec3(0.0f));
    const float radius = floatProperty(shape, "radius", 1.0f);
    if (!(radius > 0.0f)) fail(shape, fmt::format("sphere radius {} is not positive", radius));
    // A triangle's worst point is its circumcentre, at angular distance step / sqrt(2) from the
    // corners of a (step x step) cell: 1 - cos(step / sqrt(2)) <= error.
    const double step = std::sqrt(2.0) * std::acos(1.0 - static_cast<double>(kTessellationError));
    const int around = std::max(8, static_cast<int>(std::ceil(2.0 * std::numbers::pi / step)));
    const int rings = std::max(4, (around + 1) / 2);
    ShapeMesh m;
    for (int j = 0; j <= rings; ++j) {
        const float theta = kPi * j / rings;
        for (int i = 0; i <= around; ++i) {
            const float phi = 2.0f * kPi * i / around;
            // The poles exactly (sin(pi) is not 0 in float): their slivers must be degenerate and dropped.
            const float ring = j == 0 || j == rings ? 0.0f : std::sin(theta);
            const glm::vec3 d(ring * std::cos(phi), ring * std::sin(phi), j == 0 ? 1.0f : j == rings ? -1.0f : std::cos(theta));
            m.positions.push_back(centre + radius * d);
            m.normals.push_back(d);
            m.uvs.push_back({static_cast<float>(i) / around, static_cast<float>(j) / rings});
        }
    }
    const auto at = [&](int i, int j) { return static_cast<std::uint32_t>(j * (around + 1) + i); };
    for (int j = 0; j < rings; ++j) {
        for (int i = 0; i < around; ++i) {
            // Outward winding; at the poles one half of each cell is a point, and left out.
            if (j + 1 < rings) m.triangles.emplace_back(at(i, j), at(i, j + 1), at(i + 1, j + 1));
            if (j > 0) m.triangles.emplace_back(at(i, j), at(i + 1, j + 1), at(i + 1, j));
        }
    }
    return m;
}


// Mitsuba's cylinder: an open tube (no caps) of the given radius from p0 to p1, normals outward,
// u around the axis and v along it. Straight along the axis, so one ring of quads is exact there.
ShapeMesh cylinder(const Element& shape) {
    const glm::vec3 p0 = pointProperty(shape, "p0", glm::vec3(0.0f));
    const glm::vec3 p1 = pointProperty(shape, "p1", glm::vec3(0.0f, 0.0f, 1.0f));
    const float radius = floatProperty(shape, "radius", 1.0f);
    if (!(radius > 0.0f) || !std::isfinite(radius)) fail(shape, fmt::format("cylinder radius {} is not positive", radius));
    const glm::vec3 axis = p1 - p0;
    const float length = glm::length(axis);
    if (!(length > 0.0f) || !std::isfinite(length)) fail(shape, "cylinder p0 and p1 coincide");
    const glm::vec3 w = axis / length;
    // Any unit vector across the axis; the branch keeps it away from parallel to w.
    const glm::vec3 u = glm::normalize(std::abs(w.x) > 0.9f ? glm::cross(w, glm::vec3(0, 1, 0)) : glm::cross(w, glm::vec3(1, 0, 0)));
    const glm::vec3 v = glm::cross(w, u);
    // The segment count bounds the chord's sagitta; the n-gon's vertices lie on the true circle.
    const int around = circleSegments(kTessellationError);
    ShapeMesh m;
    for (int end = 0; end < 2; ++end) {
        for (int i = 0; i <= around; ++i) {
            const float phi = 2.0f * kPi * i / around;
            const glm::vec3 d = std::cos(phi) * u + std::sin(phi) * v;
            m.positions.push_back((end == 0 ? p0 : p1) + radius * d);
            m.normals.push_back(d);
            m.uvs.push_back({static_cast<float>(i) / around, static_cast<float>(end)});
        }
    }
    const auto at = [&](int i, int end) { return static_cast<std::uint32_t>(end * (around + 1) + i); };
    for (int i = 0; i < around; ++i) {
        // Counter-clockwise from outside: (u, v, w) is right-handed, so tangent x axis points out.
        m.triangles.emplace_back(at(i, 0), at(i + 1, 0), at(i + 1, 1));
        m.triangles.emplace_back(at(i, 0), at(i + 1, 1), at(i, 1));
    }
    return m;
}

}  // namespace

int circleSegments(float relativeError) {
    const double e = std::clamp(static_cast<double>(relativeError), 1e-7, 0.5);
    return std::max(8, static_cast<int>(std::ceil(std::numbers::pi / std::acos(1.0 - e))));
}

ShapeMesh shapeGeometry(const Element& shape, Warnings&) {
    const std::string type = shape.type();
    if (type == "obj") return objMesh(shape);
    if (type == "ply") return plyMesh(shape);
    if (type == "serialized") return serializedMesh(shape);
    if (type == "rectangle") return rectangle();
    if (type == "cube") return cube();
    if (type == "disk") return disk();
    if (type == "sphere") return sphere(shape);
    if (type == "cylinder") return cylinder(shape);
    fail(shape, fmt::format("unknown shape type '{}' (supported: obj, ply, serialized, rectangle, cube, disk, sphere, cylinder, "
                            "shapegroup, instance)", type));
}

void appendShape(TriangleMesh& mesh, const ShapeMesh& shape, const glm::mat4& toWorld, bool flipNormals,
                 bool faceNormals, std::uint32_t material, std::uint32_t object, std::size_t& degenerate) {
    const glm::mat3 normalMatrix = glm::transpose(glm::inverse(glm::mat3(toWorld)));
    const bool mirrored = glm::determinant(glm::mat3(toWorld)) < 0.0f;
    const bool smooth = !faceNormals && shape.normals.size() == shape.positions.size();
    const bool hasUVs = shape.uvs.size() == shape.positions.size();
    if (hasUVs && mesh.uvs.size() < mesh.positions.size()) mesh.uvs.resize(mesh.positions.size(), glm::vec2(0.0f));
    for (const glm::uvec3& tri : shape.triangles) {
        glm::uvec3 t = tri;
        if (t.x >= shape.positions.size() || t.y >= shape.positions.size() || t.z >= shape.positions.size()) continue;
        if (mirrored != flipNormals) std::swap(t.y, t.z);  // the front stays on the side the shape's normals face
        glm::vec3 p[3];
        for (int k = 0; k < 3; ++k) p[k] = glm::vec3(toWorld * glm::vec4(shape.positions[t[k]], 1.0f));
        const glm::vec3 c = glm::cross(p[1] - p[0], p[2] - p[0]);
        const float len = glm::length(c);
        if (!(len > 0.0f) || !std::isfinite(len)) {
            ++degenerate;
            continue;
        }
        const auto base = static_cast<std::uint32_t>(mesh.positions.size());
        for (int k = 0; k < 3; ++k) {
            glm::vec3 n = c / len;
            if (smooth) {
                const glm::vec3 v = normalMatrix * shape.normals[t[k]];
                const float l = glm::length(v);
                if (l > 0.0f && std::isfinite(l)) n = (flipNormals ? -v : v) / l;
            }
            mesh.positions.push_back(p[k]);
            mesh.normals.push_back(n);
            if (hasUVs) mesh.uvs.push_back(shape.uvs[t[k]]);
            else if (!mesh.uvs.empty()) mesh.uvs.push_back(glm::vec2(0.0f));
        }
        mesh.triangles.emplace_back(base, base + 1, base + 2);
        mesh.materialIds.push_back(material);
        mesh.objectIds.push_back(object);
    }
}

}  // namespace aamap::mitsuba
