#pragma once
// Radiance rpict's adaptive undersampling (-ps spacing, -pt threshold), the paper's own renderer
// without the aamap: trace one ray at every s-th pixel of every s-th row (plus the last row and
// column), then bisect recursively along the traced rows, then along every column: between two
// known pixels, trace the midpoint when they differ by more than t (rpictDiffers), otherwise
// interpolate linearly (colour and depth). At most one primary ray per pixel, at its jittered
// stratum 0. Depth comes from a probe ray per traced pixel (counted in rays.other).
#include <glm/vec3.hpp>

namespace aamap {

// Radiance's bigdiff() per channel, relative to the smaller value: |a - b| > t * min(a, b); plus
// the same test on depth, where a miss (+inf) differs from any hit. NaN differs.
bool rpictDiffers(const glm::vec3& a, float depthA, const glm::vec3& b, float depthB, double t);

}  // namespace aamap
