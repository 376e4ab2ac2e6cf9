#pragma once
// The G-buffer's textures: every (base colour, coverage) pair a material uses, packed into one
// RGBA8 sRGB 2D-array atlas (rgb: base colour, a: coverage). Why an atlas and not a descriptor
// array: the passes bind through push descriptors, which hold at most maxPushDescriptors (32 on
// lavapipe) descriptors, while Sponza-like scenes use 70+ textures; one array image is one binding
// for any number of textures. The shader does its own bilinear filter with repeat inside an
// entry's rectangle (texelFetch, so no sampler and no bleeding between entries), the same texel
// rule as the tracer (tracer/embree_scene.cpp), so both see the same colours and cut-outs.
// No mip-maps: entries larger than kMaxEntrySide are box-filtered down to fit.
#include <cstdint>
#include <map>
#include <utility>
#include <vector>

#include "scene/scene.h"

namespace aamap::passes {

struct AtlasEntry {
    std::uint32_t x = 0, y = 0, width = 0, height = 0, layer = 0;
};

struct TextureAtlas {
    static constexpr std::uint32_t kMaxEntrySide = 2048;
    static constexpr std::uint32_t kMaxPageSide = 4096;

    std::uint32_t pageSide = 0, layers = 0;  // layers >= 2 (the view must be an array) when non-empty
    std::vector<std::uint32_t> texels;       // RGBA8, sRGB-encoded rgb, linear alpha; layer-major
    std::map<std::pair<int, int>, AtlasEntry> entries;  // (diffuse, alpha) texture indices, -1: none

    bool empty() const { return entries.empty(); }
};

// The atlas entry key of a material: (-1, -1) when the material samples nothing, i.e. it has no
// usable texture or the mesh has no uvs. A coverage texture counts only for alpha-tested
// materials; an untested material's key reuses its colour texture's own alpha (never read).
std::pair<int, int> atlasKey(const Material& material, const Scene& scene);

// Packs the entries the used materials need (shelf packing, tallest first). Empty when none.
TextureAtlas buildTextureAtlas(const Scene& scene);

}  // namespace aamap::passes
