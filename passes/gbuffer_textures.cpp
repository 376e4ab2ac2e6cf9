#include "passes/gbuffer_textures.h"

#include <algorithm>
#include <cmath>
#include <set>

#include "glsl/shared/snapshot_interface.h"
#include "core/srgb.h"
#include "core/texture_filter.h"

namespace aamap::passes {
namespace {

bool usable(const Scene& scene, int texture) {
    if (texture < 0 || static_cast<std::size_t>(texture) >= scene.textures.size()) return false;
    const Texture& t = scene.textures[static_cast<std::size_t>(texture)];
    const std::size_t texels = static_cast<std::size_t>(std::max(t.width, 0)) * std::max(t.height, 0);
    return texels > 0 && t.rgba.size() >= 4 * texels;
}

// Bilinear with repeat, texel centres at (i + 0.5) / width: the tracer's rule (core/texture_filter.h).
float sample(const Texture& t, float s, float u, int channel) {
    BilinearTaps taps;
    if (!bilinearTaps({s, u}, t.width, t.height, taps)) return 1.0f;
    const auto at = [&](std::size_t i) { return t.rgba[4 * i + static_cast<std::size_t>(channel)]; };
    const float top = (1.0f - taps.ax) * at(taps.i00) + taps.ax * at(taps.i10);
    const float bottom = (1.0f - taps.ax) * at(taps.i01) + taps.ax * at(taps.i11);
    return (1.0f - taps.ay) * top + taps.ay * bottom;
}

std::uint32_t toByte(float v) { return toUnorm8(v); }  // widened for packing into RGBA words

std::uint32_t nextPowerOfTwo(std::uint32_t v) {
    std::uint32_t p = 1;
    while (p < v) p <<= 1;
    return p;
}

// The block an entry's chain occupies: level 0 above, the other levels in a row below it.
void blockSize(std::uint32_t w, std::uint32_t h, std::uint32_t& blockW, std::uint32_t& blockH) {
    const std::uint32_t levels = atlasLevelCount(w, h);
    blockW = w;
    blockH = h;
    if (levels < 2) return;
    const AtlasEntry last = atlasLevel({0, 0, w, h, 0}, levels - 1);
    blockW = std::max(w, last.x + last.width);
    blockH = h + std::max(1u, h / 2);
}

}  // namespace

static_assert(TEXTURE_MAX_ANISOTROPY == kMaxTextureAnisotropy, "the shader's probe limit is the tracer's");

std::uint32_t atlasLevelCount(std::uint32_t width, std::uint32_t height) {
    std::uint32_t levels = 1;
    for (std::uint32_t side = std::max(width, height); side > 1; side /= 2) ++levels;
    return levels;
}

AtlasEntry atlasLevel(const AtlasEntry& entry, std::uint32_t level) {
    AtlasEntry r = entry;
    if (level == 0) return r;
    r.y += entry.height;
    r.width = std::max(1u, entry.width / 2);
    r.height = std::max(1u, entry.height / 2);
    for (std::uint32_t l = 1; l < level; ++l) {
        r.x += r.width;
        r.width = std::max(1u, r.width / 2);
        r.height = std::max(1u, r.height / 2);
    }
    return r;
}

std::pair<int, int> atlasKey(const Material& material, const Scene& scene) {
    const bool hasUvs = !scene.mesh.uvs.empty() && scene.mesh.uvs.size() == scene.mesh.positions.size();
    if (!hasUvs) return {-1, -1};
    const int diffuse = usable(scene, material.diffuseTexture) ? material.diffuseTexture : -1;
    const int alpha = isAlphaTested(material) && usable(scene, material.alphaTexture) ? material.alphaTexture : -1;
    if (diffuse < 0 && alpha < 0) return {-1, -1};
    return {diffuse, alpha >= 0 ? alpha : diffuse};
}

TextureAtlas buildTextureAtlas(const Scene& scene) {
    TextureAtlas atlas;
    std::set<std::uint32_t> usedMaterials(scene.mesh.materialIds.begin(), scene.mesh.materialIds.end());
    std::set<std::pair<int, int>> keys;
    for (std::uint32_t id : usedMaterials) {
        if (id >= scene.materials.size()) continue;
        const auto key = atlasKey(scene.materials[id], scene);
        if (key.first >= 0 || key.second >= 0) keys.insert(key);
    }
    if (keys.empty()) return atlas;

    // Entry sizes: the colour texture's (else the coverage's), halved until they fit.
    struct Pending {
        std::pair<int, int> key;
        std::uint32_t width, height;  // level 0
        std::uint32_t blockWidth, blockHeight;  // the whole chain
    };
    std::vector<Pending> pending;
    std::uint64_t area = 0;
    std::uint32_t widest = 1;
    for (const auto& key : keys) {
        const Texture& base = scene.textures[static_cast<std::size_t>(key.first >= 0 ? key.first : key.second)];
        auto w = static_cast<std::uint32_t>(base.width), h = static_cast<std::uint32_t>(base.height);
        while (w > TextureAtlas::kMaxEntrySide || h > TextureAtlas::kMaxEntrySide) {
            w = (w + 1) / 2;
            h = (h + 1) / 2;
        }
        std::uint32_t bw = 0, bh = 0;
        blockSize(w, h, bw, bh);
        pending.push_back({key, w, h, bw, bh});
        area += static_cast<std::uint64_t>(bw) * bh;
        widest = std::max({widest, bw, bh});
    }
    const auto side = static_cast<std::uint32_t>(std::ceil(std::sqrt(static_cast<double>(area))));
    atlas.pageSide = std::max(nextPowerOfTwo(widest), std::min(TextureAtlas::kMaxPageSide, nextPowerOfTwo(side)));

    // Shelf packing of the blocks, tallest first.
    std::sort(pending.begin(), pending.end(), [](const Pending& a, const Pending& b) {
        return a.blockHeight != b.blockHeight ? a.blockHeight > b.blockHeight : a.key < b.key;
    });
    std::uint32_t x = 0, y = 0, shelf = 0, layer = 0;
    for (const Pending& p : pending) {
        if (x + p.blockWidth > atlas.pageSide) {
            x = 0;
            y += shelf;
            shelf = 0;
        }
        if (y + p.blockHeight > atlas.pageSide) {
            x = y = shelf = 0;
            ++layer;
        }
        atlas.entries[p.key] = {x, y, p.width, p.height, layer};
        x += p.blockWidth;
        shelf = std::max(shelf, p.blockHeight);
    }
    atlas.layers = std::max(layer + 1, 2u);  // two at least: the shader's view is always an array

    const std::size_t page = static_cast<std::size_t>(atlas.pageSide) * atlas.pageSide;
    atlas.texels.assign(page * atlas.layers, 0u);
    const auto encode = [](const glm::vec3& c) {
        std::uint32_t rgba = 0xffu << 24;
        for (int k = 0; k < 3; ++k) rgba |= toByte(linearToSrgb(c[k])) << (8 * k);
        return rgba;
    };
    for (const auto& [key, e] : atlas.entries) {
        const Texture* colour = key.first >= 0 ? &scene.textures[static_cast<std::size_t>(key.first)] : nullptr;
        const Texture* coverage = key.second >= 0 ? &scene.textures[static_cast<std::size_t>(key.second)] : nullptr;
        // Level 0: the source sampled at the entry's texel centres (a copy at equal size, a 2x2
        // box average where the entry was halved), in linear rgb for the chain.
        std::vector<glm::vec3> rgb(static_cast<std::size_t>(e.width) * e.height, glm::vec3(1.0f));
        std::vector<float> alpha(rgb.size(), 1.0f);
        for (std::uint32_t j = 0; j < e.height; ++j) {
            for (std::uint32_t i = 0; i < e.width; ++i) {
                const float s = (static_cast<float>(i) + 0.5f) / static_cast<float>(e.width);
                const float t = (static_cast<float>(j) + 0.5f) / static_cast<float>(e.height);
                const std::size_t k = static_cast<std::size_t>(j) * e.width + i;
                if (colour) rgb[k] = {sample(*colour, s, t, 0), sample(*colour, s, t, 1), sample(*colour, s, t, 2)};
                if (coverage) alpha[k] = sample(*coverage, s, t, 3);
            }
        }
        const std::vector<MipLevel> chain = buildMipChain(static_cast<int>(e.width), static_cast<int>(e.height), rgb);
        for (std::uint32_t l = 0; l < chain.size(); ++l) {
            const AtlasEntry r = atlasLevel(e, l);
            const MipLevel& level = chain[l];
            for (std::uint32_t j = 0; j < r.height; ++j) {
                for (std::uint32_t i = 0; i < r.width; ++i) {
                    const std::size_t k = static_cast<std::size_t>(j) * r.width + i;
                    std::uint32_t rgba = encode(level.rgb[k]);
                    if (l == 0) rgba = (rgba & 0xffffffu) | toByte(alpha[k]) << 24;  // coverage
                    atlas.texels[page * e.layer + static_cast<std::size_t>(r.y + j) * atlas.pageSide + r.x + i] = rgba;
                }
            }
        }
    }
    return atlas;
}

}  // namespace aamap::passes
