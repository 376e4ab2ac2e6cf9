#pragma once
// Texture antialiasing by filtering, not by rays (docs/tracer.md, "Texture filtering"): a
// box-filtered mip chain of a repeating texture and the anisotropic footprint rule that the tracer
// (tracer/embree_scene.cpp) and the Snapshot's shader (glsl/gbuffer_texture.glsl) both follow, so
// a 1-ray pixel on a minified texture already shows the texture's average over the pixel.
#include <vector>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

namespace aamap {

// At most this many probes along a footprint's major axis (the usual GPU limit). Beyond it the
// footprint is filtered more coarsely across its minor axis, never aliased.
inline constexpr int kMaxTextureAnisotropy = 16;

// One level of a mip chain: linear RGB, row 0 at the top (v = 0), repeating in both directions.
struct MipLevel {
    int width = 0, height = 0;
    std::vector<glm::vec3> rgb;
};

// Level 0 is the texture; level l + 1 has sides max(1, side_l / 2) (rounded down), and each of its
// texels is the exact area average of the level-l texels it covers (odd sides too), down to 1 x 1.
// Empty for an empty texture.
std::vector<MipLevel> buildMipChain(int width, int height, std::vector<glm::vec3> rgb);

// Where a footprint is sampled. axisA, axisB: the footprint's two full-width axes in level-0 texel
// units (for a pixel: its extent along two directions on the surface). The major axis gets `count`
// probes spaced `step` apart (in level-0 texels, centred on the lookup point), each a trilinear
// lookup at `level` = log2 of the width each probe covers (>= the minor axis), clamped to the chain.
struct FootprintProbes {
    int count = 1;
    glm::vec2 step{0.0f};
    float level = 0.0f;
};
FootprintProbes footprintProbes(glm::vec2 axisA, glm::vec2 axisB, int levels);

// Bilinear lookup with repeat at texture coordinates st in one level: texel centres at
// (i + 0.5) / side, v = 0 the top row (the rule of the unfiltered lookup, level 0).
glm::vec3 bilinear(const MipLevel& level, glm::vec2 st);

// The uv gradient (d/du, d/dv) of the bilinear lookup's luminance (Mitsuba's Rec. 709 weights) at
// st, as Mitsuba's bitmap eval_1_grad: the bump map's slope. Zero where st is not finite.
glm::vec2 bilinearLuminanceGradient(const MipLevel& level, glm::vec2 st);

// The filtered colour at st for a footprint with full-width axes duvA, duvB in texture
// coordinates (uv units). A zero footprint is the plain bilinear lookup of level 0.
glm::vec3 filteredLookup(const std::vector<MipLevel>& chain, glm::vec2 st, glm::vec2 duvA, glm::vec2 duvB);

// The footprint on a surface of a ray cone of width `width` arriving along unit `dir` at a surface
// with unit normal `normal`: two full-width world-space axes, `width` across the direction of
// incidence and width / |cos| along it (capped, so grazing rays keep a finite footprint).
void coneFootprint(const glm::vec3& dir, const glm::vec3& normal, float width, glm::vec3& axisA, glm::vec3& axisB);

// World-space vector `w` in the plane of a triangle with edges e1, e2 (from vertex 0) and uv edges
// duv1, duv2, expressed in uv: the least-squares (a, b) with w = a e1 + b e2, mapped to
// a duv1 + b duv2. Zero for a degenerate triangle.
glm::vec2 worldToUv(const glm::vec3& w, const glm::vec3& e1, const glm::vec3& e2, const glm::vec2& duv1,
                    const glm::vec2& duv2);

}  // namespace aamap
