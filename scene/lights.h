#pragma once
// Light helpers shared by the loaders and the Snapshot: grouping emissive triangles into area
// lights, point-light approximations of area lights (the paper uses 5 points per area light),
// and scene bounds.
#include <algorithm>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

#include "scene/scene.h"

namespace aamap {

struct Bounds {
    glm::vec3 lo{0.0f}, hi{0.0f};
    glm::vec3 centre() const { return 0.5f * (lo + hi); }
    glm::vec3 extent() const { return hi - lo; }
};

// A spot light's angular falloff for a direction at cosine `cosAngle` from its axis: 1 inside the
// inner cone, 0 outside the outer one, and between them t^2 with t linear in the cosine,
// t = (cosAngle - cosOuter) / (cosInner - cosOuter): the falloff glTF's KHR_lights_punctual
// recommends. Equal cones give a hard edge. Mirrored in glsl/lights.glsl (spotFalloff).
inline float spotFalloff(float cosAngle, float cosInner, float cosOuter) {
    if (cosAngle >= cosInner) return 1.0f;
    if (cosAngle <= cosOuter) return 0.0f;
    const float t = (cosAngle - cosOuter) / (cosInner - cosOuter);
    return t * t;
}

// The angular factor of a point light's intensity towards unit direction `out` (from the light):
// 1 (isotropic), max(0, cos) about `normal` (lobe), or the spot falloff about `spotDirection`.
// Inline (as the next one): the tracer uses them without linking the scene library.
inline float emissionFactor(const PointLight& light, const glm::vec3& out) {
    if (glm::dot(light.normal, light.normal) > 0.0f) return std::max(0.0f, glm::dot(light.normal, out));
    if (glm::dot(light.spotDirection, light.spotDirection) > 0.0f)
        return spotFalloff(glm::dot(light.spotDirection, out), light.cosInner, light.cosOuter);
    return 1.0f;
}

// Solid angle the intensity is spread over: emitted power = intensity * this (sr). 4 pi for an
// isotropic light, pi for a cosine lobe, 2 pi ((1 - cosInner) + (cosInner - cosOuter) / 3) for a
// spot: 2 pi times the integral of spotFalloff over the cosine, 1 on [cosInner, 1] and t^2 (t
// linear in the cosine) on [cosOuter, cosInner], which integrates to (cosInner - cosOuter) / 3.
inline double emittingSolidAngle(const PointLight& light) {
    constexpr double kPi = 3.14159265358979323846;
    if (glm::dot(light.normal, light.normal) > 0.0f) return kPi;
    if (glm::dot(light.spotDirection, light.spotDirection) > 0.0f) {
        const double ci = light.cosInner, co = std::min(light.cosOuter, light.cosInner);
        return 2.0 * kPi * ((1.0 - ci) + (ci - co) / 3.0);
    }
    return 4.0 * kPi;
}

// Axis-aligned bounds of the mesh positions; {0,0} for an empty mesh. Point lights are not
// included: they may sit far outside the geometry and would distort scale-dependent epsilons.
Bounds sceneBounds(const Scene& scene);

// Area and unit geometric normal (from the winding, counter-clockwise = front) of one triangle.
float triangleArea(const TriangleMesh& mesh, std::uint32_t triangle);
glm::vec3 triangleNormal(const TriangleMesh& mesh, std::uint32_t triangle);

// Groups the triangles whose material has Ke > 0 into one AreaLight per (objectId, materialId),
// in order of first appearance. Names are "<object name>/<material name>" when objectNames covers
// the objectId, else "object<id>/<material name>". Zero-area triangles are left out.
std::vector<AreaLight> buildAreaLights(const Scene& scene, std::span<const std::string> objectNames = {});

// k deterministic, stratified points on the light (k >= 1): the k strata of the area CDF pick
// the triangles, and within a triangle the points follow the triangular van der Corput sequence
// (Basu & Owen 2015), so one point is the centroid. Each is a cosine-lobe PointLight along its
// triangle's normal with intensity radiance * area / k, so the sum of intensities is
// radiance * area (the light's on-axis intensity). Throws std::invalid_argument for k < 1.
std::vector<PointLight> approximateAreaLight(const Scene& scene, const AreaLight& light, int k);

// The scene's lights in one phrase for the log: "2 area, 1 point and 1 directional lights and an
// environment map", "no lights".
std::string describeLights(const Scene& scene);

// A warning for a scene without any light (area, point, directional or environment): its renders
// show emitters only and the aamap has nothing to find. Every command that renders says it.
std::optional<std::string> unlitSceneWarning(const Scene& scene);

}  // namespace aamap
