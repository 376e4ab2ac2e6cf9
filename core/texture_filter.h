#pragma once
// Texture antialiasing by filtering, not by rays (docs/tracer.md, "Texture filtering"): a
// box-filtered mip chain of a repeating texture and the anisotropic footprint rule that the tracer
// (tracer/embree_scene.cpp) and the Snapshot's shader (glsl/gbuffer_texture.glsl) both follow, so
// a 1-ray pixel on a minified texture already shows the texture's average over the pixel.
#include <cstddef>
#include <cstdint>
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

// The four texels around texture coordinates st in a width x height grid with repeat (texel
// centres at (i + 0.5) / side, v = 0 the top row) and the weights between them; false for a
// non-finite st (or one whose texel coordinate overflows). Columns x0, x1 (x0's right neighbour,
// wrapped), rows y0, y1, and their row-major indices (x0, y0), (x1, y0), (x0, y1), (x1, y1).
struct BilinearTaps {
    std::size_t x0, x1, y0, y1;
    std::size_t i00, i10, i01, i11;
    float ax, ay;
};
bool bilinearTaps(glm::vec2 st, int width, int height, BilinearTaps& taps);

// How a packed level stores its texels: 8-bit sRGB-encoded, 8-bit linear (value / 255), or float.
enum class TexelEncoding : std::uint8_t { Srgb8, Unorm8, Float };

// The narrowest encoding that holds every texel of `level` exactly: Srgb8 where each channel is
// srgbToLinear(i / 255) for some byte i (an 8-bit colour texture as the loaders decode it), Unorm8
// where each is i / 255 (a raw 8-bit map), else Float (HDR files, procedural textures).
TexelEncoding exactEncoding(const MipLevel& level);

// A mip level as the tracer samples it. Texels lie in 4 x 4 tiles, so a bilinear lookup's four
// texels mostly share a tile: one 64-byte cache line at 8 bits a channel, where float RGB in rows
// spreads them over two lines or more and takes three times the memory (the Snapshot's atlas keeps
// its levels as 8-bit sRGB as well). An 8-bit level whose texels are not exact (a mip level below
// level 0) rounds each channel to the nearest code, as the atlas does.
class PackedLevel {
public:
    PackedLevel(const MipLevel& level, TexelEncoding encoding);
    int width() const { return width_; }
    int height() const { return height_; }
    TexelEncoding encoding() const { return encoding_; }
    glm::vec3 texel(std::size_t x, std::size_t y) const;
    // The bilinear blend of taps' four texels (bilinearTaps of this level's size).
    glm::vec3 blend(const BilinearTaps& taps) const;

private:
    std::size_t slot(std::size_t x, std::size_t y) const { return ((y >> 2) * tilesX_ + (x >> 2)) * 16 + (y & 3) * 4 + (x & 3); }
    int width_ = 0, height_ = 0;
    std::size_t tilesX_ = 0;
    TexelEncoding encoding_ = TexelEncoding::Float;
    std::vector<std::uint32_t> codes_;  // 8-bit encodings: R, G, B in the low three bytes
    std::vector<glm::vec3> values_;     // Float
};

// A chain packed level by level, every level in the encoding that holds level 0 exactly.
std::vector<PackedLevel> packMipChain(const std::vector<MipLevel>& chain);

// Bilinear lookup with repeat at texture coordinates st in one level (bilinearTaps' rule); white
// where st is not finite.
glm::vec3 bilinear(const PackedLevel& level, glm::vec2 st);

// The uv gradient (d/du, d/dv) of the bilinear lookup's luminance (Mitsuba's Rec. 709 weights) at
// st, as Mitsuba's bitmap eval_1_grad: the bump map's slope. Zero where st is not finite.
glm::vec2 bilinearLuminanceGradient(const PackedLevel& level, glm::vec2 st);

// The filtered colour at st for a footprint with full-width axes duvA, duvB in texture
// coordinates (uv units). A zero footprint is the plain bilinear lookup of level 0.
glm::vec3 filteredLookup(const std::vector<PackedLevel>& chain, glm::vec2 st, glm::vec2 duvA, glm::vec2 duvB);

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
