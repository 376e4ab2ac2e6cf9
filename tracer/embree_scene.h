#pragma once
// The Embree side of the tracer: one device, the merged mesh as one triangle geometry, and the
// per-triangle data that shading needs (kept here so the tracer does not depend on the Scene
// outliving it).
#include <cstdint>
#include <vector>

#include <embree3/rtcore.h>
#include <glm/vec3.hpp>

#include "scene/scene.h"

namespace aamap {

// What shading reads per material; precomputed so the hot path only multiplies.
struct ShadingMaterial {
    MaterialKind kind = MaterialKind::Diffuse;
    bool emissive = false;
    glm::vec3 kdOverPi{0.0f};  // Lambert BRDF
    glm::vec3 ke{0.0f};
};

struct Triangle {
    glm::vec3 v0, e1, e2;  // v1 = v0 + e1, v2 = v0 + e2
    glm::vec3 normal;      // unit geometric normal, cross(e1, e2): counter-clockwise is the front
    std::uint32_t material;
};

class EmbreeScene {
public:
    explicit EmbreeScene(const Scene& scene);  // validates the mesh (std::invalid_argument) and builds
    ~EmbreeScene();
    EmbreeScene(const EmbreeScene&) = delete;
    EmbreeScene& operator=(const EmbreeScene&) = delete;

    RTCScene handle() const { return scene_; }
    double buildSeconds() const { return buildSeconds_; }

    const Triangle& triangle(std::uint32_t id) const { return triangles_[id]; }
    std::size_t triangleCount() const { return triangles_.size(); }
    const ShadingMaterial& material(std::uint32_t id) const { return materials_[id]; }
    // Unit interpolated vertex normal at barycentrics (u, v); the geometric normal if the mesh has
    // no usable normals there.
    glm::vec3 shadingNormal(std::uint32_t id, float u, float v) const;

private:
    RTCDevice device_ = nullptr;
    RTCScene scene_ = nullptr;
    double buildSeconds_ = 0.0;
    std::vector<Triangle> triangles_;
    std::vector<ShadingMaterial> materials_;
    std::vector<glm::vec3> vertexNormals_;  // 3 per triangle, empty without normals
};

}  // namespace aamap
