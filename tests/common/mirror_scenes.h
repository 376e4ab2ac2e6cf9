#pragma once
// Mirror scenes shared by the mirror-plane tests (tests/scene) and the Snapshot's mirror tests
// (tests/gpu): a mirror facing an emissive rectangle, a framed mirror, a mirrored cube.
#include <cstdint>
#include <initializer_list>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

#include "scene/scene.h"

namespace aamap::test {

struct Rect {
    float x0, x1, y0, y1;
    bool inside(glm::vec3 p, float margin) const {
        return p.x > x0 + margin && p.x < x1 - margin && p.y > y0 + margin && p.y < y1 - margin;
    }
    bool outside(glm::vec3 p, float margin) const {
        return p.x < x0 - margin || p.x > x1 + margin || p.y < y0 - margin || p.y > y1 + margin;
    }
};

inline const Rect kMirror{-2.0f, 2.0f, -2.0f, 2.0f};  // at z = 0, facing +z
inline const Rect kObject{0.3f, 1.5f, 0.2f, 1.0f};    // at z = 2, facing -z (towards the mirror)
inline const glm::vec3 kEmission(2.0f, 0.5f, 0.25f);
inline const glm::vec3 kReflectance(0.5f, 0.5f, 0.5f);

inline void addRect(Scene& s, const Rect& r, float z, bool facingPlusZ, std::uint32_t material) {
    const auto b = static_cast<std::uint32_t>(s.mesh.positions.size());
    s.mesh.positions.insert(s.mesh.positions.end(), {{r.x0, r.y0, z}, {r.x1, r.y0, z}, {r.x1, r.y1, z}, {r.x0, r.y1, z}});
    s.mesh.normals.insert(s.mesh.normals.end(), 4, glm::vec3(0, 0, facingPlusZ ? 1.0f : -1.0f));
    if (facingPlusZ)
        s.mesh.triangles.insert(s.mesh.triangles.end(), {{b, b + 1, b + 2}, {b, b + 2, b + 3}});
    else
        s.mesh.triangles.insert(s.mesh.triangles.end(), {{b, b + 2, b + 1}, {b, b + 3, b + 2}});
    s.mesh.materialIds.insert(s.mesh.materialIds.end(), 2, material);
    s.mesh.objectIds.insert(s.mesh.objectIds.end(), 2, material);
}

// A mirror (kd 0, ks 0.5) and an emissive rectangle facing it; no lights at all.
inline Scene mirrorScene(MaterialKind mirrorKind) {
    Scene s;
    Material mirror;
    mirror.name = "mirror";
    mirror.kind = mirrorKind;
    mirror.kd = glm::vec3(0.0f);
    mirror.ks = kReflectance;
    Material glow;
    glow.name = "glow";
    glow.kd = glm::vec3(0.0f);
    glow.ke = kEmission;
    s.materials = {mirror, glow};
    addRect(s, kMirror, 0.0f, true, 0);
    addRect(s, kObject, 2.0f, false, 1);
    return s;
}

// A point light between the mirror and the object.
inline void addBulb(Scene& scene) {
    PointLight light;
    light.name = "bulb";
    light.position = {0.9f, 0.6f, 1.0f};
    light.intensity = glm::vec3(5.0f);
    scene.pointLights.push_back(light);
}

// A convex planar polygon as a triangle fan, one object and material.
inline void addPolygon(Scene& s, std::initializer_list<glm::vec3> corners, std::uint32_t material, std::uint32_t object) {
    const auto b = static_cast<std::uint32_t>(s.mesh.positions.size());
    const std::vector<glm::vec3> c(corners);
    const glm::vec3 n = glm::normalize(glm::cross(c[1] - c[0], c[2] - c[0]));
    s.mesh.positions.insert(s.mesh.positions.end(), c.begin(), c.end());
    s.mesh.normals.insert(s.mesh.normals.end(), c.size(), n);
    for (std::uint32_t k = 1; k + 1 < c.size(); ++k) {
        s.mesh.triangles.push_back({b, b + k, b + k + 1});
        s.mesh.materialIds.push_back(material);
        s.mesh.objectIds.push_back(object);
    }
}

// mirrorScene's mirror in a frame: four bevel strips 0.1 wide, at 45 degrees back from its edges,
// of the mirror's object and material.
inline Scene framedMirrorScene() {
    Scene s = mirrorScene(MaterialKind::Mirror);
    const float a = 2.0f, b = 2.1f, back = -0.1f;
    addPolygon(s, {{a, -a, 0}, {b, -b, back}, {b, b, back}, {a, a, 0}}, 0, 0);
    addPolygon(s, {{-a, a, 0}, {-b, b, back}, {-b, -b, back}, {-a, -a, 0}}, 0, 0);
    addPolygon(s, {{a, a, 0}, {b, b, back}, {-b, b, back}, {-a, a, 0}}, 0, 0);
    addPolygon(s, {{-a, -a, 0}, {-b, -b, back}, {b, -b, back}, {a, -a, 0}}, 0, 0);
    return s;
}

// The unit cube [-1, 1]^3 as one mirror group: 6 faces of 2 triangles.
inline void addCube(Scene& s, std::uint32_t material, std::uint32_t object) {
    for (int axis = 0; axis < 3; ++axis)
        for (const float side : {-1.0f, 1.0f}) {
            const int u = (axis + 1) % 3, v = (axis + 2) % 3;
            std::vector<glm::vec3> c(4, glm::vec3(0.0f));
            const float us[4] = {-1, 1, 1, -1}, vs[4] = {-1, -1, 1, 1};
            for (int k = 0; k < 4; ++k) {
                c[k][axis] = side;
                c[k][u] = us[k];
                c[k][v] = side > 0 ? vs[k] : -vs[k];
            }
            addPolygon(s, {c[0], c[1], c[2], c[3]}, material, object);
        }
}

}  // namespace aamap::test
