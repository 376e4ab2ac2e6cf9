#pragma once
#include <algorithm>
#include <cmath>

#include <glm/vec3.hpp>

namespace aamap {

// Offset for rays leaving a surface, in scene units. The hit point is rebuilt from the triangle's
// vertices and barycentrics, so its float error is a few ulps of the largest coordinate involved
// (the point's own, or the triangle's vertices' when the point is near the origin). The offset is
// purely relative to that magnitude, so a scene scaled by any power of ten renders the same:
// 1e-4 relative is ~1000 float ulps, well above the error and below any feature we model.
// A fixed epsilon fails at one end of the scale range (acne in kilometres, leaks in millimetres).
constexpr float kRayOffsetRelative = 1e-4f;
// Near the origin the vertices, not the point, set the error: 1e-2 of their magnitude still
// leaves ~10 ulps of margin.
constexpr float kVertexScaleShare = 1e-2f;
// Only guards the all-zero case (no finite scene has every coordinate 0); far below any float
// error that a real hit point can carry at scale 1e-3.
constexpr float kRayOffsetFloor = 1e-30f;

// The offset scale for a point with coordinates (x, y, z): max(|x|, |y|, |z|, floor).
inline float offsetScale(float x, float y, float z) {
    return std::max(std::max(std::abs(x), std::abs(y)), std::max(std::abs(z), kRayOffsetFloor));
}
inline float rayOffset(const glm::vec3& p) { return kRayOffsetRelative * offsetScale(p.x, p.y, p.z); }
// For a point rebuilt from a triangle whose vertices reach `vertexScale` (Triangle::vertexScale).
inline float rayOffset(const glm::vec3& p, float vertexScale) {
    return kRayOffsetRelative * std::max(offsetScale(p.x, p.y, p.z), kVertexScaleShare * vertexScale);
}

}  // namespace aamap
