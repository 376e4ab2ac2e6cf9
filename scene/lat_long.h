#pragma once
// The equirectangular (latitude-longitude) map convention of EnvironmentLight (scene/scene.h),
// Mitsuba's `envmap` (0.5/0.6 and 3.x alike: envmap.cpp's direction_to_uv): in the map's frame
// (+Y up), u = atan2(x, -z) / (2 pi) (wrapping) and v = acos(y) / pi, row 0 at the top. The left
// edge (u = 0) looks along -Z, u = 0.25 along +X, the centre column along +Z. Inline and header-only: the tracer and the Snapshot both use
// it without linking the scene library.
#include <algorithm>
#include <cmath>
#include <numbers>

#include <glm/geometric.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

namespace aamap::latlong {

// (u, v) in [0,1]^2 of a unit direction in the map's frame.
inline glm::vec2 fromDirection(const glm::vec3& d) {
    constexpr float kPi = std::numbers::pi_v<float>;
    float u = std::atan2(d.x, -d.z) * (0.5f / kPi);
    u -= std::floor(u);
    return {u, std::acos(std::clamp(d.y, -1.0f, 1.0f)) / kPi};
}

// The direction in the map's frame at (u, v), given sinTheta = sin(pi v): unit up to rounding,
// for a caller that needs sin(theta) as well and computes it once.
inline glm::vec3 toDirection(glm::vec2 uv, float sinTheta) {
    constexpr float kPi = std::numbers::pi_v<float>;
    const float phi = uv.x * 2.0f * kPi, theta = uv.y * kPi;
    return {sinTheta * std::sin(phi), std::cos(theta), -sinTheta * std::cos(phi)};
}

// The unit direction in the map's frame at (u, v).
inline glm::vec3 toDirection(glm::vec2 uv) {
    constexpr float kPi = std::numbers::pi_v<float>;
    return glm::normalize(toDirection(uv, std::sin(uv.y * kPi)));
}

// Solid angle of row `row` of a width x height map's pixels (each pixel of the row has this).
inline double pixelSolidAngle(int row, int width, int height) {
    constexpr double kPi = std::numbers::pi;
    return (2.0 * kPi / width) * (std::cos(row * kPi / height) - std::cos((row + 1) * kPi / height));
}

}  // namespace aamap::latlong
