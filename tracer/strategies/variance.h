#pragma once
// Variance-driven adaptive sampling as in Blender Cycles: every pixel keeps the sum of all its
// samples and of every second one (the half buffer); the error estimate compares the two means,
// normalised by the square root of the pixel's brightness. All pixels take minSamples samples;
// then, round after round, every pixel whose error is not below the noise threshold, and its
// 3 x 3 neighbourhood (Cycles dilates non-converged pixels in x, then in y), takes sampleStep
// more, up to n^2. Sample i of a pixel is stratum varianceOrder(n)[i] of the n x n grid, so a
// pixel that reaches n^2 samples holds exactly the samples of uniform sampling.
#include <cstdint>
#include <vector>

#include <glm/vec3.hpp>

#include "core/image.h"

namespace aamap {

// Cycles' error, written with means: sum_c |all_c - half_c| / (1e-4 + sqrt(sum_c all_c)).
double varianceError(const glm::dvec3& meanAll, const glm::dvec3& meanHalf);

// The strata (row-major indices into the n x n grid) in sampling order: a fixed pseudo-random
// permutation, so that the even and the odd samples are each an unbiased sample of the pixel
// (a regular stride would put them in alternate columns).
std::vector<int> varianceOrder(int n);

// 1 where `active` or one of its 8 neighbours is 1.
Image<std::uint8_t> dilate3x3(const Image<std::uint8_t>& active);

}  // namespace aamap
