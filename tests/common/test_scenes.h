#pragma once
// Small scene pieces shared by the GPU tests: quads in a plane z = const facing +z, UV spheres, and a camera
// looking straight down -z, under which the plane z = 0 maps linearly onto the image.
#include <cmath>
#include <cstdint>

#include <glm/vec3.hpp>

#include "scene/scene.h"

namespace aamap::test {

// The quad [x0,x1] x [y0,y1] at height z, facing +z (two triangles), with `material` as both its
// material and its object id.
inline void addQuadZ(Scene& scene, float z, float x0, float x1, float y0, float y1, std::uint32_t material) {
    const auto base = static_cast<std::uint32_t>(scene.mesh.positions.size());
    scene.mesh.positions.insert(scene.mesh.positions.end(), {{x0, y0, z}, {x1, y0, z}, {x1, y1, z}, {x0, y1, z}});
    scene.mesh.normals.insert(scene.mesh.normals.end(), 4, glm::vec3(0, 0, 1));
    scene.mesh.triangles.insert(scene.mesh.triangles.end(), {{base, base + 1, base + 2}, {base, base + 2, base + 3}});
    scene.mesh.materialIds.insert(scene.mesh.materialIds.end(), 2, material);
    scene.mesh.objectIds.insert(scene.mesh.objectIds.end(), 2, material);
}

// A UV sphere of `segments` x `rings` around `centre`, one object and material, normals outward.
inline void addSphere(Scene& s, glm::vec3 centre, float radius, int segments, int rings, std::uint32_t material,
               std::uint32_t object) {
    const auto b = static_cast<std::uint32_t>(s.mesh.positions.size());
    for (int r = 0; r <= rings; ++r)
        for (int k = 0; k <= segments; ++k) {
            const float theta = 3.14159265f * r / rings, phi = 6.28318531f * k / segments;
            const glm::vec3 n(std::sin(theta) * std::cos(phi), std::cos(theta), std::sin(theta) * std::sin(phi));
            s.mesh.positions.push_back(centre + radius * n);
            s.mesh.normals.push_back(n);
        }
    const auto at = [&](int r, int k) { return b + static_cast<std::uint32_t>(r * (segments + 1) + k); };
    for (int r = 0; r < rings; ++r)
        for (int k = 0; k < segments; ++k) {
            if (r > 0) s.mesh.triangles.push_back({at(r, k), at(r, k + 1), at(r + 1, k)});
            if (r + 1 < rings) s.mesh.triangles.push_back({at(r, k + 1), at(r + 1, k + 1), at(r + 1, k)});
        }
    const std::size_t added = s.mesh.triangles.size() - s.mesh.materialIds.size();
    s.mesh.materialIds.insert(s.mesh.materialIds.end(), added, material);
    s.mesh.objectIds.insert(s.mesh.objectIds.end(), added, object);
}

// A camera at `position` looking down -z, +y up on screen, square field of view.
inline View viewDownZ(glm::vec3 position, float fovDeg) {
    View view;
    view.position = position;
    view.direction = {0, 0, -1};
    view.up = {0, 1, 0};
    view.horizontalFovDeg = view.verticalFovDeg = fovDeg;
    return view;
}

}  // namespace aamap::test
