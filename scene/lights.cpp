#include "scene/lights.h"

#include <algorithm>
#include <map>
#include <stdexcept>
#include <utility>

#include <fmt/format.h>
#include <glm/common.hpp>
#include <glm/geometric.hpp>

namespace aamap {

Bounds sceneBounds(const Scene& scene) {
    const auto& positions = scene.mesh.positions;
    if (positions.empty()) return {};
    Bounds b{positions.front(), positions.front()};
    for (const glm::vec3& p : positions) {
        b.lo = glm::min(b.lo, p);
        b.hi = glm::max(b.hi, p);
    }
    return b;
}

namespace {

glm::vec3 crossOf(const TriangleMesh& mesh, std::uint32_t triangle) {
    const glm::uvec3 t = mesh.triangles[triangle];
    const glm::vec3 a = mesh.positions[t.x];
    return glm::cross(mesh.positions[t.y] - a, mesh.positions[t.z] - a);
}

bool isEmissive(const Material& m) { return m.ke.x > 0.0f || m.ke.y > 0.0f || m.ke.z > 0.0f; }

// Centroid of the sub-triangle picked by the base-4 digits of `index` (least significant first):
// 0 = the middle (inverted) sub-triangle, 1..3 = the corner ones. Index 0 gives the centroid.
glm::vec3 triangularVanDerCorput(glm::vec3 a, glm::vec3 b, glm::vec3 c, std::uint32_t index) {
    while (index != 0) {
        const glm::vec3 ab = 0.5f * (a + b), bc = 0.5f * (b + c), ca = 0.5f * (c + a);
        switch (index & 3u) {
            case 0: a = bc; b = ca; c = ab; break;
            case 1: b = ab; c = ca; break;
            case 2: a = ab; c = bc; break;
            default: a = ca; b = bc; break;
        }
        index >>= 2;
    }
    return (a + b + c) / 3.0f;
}

}  // namespace

float triangleArea(const TriangleMesh& mesh, std::uint32_t triangle) {
    return 0.5f * glm::length(crossOf(mesh, triangle));
}

glm::vec3 triangleNormal(const TriangleMesh& mesh, std::uint32_t triangle) {
    const glm::vec3 n = crossOf(mesh, triangle);
    const float len = glm::length(n);
    return len > 0.0f ? n / len : glm::vec3(0.0f);
}

std::vector<AreaLight> buildAreaLights(const Scene& scene, std::span<const std::string> objectNames) {
    const TriangleMesh& mesh = scene.mesh;
    std::vector<AreaLight> lights;
    std::map<std::pair<std::uint32_t, std::uint32_t>, std::size_t> byKey;
    for (std::uint32_t t = 0; t < mesh.triangles.size(); ++t) {
        const std::uint32_t materialId = mesh.materialIds[t];
        if (materialId >= scene.materials.size() || !isEmissive(scene.materials[materialId])) continue;
        const float area = triangleArea(mesh, t);
        if (!(area > 0.0f)) continue;
        const std::uint32_t objectId = t < mesh.objectIds.size() ? mesh.objectIds[t] : 0;
        auto [it, inserted] = byKey.try_emplace({objectId, materialId}, lights.size());
        if (inserted) {
            const Material& m = scene.materials[materialId];
            const std::string object =
                objectId < objectNames.size() ? objectNames[objectId] : fmt::format("object{}", objectId);
            lights.push_back({fmt::format("{}/{}", object, m.name), {}, m.ke, 0.0f});
        }
        AreaLight& light = lights[it->second];
        light.triangles.push_back(t);
        light.area += area;
    }
    return lights;
}

std::vector<PointLight> approximateAreaLight(const Scene& scene, const AreaLight& light, int k) {
    if (k < 1) throw std::invalid_argument("approximateAreaLight: k must be at least 1");
    const TriangleMesh& mesh = scene.mesh;
    std::vector<float> areas;
    double total = 0.0;
    for (std::uint32_t t : light.triangles) {
        areas.push_back(triangleArea(mesh, t));
        total += areas.back();
    }
    std::vector<PointLight> points;
    if (!(total > 0.0)) return points;

    // Stratum j (centre (j + 0.5) / k of the area CDF) goes to the triangle that holds it.
    std::vector<std::uint32_t> perTriangle(areas.size(), 0);
    double cdfEnd = 0.0;
    std::size_t tri = 0;
    for (int j = 0; j < k; ++j) {
        const double u = (j + 0.5) / k * total;
        while (tri + 1 < areas.size() && u >= cdfEnd + areas[tri]) cdfEnd += areas[tri++];
        ++perTriangle[tri];
    }
    // The exact light area (not a stale light.area) keeps sum(intensity) == radiance * area.
    const glm::vec3 intensity = light.radiance * static_cast<float>(total / k);
    for (std::size_t i = 0; i < areas.size(); ++i) {
        const glm::uvec3 t = mesh.triangles[light.triangles[i]];
        const glm::vec3 normal = triangleNormal(mesh, light.triangles[i]);
        for (std::uint32_t s = 0; s < perTriangle[i]; ++s) {
            PointLight p;
            p.name = fmt::format("{}#{}", light.name, points.size());
            p.position = triangularVanDerCorput(mesh.positions[t.x], mesh.positions[t.y], mesh.positions[t.z], s);
            p.intensity = intensity;
            p.normal = normal;
            points.push_back(std::move(p));
        }
    }
    return points;
}

std::string describeLights(const Scene& scene) {
    std::vector<std::string> kinds;
    const auto add = [&](std::size_t n, const char* kind) {
        if (n > 0) kinds.push_back(fmt::format("{} {}", n, kind));
    };
    add(scene.areaLights.size(), "area");
    add(scene.pointLights.size(), "point");
    add(scene.directionalLights.size(), "directional");
    std::string text;
    for (std::size_t i = 0; i < kinds.size(); ++i)
        text += (i == 0 ? "" : i + 1 == kinds.size() ? " and " : ", ") + kinds[i];
    if (!text.empty()) text += kinds.size() == 1 && text.starts_with("1 ") ? " light" : " lights";
    if (scene.environment) text += text.empty() ? "an environment map" : " and an environment map";
    return text.empty() ? "no lights" : text;
}

std::optional<std::string> unlitSceneWarning(const Scene& scene) {
    if (!scene.areaLights.empty() || !scene.pointLights.empty() || !scene.directionalLights.empty() || scene.environment)
        return std::nullopt;
    return fmt::format("scene '{}' has no lights: the renders show emitters only and the aamap has nothing to find",
                       scene.name);
}

}  // namespace aamap
