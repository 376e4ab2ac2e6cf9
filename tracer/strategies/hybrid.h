#pragma once
// Hybrid (beyond the paper): the aamap decides where to look, sample contrast decides where to
// stop. A pixel the map does not flag (a = 0) takes one ray. A flagged pixel (a > 0, or NaN)
// starts with k(a)^2 samples (k from the strata mapping, at least 2 so that there is a half
// buffer) and then, while the Cycles error of its own two half buffers (varianceError) is not
// below the noise threshold, takes sampleStep more, up to n^2. Samples follow varianceOrder(n)
// over the pixel's n x n strata, so a pixel that reaches n^2 holds uniform sampling's samples.
// Pixels decide alone (no dilation: the map already spread the flags), in one tile phase.
#include <glm/vec3.hpp>

namespace aamap {

// Samples a pixel takes before the stop rule is first asked: 1 when unflagged (a == 0), else
// max(k^2, 2) capped at n^2.
int hybridStartSamples(float a, int n, int k);
// The stop rule after `taken` samples with means meanAll and meanHalf (odd samples): stop at
// n^2, or when the error estimate is below the threshold.
bool hybridConverged(const glm::dvec3& meanAll, const glm::dvec3& meanHalf, int taken, int n, double threshold);

}  // namespace aamap
