#pragma once
// The sRGB transfer functions of 8-bit textures, in one place: the loaders decode with
// srgbToLinear, the Snapshot's texture atlas and the tracer's packed texels encode with
// linearToSrgb, so a texel decoded and encoded again comes back as the same byte.
#include <algorithm>
#include <cmath>
#include <cstdint>

namespace aamap {

// The sRGB EOTF on [0, 1]: an encoded value to linear.
inline float srgbToLinear(float c) { return c <= 0.04045f ? c / 12.92f : std::pow((c + 0.055f) / 1.055f, 2.4f); }

// The inverse, clamped to [0, 1].
inline float linearToSrgb(float c) {
    c = std::clamp(c, 0.0f, 1.0f);
    return c <= 0.0031308f ? 12.92f * c : 1.055f * std::pow(c, 1.0f / 2.4f) - 0.055f;
}

// A value in [0, 1] (clamped) to the nearest of 256 levels.
inline std::uint8_t toUnorm8(float v) { return static_cast<std::uint8_t>(std::lround(std::clamp(v, 0.0f, 1.0f) * 255.0f)); }

}  // namespace aamap
