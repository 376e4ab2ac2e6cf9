#pragma once
// One record's hemisphere: stratified cosine-weighted sampling in M x N cells (theta x phi) with
// Radiance-style supersampling, the irradiance, the harmonic-mean distance and the translational
// and rotational gradients of Ward & Heckbert 1992. Pure function of its arguments.
#include <array>
#include <cstdint>

#include <glm/vec3.hpp>

#include "tracer/irradiance_cache.h"

namespace aamap {

struct HemisphereLayout {
    int theta = 1;  // M
    int phi = 1;    // N, about pi * M
};
// Radiance's split of `divisions` cells: M = round(sqrt(divisions / pi)), N = round(pi * M).
HemisphereLayout hemisphereLayout(int divisions);

struct HemisphereEstimate {
    glm::vec3 irradiance{0.0f};
    std::array<glm::vec3, 3> gradT{};  // per channel, in world space (tangent to the surface)
    std::array<glm::vec3, 3> gradR{};
    float harmonicDistance = 0.0f;  // cells / sum(1 / d); infinity when nothing was hit
    std::uint64_t rays = 0;         // RadianceFn calls
};

// Samples the hemisphere over unit normal n at p: rays leave p + offset * n with depth `depth`; cell (j, k), sample s draws its jitter and its RadianceFn seed from
// (seed, j, k, s) only. `supersamples` extra samples go, one at a time, to the cell whose
// brightness differs most from its neighbours per sample already taken.
HemisphereEstimate sampleHemisphere(const glm::vec3& p, const glm::vec3& n, float offset, int divisions,
                                    int supersamples, int depth, std::uint64_t seed, const RadianceFn& radiance);

// Radiance's brightness weights (a luminance-like scalar for the error and radius heuristics).
inline float brightness(const glm::vec3& c) { return 0.2651f * c.x + 0.6701f * c.y + 0.0648f * c.z; }

}  // namespace aamap
