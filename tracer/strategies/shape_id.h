#pragma once
// pbrt-v2's AdaptiveSampler with the shape-id method: every pixel first takes m x m samples
// (m = floor(sqrt(minSamples)), at most n); if they did not all hit the same shape (an object of
// the scene; a miss counts as its own shape), the pixel is supersampled with n x n fresh samples
// and the first ones are discarded, as pbrt-v2 does. Shapes come from a probe ray per first
// sample (counted in rays.other).
#include <cstdint>
#include <vector>

namespace aamap {

// pbrt-v2 AdaptiveSampler::needsSupersampling, shape-id method.
bool shapesDiffer(const std::vector<std::uint32_t>& shapes);

// m for minSamples: floor(sqrt(minSamples)) in [1, n].
int shapeIdMinStrata(int minSamples, int n);

}  // namespace aamap
