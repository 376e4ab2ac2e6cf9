#include "scene/light_file.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <vector>

#include <fmt/format.h>
#include <glm/geometric.hpp>
#include <glm/mat3x3.hpp>
#include <glm/matrix.hpp>
#include <glm/trigonometric.hpp>

#include "core/error.h"
#include "scene/environment_map.h"
#include "scene/lights.h"
#include "scene/scene.h"

namespace aamap {
namespace {

constexpr double kPi = 3.14159265358979323846;

glm::dvec3 toDvec3(const std::array<double, 3>& a) { return {a[0], a[1], a[2]}; }

glm::dvec3 unit(const std::array<double, 3>& a, const LightSpec& light, const char* what) {
    const glm::dvec3 v = toDvec3(a);
    const double len = glm::length(v);
    if (!(len > 0.0) || !std::isfinite(len))
        throw std::invalid_argument(fmt::format("light '{}': {} must be a non-zero vector", light.name, what));
    return v / len;
}

// A unit vector perpendicular to n: `up` made orthogonal to it, or any one if up is zero or
// parallel to n.
glm::dvec3 perpendicular(const glm::dvec3& n, const glm::dvec3& up) {
    glm::dvec3 v = up - n * glm::dot(n, up);
    if (glm::length(v) > 1e-9 * std::max(glm::length(up), 1e-300)) return glm::normalize(v);
    const glm::dvec3 a = std::abs(n.x) < 0.9 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0);
    return glm::normalize(a - n * glm::dot(n, a));
}

// Appends a fan or strip of triangles with one new emissive material and one new object, and
// registers it as an area light of the given radiance. Front faces (counter-clockwise) face n.
void addEmitter(Scene& scene, const std::string& name, const std::vector<glm::dvec3>& points,
                const std::vector<glm::uvec3>& triangles, const glm::dvec3& n, const glm::vec3& radiance) {
    TriangleMesh& mesh = scene.mesh;
    const bool withNormals = mesh.normals.size() == mesh.positions.size();
    const bool withUvs = !mesh.uvs.empty() && mesh.uvs.size() == mesh.positions.size();
    const bool withObjects = mesh.objectIds.size() == mesh.triangles.size();
    std::uint32_t object = 0;
    for (std::uint32_t id : mesh.objectIds) object = std::max(object, id + 1);

    Material m;
    m.name = "light:" + name;
    m.kd = glm::vec3(0.0f);  // the emitter's body reflects nothing
    m.ke = radiance;
    scene.materials.push_back(m);
    const auto material = static_cast<std::uint32_t>(scene.materials.size() - 1);

    const auto base = static_cast<std::uint32_t>(mesh.positions.size());
    for (const glm::dvec3& p : points) {
        mesh.positions.push_back(glm::vec3(p));
        if (withNormals) mesh.normals.push_back(glm::vec3(n));
        if (withUvs) mesh.uvs.push_back(glm::vec2(0.0f));
    }
    AreaLight light;
    light.name = name;
    light.radiance = radiance;
    for (const glm::uvec3& t : triangles) {
        light.triangles.push_back(static_cast<std::uint32_t>(mesh.triangles.size()));
        mesh.triangles.push_back(t + glm::uvec3(base));
        mesh.materialIds.push_back(material);
        if (withObjects) mesh.objectIds.push_back(object);
        light.area += triangleArea(mesh, light.triangles.back());
    }
    scene.areaLights.push_back(std::move(light));
}

glm::vec3 toVec3(const glm::dvec3& v) { return glm::vec3(v); }

}  // namespace

double diskRimRadius(double radius, int segments) {
    // A regular N-gon of circumradius R has area (N / 2) R^2 sin(2 pi / N); set it to pi r^2.
    const double n = std::max(segments, 3);
    return radius * std::sqrt(2.0 * kPi / (n * std::sin(2.0 * kPi / n)));
}

glm::mat3 environmentToLocal(const std::array<double, 3>& up, double rotationDeg) {
    const glm::dvec3 u = toDvec3(up);
    const glm::dvec3 y = glm::length(u) > 0.0 ? glm::normalize(u) : glm::dvec3(0, 1, 0);
    const glm::dvec3 z = perpendicular(y, glm::dvec3(0, 0, 1));  // +Z stays +Z for the default up
    const glm::dvec3 x = glm::cross(y, z);
    const double a = glm::radians(rotationDeg), c = std::cos(a), s = std::sin(a);
    // World from map: the up frame after a right-handed turn by `a` about its Y.
    const glm::dmat3 frame(x, y, z);
    const glm::dmat3 turn(glm::dvec3(c, 0, -s), glm::dvec3(0, 1, 0), glm::dvec3(s, 0, c));
    return glm::mat3(glm::transpose(frame * turn));
}

void addLights(Scene& scene, std::span<const LightSpec> lights) {
    for (const LightSpec& spec : lights) {
        const glm::dvec3 position = toDvec3(spec.position);
        const glm::dvec3 emission = toDvec3(spec.emission);
        switch (spec.type) {
            case LightType::Point:
            case LightType::Spot: {
                PointLight p;
                p.name = spec.name;
                p.position = toVec3(position);
                if (spec.type == LightType::Point) {
                    if (glm::length(toDvec3(spec.normal)) > 0.0) p.normal = toVec3(unit(spec.normal, spec, "normal"));
                } else {
                    if (!(spec.innerAngle >= 0.0 && spec.innerAngle <= spec.outerAngle && spec.outerAngle > 0.0 &&
                          spec.outerAngle <= 180.0))
                        throw std::invalid_argument(fmt::format("light '{}': spot angles need 0 <= inner <= outer <= 180, "
                                                                "outer > 0", spec.name));
                    p.spotDirection = toVec3(unit(spec.direction, spec, "direction"));
                    p.cosInner = static_cast<float>(std::cos(glm::radians(spec.innerAngle)));
                    p.cosOuter = static_cast<float>(std::cos(glm::radians(spec.outerAngle)));
                }
                // Power: spread over the solid angle the profile integrates to.
                p.intensity = toVec3(spec.unit == EmissionUnit::Power ? emission / emittingSolidAngle(p) : emission);
                scene.pointLights.push_back(std::move(p));
                break;
            }
            case LightType::Quad: {
                const glm::dvec3 n = unit(spec.normal, spec, "normal");
                const glm::dvec3 v = perpendicular(n, toDvec3(spec.up));
                const glm::dvec3 u = glm::cross(v, n);  // cross(u, v) = n: counter-clockwise seen from the front
                const double w = spec.size[0], h = spec.size[1];
                if (!(w > 0.0 && h > 0.0))
                    throw std::invalid_argument(fmt::format("light '{}': quad size must be positive", spec.name));
                const glm::dvec3 a = 0.5 * w * u, b = 0.5 * h * v;
                const double area = w * h;
                const glm::dvec3 radiance = spec.unit == EmissionUnit::Power ? emission / (kPi * area) : emission;
                addEmitter(scene, spec.name, {position - a - b, position + a - b, position + a + b, position - a + b},
                           {{0, 1, 2}, {0, 2, 3}}, n, toVec3(radiance));
                break;
            }
            case LightType::Disk: {
                const glm::dvec3 n = unit(spec.normal, spec, "normal");
                const glm::dvec3 v = perpendicular(n, glm::dvec3(0.0));
                const glm::dvec3 u = glm::cross(v, n);
                if (!(spec.radius > 0.0))
                    throw std::invalid_argument(fmt::format("light '{}': disk radius must be positive", spec.name));
                const int segments = std::max(spec.segments, 3);
                // The fan's rim is pushed out so that its area is pi r^2 exactly (diskRimRadius).
                const double rim = diskRimRadius(spec.radius, segments);
                const double area = kPi * spec.radius * spec.radius;
                std::vector<glm::dvec3> points{position};
                std::vector<glm::uvec3> triangles;
                for (int i = 0; i < segments; ++i) {
                    const double phi = 2.0 * kPi * i / segments;
                    points.push_back(position + rim * (std::cos(phi) * u + std::sin(phi) * v));
                    triangles.push_back({0u, static_cast<unsigned>(1 + i), static_cast<unsigned>(1 + (i + 1) % segments)});
                }
                const glm::dvec3 radiance = spec.unit == EmissionUnit::Power ? emission / (kPi * area) : emission;
                addEmitter(scene, spec.name, points, triangles, n, toVec3(radiance));
                break;
            }
            case LightType::Directional: {
                DirectionalLight d;
                d.name = spec.name;
                d.direction = toVec3(unit(spec.direction, spec, "direction"));
                d.irradiance = toVec3(emission);
                scene.directionalLights.push_back(std::move(d));
                break;
            }
            case LightType::Environment: {
                if (scene.environment)
                    throw std::invalid_argument(fmt::format("light '{}': the scene already has an environment ('{}'); "
                                                            "a scene has at most one", spec.name, scene.environment->name));
                EnvironmentLight env;
                env.name = spec.name;
                if (spec.map.empty()) {
                    env.scale = toVec3(emission);
                } else {
                    env.scale = glm::vec3(static_cast<float>(spec.scale));
                    std::string error;
                    if (!loadEnvironmentMap(spec.map, env, error))
                        throw InputError(spec.map, fmt::format("light '{}': {}", spec.name, error));
                    env.toLocal = environmentToLocal(spec.up, spec.rotation);
                }
                scene.environment = std::move(env);
                break;
            }
        }
    }
}

}  // namespace aamap
