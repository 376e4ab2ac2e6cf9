#include "tracer/embree_scene.h"

#include <chrono>
#include <cmath>
#include <numbers>
#include <stdexcept>

#include <fmt/format.h>
#include <glm/geometric.hpp>
#include <spdlog/spdlog.h>

#include "core/error.h"

namespace aamap {
namespace {

void onEmbreeError(void*, RTCError code, const char* message) {
    spdlog::error("embree error {}: {}", static_cast<int>(code), message ? message : "(no message)");
}

void validate(const Scene& scene) {
    const TriangleMesh& m = scene.mesh;
    const std::size_t triCount = m.triangles.size();
    if (m.materialIds.size() != triCount)
        throw std::invalid_argument(
            fmt::format("mesh has {} triangles but {} material ids", triCount, m.materialIds.size()));
    if (!m.normals.empty() && m.normals.size() != m.positions.size())
        throw std::invalid_argument(
            fmt::format("mesh has {} positions but {} normals", m.positions.size(), m.normals.size()));
    for (std::size_t t = 0; t < triCount; ++t) {
        const glm::uvec3& tri = m.triangles[t];
        if (tri.x >= m.positions.size() || tri.y >= m.positions.size() || tri.z >= m.positions.size())
            throw std::invalid_argument(fmt::format("triangle {} indexes past the {} positions", t, m.positions.size()));
        if (m.materialIds[t] >= scene.materials.size())
            throw std::invalid_argument(fmt::format("triangle {} has material {} of {}", t, m.materialIds[t],
                                                    scene.materials.size()));
    }
}

}  // namespace

EmbreeScene::EmbreeScene(const Scene& scene) {
    validate(scene);
    const TriangleMesh& m = scene.mesh;

    materials_.reserve(scene.materials.size());
    for (const Material& mat : scene.materials) {
        ShadingMaterial s;
        s.kind = mat.kind;
        s.kdOverPi = mat.kd * std::numbers::inv_pi_v<float>;
        s.ke = mat.ke;
        s.emissive = mat.ke.x > 0.0f || mat.ke.y > 0.0f || mat.ke.z > 0.0f;
        materials_.push_back(s);
    }

    triangles_.reserve(m.triangles.size());
    const bool hasNormals = !m.normals.empty();
    if (hasNormals) vertexNormals_.reserve(3 * m.triangles.size());
    for (std::size_t t = 0; t < m.triangles.size(); ++t) {
        const glm::uvec3& idx = m.triangles[t];
        Triangle tri;
        tri.v0 = m.positions[idx.x];
        tri.e1 = m.positions[idx.y] - tri.v0;
        tri.e2 = m.positions[idx.z] - tri.v0;
        const glm::vec3 n = glm::cross(tri.e1, tri.e2);
        const float len = glm::length(n);
        tri.normal = len > 0.0f ? n / len : glm::vec3(0.0f);  // degenerate: never hit by Embree
        tri.material = m.materialIds[t];
        triangles_.push_back(tri);
        if (hasNormals)
            for (int c = 0; c < 3; ++c) vertexNormals_.push_back(m.normals[idx[c]]);
    }

    device_ = rtcNewDevice(nullptr);
    if (!device_)
        throw EnvironmentError(fmt::format("cannot create an Embree device (error {})",
                                           static_cast<int>(rtcGetDeviceError(nullptr))));
    rtcSetDeviceErrorFunction(device_, onEmbreeError, nullptr);

    const auto start = std::chrono::steady_clock::now();
    scene_ = rtcNewScene(device_);
    rtcSetSceneBuildQuality(scene_, RTC_BUILD_QUALITY_HIGH);
    if (!m.triangles.empty()) {
        RTCGeometry geom = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_TRIANGLE);
        rtcSetGeometryBuildQuality(geom, RTC_BUILD_QUALITY_HIGH);
        // Copied, not shared: Embree reads vertices with 16-byte loads, so the buffer needs
        // padding past the last vertex that a std::vector<glm::vec3> does not promise.
        auto* vertices = static_cast<float*>(rtcSetNewGeometryBuffer(
            geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, sizeof(glm::vec3), m.positions.size()));
        auto* indices = static_cast<std::uint32_t*>(rtcSetNewGeometryBuffer(
            geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, sizeof(glm::uvec3), m.triangles.size()));
        if (!vertices || !indices) {
            rtcReleaseGeometry(geom);
            rtcReleaseScene(scene_);
            rtcReleaseDevice(device_);
            throw EnvironmentError("Embree could not allocate the geometry buffers");
        }
        for (std::size_t i = 0; i < m.positions.size(); ++i)
            for (int c = 0; c < 3; ++c) vertices[3 * i + c] = m.positions[i][c];
        for (std::size_t i = 0; i < m.triangles.size(); ++i)
            for (int c = 0; c < 3; ++c) indices[3 * i + c] = m.triangles[i][c];
        rtcCommitGeometry(geom);
        rtcAttachGeometry(scene_, geom);  // geometry id 0: primID indexes TriangleMesh::triangles
        rtcReleaseGeometry(geom);
    }
    rtcCommitScene(scene_);
    buildSeconds_ = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    spdlog::debug("embree: {} triangles, BVH built in {:.3f} s", triangles_.size(), buildSeconds_);
}

EmbreeScene::~EmbreeScene() {
    if (scene_) rtcReleaseScene(scene_);
    if (device_) rtcReleaseDevice(device_);
}

glm::vec3 EmbreeScene::shadingNormal(std::uint32_t id, float u, float v) const {
    const Triangle& tri = triangles_[id];
    if (vertexNormals_.empty()) return tri.normal;
    const glm::vec3* n = &vertexNormals_[3 * static_cast<std::size_t>(id)];
    const glm::vec3 interp = (1.0f - u - v) * n[0] + u * n[1] + v * n[2];
    const float len2 = glm::dot(interp, interp);
    if (!(len2 > 1e-12f) || !std::isfinite(len2)) return tri.normal;
    return interp / std::sqrt(len2);
}

}  // namespace aamap
