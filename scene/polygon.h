#pragma once
// Polygon triangulation for the loaders: OBJ faces may be quads or larger, convex or not.
#include <array>
#include <span>
#include <vector>

#include <glm/vec3.hpp>

namespace aamap {

// Triangles as indices into `points`, wound like the polygon. Convex quads split along the
// shorter diagonal; other polygons are ear-clipped in the plane of their Newell normal, falling
// back to a fan when that fails (self-intersecting or degenerate input).
std::vector<std::array<int, 3>> triangulatePolygon(std::span<const glm::vec3> points);

}  // namespace aamap
