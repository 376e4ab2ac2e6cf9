#pragma once
// The scene's mirrors as planes: the MaterialKind::Mirror triangles of one object and one material
// form a mirror group, which findPlanarMirrors splits into planes (a wall mirror with its bevel
// strips, the faces of a mirrored box); each plane is a PlanarMirror. A group of many small planes
// is a tessellated curved surface: its triangles outside the planes it keeps are a CurvedMirror.
// Pure geometry on the CPU: the Snapshot's mirror passes (passes/mirror.h, passes/mirror_probes.h)
// decide per view which of them to reflect and how.
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include <glm/mat4x4.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include "scene/scene.h"

namespace aamap {

// How a mirror group splits into planes. Triangles share a plane when their normals are within
// kPlaneNormalCos of each other (about 0.8 degrees: far below a bevel's or a box edge's angle,
// far above float noise in a modelled flat face) and their vertices within kPlaneOffsetTolerance
// x the scene's diagonal of the plane (either orientation: both faces of a thin mirror are one);
// a smaller plane whose vertices all lie in a larger one is part of it (a sliver's tilted normal).
inline constexpr float kPlaneNormalCos = 0.9999f;
inline constexpr float kPlaneOffsetTolerance = 1e-4f;
// A group of at most kMaxPlanesPerGroup planes is faceted on purpose (a framed mirror: 5, a box:
// 6), so every plane is a mirror. A group of more planes is a tessellated curved surface, whose
// facets hold a small share of its area each (a 12 x 6 sphere: under 3%): only planes holding at
// least kMinPlaneAreaFraction of the group's area are mirrors there (the flat cap of a cylinder).
inline constexpr std::size_t kMaxPlanesPerGroup = 8;
inline constexpr float kMinPlaneAreaFraction = 0.1f;

struct PlanarMirror {
    std::string name;                      // "object/material", plus " plane k" when its group has several
    glm::vec3 normal{0.0f};                // unit, the plane is dot(normal, p) = offset
    float offset = 0.0f;
    std::vector<std::uint32_t> triangles;  // indices into TriangleMesh::triangles, ascending
    glm::vec3 reflectance{1.0f};           // the tracer's ks for this material (after energy scaling)
};

// The triangles of one mirror group that lie in no accepted plane: reflected through an
// environment probe (passes/mirror_probes.h), not a planar view.
struct CurvedMirror {
    std::string group;           // "object/material"
    std::size_t planes = 0;      // of the same group that are PlanarMirrors
    std::vector<std::uint32_t> triangles;  // the curved ones, ascending
    glm::vec3 reflectance{1.0f};             // as PlanarMirror::reflectance
    std::string describe() const;  // "object 3/m: 2 planes reflected, 40 triangles curved"
};

struct MirrorGroups {
    std::vector<PlanarMirror> planar;  // per group (by object, then material), largest plane first
    std::vector<CurvedMirror> curved;  // the groups with curved triangles, in the same order
};

// Splits the scene's mirror triangles per object and material, then each group into planes.
MirrorGroups findPlanarMirrors(const Scene& scene);

// Snapshot pixels that `triangles` (of `positions`) cover under `viewProj` (w the view depth),
// each clipped to the frustum and to w >= nearPlane, in a `pixels`-sized image. Overlaps count
// twice and occlusion is ignored: an over-estimate, so a plane that shows is never skipped for
// being small. Indices out of range count nothing. ndcBounds (if given) gets the clipped
// triangles' NDC bounding box (min x, min y, max x, max y; empty: min > max).
double projectedPixels(const std::vector<glm::vec3>& positions, const std::vector<glm::uvec3>& triangles,
                       const std::vector<std::uint32_t>& which, const glm::mat4& viewProj, float nearPlane,
                       glm::uvec2 pixels, glm::vec4* ndcBounds = nullptr);

// Diffuse albedo and reflectance of a Mirror material as the tracer splits them
// (tracer/embree_scene.cpp convertMaterial): ks 0 means a perfect mirror, and kd + ks <= 1.
void mirrorAlbedos(const Material& m, glm::vec3& kd, glm::vec3& reflectance);

// Reflection in the plane dot(n, p) = d (n unit).
glm::mat4 reflectionMatrix(glm::vec3 n, float d);

}  // namespace aamap
