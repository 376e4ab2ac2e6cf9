#pragma once
// The G-buffer's textures: every (base colour, coverage) pair a material uses, packed into one
// RGBA8 sRGB 2D-array atlas (rgb: base colour, a: coverage). Why an atlas and not a descriptor
// array: the passes bind through push descriptors, which hold at most maxPushDescriptors (32 on
// lavapipe) descriptors, while Sponza-like scenes use 70+ textures; one array image is one binding
// for any number of textures. The shader does its own bilinear filter with repeat inside an
// entry's rectangle (texelFetch, so no sampler and no bleeding between entries), the same texel
// rule as the tracer (tracer/embree_scene.cpp), so both see the same colours and cut-outs.
// Entries larger than kMaxEntrySide are box-filtered down to fit; that is level 0 of the entry's
// mip chain (core/texture_filter.h, buildMipChain), whose levels the colour lookup filters
// (glsl/gbuffer_texture.glsl, the rule of filteredLookup). Coverage is read from level 0 only.
#include <cstdint>
#include <map>
#include <utility>
#include <vector>

#include "scene/scene.h"

namespace aamap::passes {

// Level 0's rectangle. The levels >= 1 of the entry's chain (down to 1 x 1, so their count follows
// from the size) lie in a row just below it, left-aligned, in order: see atlasLevel. Their alpha is
// unused.
struct AtlasEntry {
    std::uint32_t x = 0, y = 0, width = 0, height = 0, layer = 0;
};

// The number of levels of a width x height entry's chain: buildMipChain's, down to 1 x 1.
std::uint32_t atlasLevelCount(std::uint32_t width, std::uint32_t height);

// Level `level`'s rectangle (x, y, width, height; layer as the entry's): level 0 is the entry,
// level 1 starts at (x, y + height), level l + 1 right after level l. The shader's rule too
// (glsl/gbuffer_texture.glsl, atlasLevel).
AtlasEntry atlasLevel(const AtlasEntry& entry, std::uint32_t level);

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
