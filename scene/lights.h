#pragma once
// Light helpers shared by the loaders and the Snapshot: grouping emissive triangles into area
// lights, point-light approximations of area lights (the paper uses 5 points per area light),
// and scene bounds.
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "scene/scene.h"

namespace aamap {

struct Bounds {
    glm::vec3 lo{0.0f}, hi{0.0f};
    glm::vec3 centre() const { return 0.5f * (lo + hi); }
    glm::vec3 extent() const { return hi - lo; }
};

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

}  // namespace aamap
