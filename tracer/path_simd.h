#pragma once
// Path mode's common vertex shaded across a packet's lanes at once (Google Highway, dispatched at
// run time to the best of SSE4 / AVX2 / AVX-512): a step's random numbers, the light pick on the
// power CDF, the point on an area light (by area), the light sample's geometry and, for Lambert
// lanes, the BSDF evaluation, the MIS weight, the cosine-sampled bounce and roulette. The lanes
// are laid out SoA; each lane's arithmetic is the scalar code's, operation for operation and
// without fused multiply-adds, so only the sine and cosine of the bounce differ from libm's
// (docs/tracer.md, "Path mode in lockstep").
#include <cstdint>
#include <vector>

namespace aamap {

struct LightSet;

namespace pathsimd {

constexpr int kLanes = 8;

// The area lights flattened for gathers (built once per integrator, only without point lights).
struct LightTable {
    std::vector<float> selectCdf, selectPdf;  // LightSet's, over the area lights
    std::vector<std::int32_t> triStart, triCount;  // per light: its triangles in the arrays below
    std::vector<float> radiance[3], area, vertexScale;
    std::vector<float> cdfLow, cdf, invCdfWidth;  // per triangle, as AreaLightSampler::Tri
    std::vector<float> v0[3], e1[3], e2[3], normal[3];
};
LightTable makeLightTable(const LightSet& lights);

// One step's lanes, SoA. Inputs first; `lambert` lanes (a Classic Lambert-only material) are
// shaded to the end, the others get the random numbers and the light sample only.
struct alignas(64) Lanes {
    // in
    std::uint64_t key[kLanes];  // Sampler::key()
    std::int32_t lambert[kLanes];  // -1 or 0
    float p[3][kLanes], g[3][kLanes], n[3][kLanes];  // position, geometric and shading normals
    float albedo[3][kLanes], offset[kLanes], beta[3][kLanes], etaScale[kLanes];
    // out: the step's random numbers (dims::path(depth, slot) as the scalar Sampler draws them)
    float uLobe[kLanes], uLight[2][kLanes], uBsdf[2][kLanes], uRoulette[kLanes];
    // out: the light sample. lightOk: the light is above both normals, in front of its own face
    // and the segment not empty; then origin, segment (to the light point, tfar), wi, the cosine
    // at the surface, the light's inverse pdf, its pick probability and radiance.
    std::int32_t lightOk[kLanes];
    float origin[3][kLanes], segment[3][kLanes], tfar[kLanes], wi[3][kLanes], cosSurface[kLanes];
    float inv[kLanes], pick[kLanes], radiance[3][kLanes];
    // out, Lambert lanes only: shadow = lightOk and a positive MIS denominator, with the
    // contribution where the segment is clear; next: the path goes on along dir (from origin,
    // the surface being above both normals), with the new beta and the BSDF pdf.
    std::int32_t shadow[kLanes], next[kLanes];
    float contribution[3][kLanes], dir[3][kLanes], pdf[kLanes];
};

// Shades lanes [0, count) at path vertex `depth` (the same for every lane of a lockstep step);
// roulette: whether Russian roulette plays at this depth. Lanes [count, kLanes) are scratch.
void shade(const LightTable& lights, Lanes& lanes, int count, int depth, bool roulette);

}  // namespace pathsimd
}  // namespace aamap
