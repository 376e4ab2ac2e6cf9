#pragma once
// Path mode's common vertex shaded across a packet's lanes at once (Google Highway, dispatched at
// run time to the best of SSE4 / AVX2 / AVX-512): a step's random numbers, the light pick on the
// power CDF, the point on an area light (by area), the light sample's geometry and, for Lambert
// and GGX rough plastic lanes, the BSDF evaluation, the MIS weight, the bounce and roulette. The lanes
// are laid out SoA; each lane's arithmetic is the scalar code's, operation for operation and
// without fused multiply-adds, so only the sine and cosine of the bounce differ from libm's
// (docs/tracer.md, "Path mode in lockstep").
#include <cstdint>
#include <vector>

namespace aamap {

struct LightSet;
struct ShadingMaterial;

namespace pathsimd {

constexpr int kLanes = 8;

// The area lights flattened for gathers (built once per integrator, only without point lights).
struct LightTable {
    std::vector<float> selectCdf, selectPdf;  // LightSet's, over the area lights
    std::vector<std::int32_t> triStart, triCount;  // per light: its triangles in the arrays below
    std::vector<float> radiance[3], area, vertexScale;
    std::vector<float> cdfLow, cdf, invCdfWidth;  // per triangle, as AreaLightSampler::Tri
    std::vector<float> v0[3], e1[3], e2[3], normal[3];
    // An environment map sampled on the lanes (EnvironmentSampler::sample): its CDFs and guide
    // tables, each cell's density over [0,1)^2 and radiance, and the map-to-world rotation
    // (column-major). envWidth 0: none, or a constant sky (left to BSDF sampling).
    int envWidth = 0, envHeight = 0;
    std::vector<float> envMarginal, envConditional, envPdf, envRadiance[3];
    std::vector<std::int32_t> envMarginalGuide, envConditionalGuide;
    float envToWorld[9] = {};
};
LightTable makeLightTable(const LightSet& lights);

// What the lanes do with a lane's BSDF: kOther lanes get the random numbers and the light sample
// only (their BSDF stays scalar), the others are shaded to the end.
enum LaneModel : std::int32_t {
    kOther = 0,
    kLambert = 1,       // Classic, Lambert only
    kRoughPlastic = 2,  // Mitsuba's roughplastic with GGX
};

// One step's lanes, SoA. Inputs first.
struct alignas(64) Lanes {
    // in
    std::uint64_t key[kLanes];  // Sampler::key()
    std::int32_t model[kLanes];  // LaneModel
    float p[3][kLanes], g[3][kLanes], n[3][kLanes], wo[3][kLanes];  // position, normals, to the viewer
    float albedo[3][kLanes], offset[kLanes], beta[3][kLanes], etaScale[kLanes];
    // in, rough plastic: alpha_u, alpha_v (clamped as microfacet::Distribution does), ior, the base's
    // albedo (bsdf::plasticBase), the coating's tint, its transmittance towards wo and the
    // probability of sampling it (bsdf::plasticSpecularPick), and the material (its table).
    float alpha[2][kLanes], ior[kLanes], base[3][kLanes], tint[3][kLanes], tO[kLanes], pickSpecular[kLanes];
    const ShadingMaterial* material[kLanes];
    // out: the step's random numbers (dims::path(depth, slot) as the scalar Sampler draws them)
    float uLobe[kLanes], uLight[2][kLanes], uBsdf[2][kLanes], uRoulette[kLanes];
    // out: the light sample. lightOk: the light is above both normals, in front of its own face
    // and the segment not empty; then origin, segment (to the light point, tfar), wi, the cosine
    // at the surface, the light's inverse pdf, its pick probability and radiance.
    std::int32_t lightOk[kLanes];
    float origin[3][kLanes], segment[3][kLanes], tfar[kLanes], wi[3][kLanes], cosSurface[kLanes];
    float inv[kLanes], pick[kLanes], radiance[3][kLanes];
    // out, lanes not kOther: shadow = lightOk and a positive MIS denominator, with the
    // contribution where the segment is clear; next: the path goes on along dir (from origin,
    // the surface being above both normals), with the new beta and the BSDF pdf.
    std::int32_t shadow[kLanes], next[kLanes];
    float contribution[3][kLanes], dir[3][kLanes], pdf[kLanes];
    // out, Lambert and rough plastic lanes with an environment map in the table: its light sample
    // (nextEventInfinite's), a shadow ray from origin along envDir to infinity when envShadow.
    std::int32_t envShadow[kLanes];
    float envDir[3][kLanes], envContribution[3][kLanes];
};

// Shades lanes [0, count) at path vertex `depth` (the same for every lane of a lockstep step);
// roulette: whether Russian roulette plays at this depth. Lanes [count, kLanes) are scratch.
void shade(const LightTable& lights, Lanes& lanes, int count, int depth, bool roulette);

}  // namespace pathsimd
}  // namespace aamap
