#pragma once
#include <algorithm>
#include <cmath>

#include <glm/vec3.hpp>

namespace aamap {

// Offset for rays leaving a surface, in scene units. The hit point is rebuilt from the triangle's
// vertices and barycentrics, so its float error is a few ulps of the largest coordinate involved.
// A fixed epsilon fails at one end of the scale range: too small for a scene in millimetres or far
// from the origin (self-shadowing acne), too large for a small one (light leaking through thin
// walls). 1e-4 relative is ~1000 float ulps, well above the error and below any feature we model.
// The floor of 1 keeps it absolute (1e-4) near the origin, where relative precision would be
// needlessly tight; scenes with features under ~1e-3 units would need a smaller floor.
constexpr float kRayOffsetRelative = 1e-4f;

// The offset scale for a point with coordinates (x, y, z): max(1, |x|, |y|, |z|).
inline float offsetScale(float x, float y, float z) {
    return std::max(std::max(std::abs(x), std::abs(y)), std::max(std::abs(z), 1.0f));
}
inline float rayOffset(const glm::vec3& p) { return kRayOffsetRelative * offsetScale(p.x, p.y, p.z); }

}  // namespace aamap
