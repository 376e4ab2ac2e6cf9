#pragma once
// Which side of a triangle is its front. Emission is one-sided and glass tells entering from
// leaving by the side a ray hits, so the front must be the side a scene's author meant. Where a
// mesh has vertex normals, that is the side they point to (Mitsuba and pbrt orient a triangle by
// its shading normals); the winding only decides for meshes without normals. Exporters do write
// triangles whose winding disagrees with their normals (tessellated rectangles, mirrored
// transforms), so the loaders' meshes are made consistent once, here, and every consumer (tracer,
// Snapshot, light sampling) may then take cross(e1, e2) as the front.
#include <cstddef>

#include "scene/scene.h"

namespace aamap {

// Reverses the winding of each triangle whose face normal points away from the sum of its three
// vertex normals (a tie, or a degenerate triangle, stays as it is). Returns how many were
// reversed. No-op for meshes without per-vertex normals.
std::size_t orientTrianglesToNormals(TriangleMesh& mesh);

}  // namespace aamap
