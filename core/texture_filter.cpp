#include "core/texture_filter.h"

#include <algorithm>
#include <cmath>
#include <cstddef>

#include <glm/geometric.hpp>

#include "core/srgb.h"

namespace aamap {
namespace {

// One box-filter step along one axis: `n` source samples to max(1, n / 2); output sample i is the
// exact average over the source interval [i n / m, (i + 1) n / m). `get(j)` reads source j,
// `put(i, value)` writes output i.
template <class Get, class Put>
void downsampleAxis(int n, int m, Get&& get, Put&& put) {
    const double scale = static_cast<double>(n) / m;
    for (int i = 0; i < m; ++i) {
        const double lo = i * scale, hi = (i + 1) * scale;
        glm::dvec3 sum(0.0);
        for (int j = static_cast<int>(std::floor(lo)); j < n && j < hi; ++j) {
            const double overlap = std::min(hi, j + 1.0) - std::max(lo, static_cast<double>(j));
            if (overlap > 0.0) sum += overlap * glm::dvec3(get(j));
        }
        put(i, glm::vec3(sum / scale));
    }
}

MipLevel halve(const MipLevel& src) {
    const int w = std::max(1, src.width / 2), h = std::max(1, src.height / 2);
    // Rows first (src.height rows of width w), then columns.
    std::vector<glm::vec3> rows(static_cast<std::size_t>(w) * src.height);
    for (int y = 0; y < src.height; ++y) {
        const std::size_t in = static_cast<std::size_t>(y) * src.width, out = static_cast<std::size_t>(y) * w;
        downsampleAxis(src.width, w, [&](int j) { return src.rgb[in + j]; },
                       [&](int i, glm::vec3 c) { rows[out + i] = c; });
    }
    MipLevel dst{w, h, std::vector<glm::vec3>(static_cast<std::size_t>(w) * h)};
    for (int x = 0; x < w; ++x)
        downsampleAxis(src.height, h, [&](int j) { return rows[static_cast<std::size_t>(j) * w + x]; },
                       [&](int i, glm::vec3 c) { dst.rgb[static_cast<std::size_t>(i) * w + x] = c; });
    return dst;
}

}  // namespace

std::vector<MipLevel> buildMipChain(int width, int height, std::vector<glm::vec3> rgb) {
    std::vector<MipLevel> chain;
    if (width <= 0 || height <= 0 || rgb.size() < static_cast<std::size_t>(width) * height) return chain;
    chain.push_back({width, height, std::move(rgb)});
    while (chain.back().width > 1 || chain.back().height > 1) chain.push_back(halve(chain.back()));
    return chain;
}

FootprintProbes footprintProbes(glm::vec2 axisA, glm::vec2 axisB, int levels) {
    FootprintProbes p;
    const float la = glm::length(axisA), lb = glm::length(axisB);
    if (!std::isfinite(la) || !std::isfinite(lb)) {
        p.level = static_cast<float>(std::max(levels - 1, 0));  // an unbounded footprint: the average
        return p;
    }
    const glm::vec2 major = la >= lb ? axisA : axisB;
    const float majorLength = std::max(la, lb), minorLength = std::min(la, lb);
    // Probes closer than a texel add nothing: at most one per texel of the major axis.
    p.count = std::clamp(static_cast<int>(std::ceil(majorLength / std::max(minorLength, 1.0f))), 1,
                         kMaxTextureAnisotropy);
    p.step = major / static_cast<float>(p.count);
    const float width = std::max(minorLength, majorLength / static_cast<float>(p.count));
    p.level = width > 1.0f ? std::min(std::log2(width), static_cast<float>(std::max(levels - 1, 0))) : 0.0f;
    return p;
}

namespace {

// Texel index i (a whole number) wrapped into [0, n). Most lookups land inside the texture, where
// this costs a compare instead of a division; far outside (uv of 1e30 included) it stays in range.
std::size_t wrapTexel(float i, int n) {
    const float side = static_cast<float>(n);
    if (i >= 0.0f && i < side) return static_cast<std::size_t>(i);
    const double r = static_cast<double>(i) - n * std::floor(static_cast<double>(i) / n);
    const std::size_t k = r >= 0.0 ? static_cast<std::size_t>(r) : 0;
    return k < static_cast<std::size_t>(n) ? k : 0;
}

}  // namespace

bool bilinearTaps(glm::vec2 st, int width, int height, BilinearTaps& t) {
    const float x = st.x * static_cast<float>(width) - 0.5f, y = st.y * static_cast<float>(height) - 0.5f;
    if (!std::isfinite(x) || !std::isfinite(y)) return false;
    const float fx = std::floor(x), fy = std::floor(y);
    t.ax = x - fx;
    t.ay = y - fy;
    const std::size_t w = static_cast<std::size_t>(width), h = static_cast<std::size_t>(height);
    t.x0 = wrapTexel(fx, width);
    t.y0 = wrapTexel(fy, height);
    t.x1 = t.x0 + 1 < w ? t.x0 + 1 : 0;
    t.y1 = t.y0 + 1 < h ? t.y0 + 1 : 0;
    t.i00 = t.y0 * w + t.x0;
    t.i10 = t.y0 * w + t.x1;
    t.i01 = t.y1 * w + t.x0;
    t.i11 = t.y1 * w + t.x1;
    return true;
}

namespace {

// Decoding tables of the two 8-bit encodings, built with the loaders' own conversions.
struct ByteTables {
    float srgb[256], unorm[256];
    ByteTables() {
        for (int i = 0; i < 256; ++i) {
            unorm[i] = static_cast<float>(i) / 255.0f;
            srgb[i] = srgbToLinear(unorm[i]);
        }
    }
};
const ByteTables& byteTables() {
    static const ByteTables tables;
    return tables;
}

std::uint8_t encodeChannel(float v, TexelEncoding e) { return toUnorm8(e == TexelEncoding::Srgb8 ? linearToSrgb(v) : v); }

bool exactIn(const MipLevel& level, TexelEncoding e) {
    const float* table = e == TexelEncoding::Srgb8 ? byteTables().srgb : byteTables().unorm;
    for (const glm::vec3& c : level.rgb)
        for (int k = 0; k < 3; ++k)
            if (!(table[encodeChannel(c[k], e)] == c[k])) return false;
    return true;
}

}  // namespace

TexelEncoding exactEncoding(const MipLevel& level) {
    if (exactIn(level, TexelEncoding::Srgb8)) return TexelEncoding::Srgb8;
    if (exactIn(level, TexelEncoding::Unorm8)) return TexelEncoding::Unorm8;
    return TexelEncoding::Float;
}

PackedLevel::PackedLevel(const MipLevel& level, TexelEncoding encoding)
    : width_(level.width), height_(level.height), tilesX_((static_cast<std::size_t>(level.width) + 3) / 4),
      encoding_(encoding) {
    const std::size_t tilesY = (static_cast<std::size_t>(level.height) + 3) / 4;
    if (encoding == TexelEncoding::Float)
        values_.assign(tilesX_ * tilesY * 16, glm::vec3(0.0f));
    else
        codes_.assign(tilesX_ * tilesY * 16, 0u);
    for (std::size_t y = 0; y < static_cast<std::size_t>(height_); ++y)
        for (std::size_t x = 0; x < static_cast<std::size_t>(width_); ++x) {
            const glm::vec3& c = level.rgb[y * static_cast<std::size_t>(width_) + x];
            if (encoding == TexelEncoding::Float) {
                values_[slot(x, y)] = c;
                continue;
            }
            std::uint32_t code = 0;
            for (int k = 0; k < 3; ++k) code |= static_cast<std::uint32_t>(encodeChannel(c[k], encoding)) << (8 * k);
            codes_[slot(x, y)] = code;
        }
}

glm::vec3 PackedLevel::texel(std::size_t x, std::size_t y) const {
    if (encoding_ == TexelEncoding::Float) return values_[slot(x, y)];
    const float* table = encoding_ == TexelEncoding::Srgb8 ? byteTables().srgb : byteTables().unorm;
    const std::uint32_t code = codes_[slot(x, y)];
    return {table[code & 0xffu], table[(code >> 8) & 0xffu], table[(code >> 16) & 0xffu]};
}

std::vector<PackedLevel> packMipChain(const std::vector<MipLevel>& chain) {
    std::vector<PackedLevel> packed;
    if (chain.empty()) return packed;
    const TexelEncoding encoding = exactEncoding(chain[0]);
    packed.reserve(chain.size());
    for (const MipLevel& level : chain) packed.emplace_back(level, encoding);
    return packed;
}

glm::vec3 PackedLevel::blend(const BilinearTaps& t) const {
    // The encoding is looked at once per lookup, not per texel.
    const auto mix = [&t](const auto& at) {
        const glm::vec3 top = (1.0f - t.ax) * at(t.x0, t.y0) + t.ax * at(t.x1, t.y0);
        const glm::vec3 bottom = (1.0f - t.ax) * at(t.x0, t.y1) + t.ax * at(t.x1, t.y1);
        return (1.0f - t.ay) * top + t.ay * bottom;
    };
    if (encoding_ == TexelEncoding::Float) return mix([this](std::size_t x, std::size_t y) { return values_[slot(x, y)]; });
    const float* table = encoding_ == TexelEncoding::Srgb8 ? byteTables().srgb : byteTables().unorm;
    return mix([this, table](std::size_t x, std::size_t y) {
        const std::uint32_t code = codes_[slot(x, y)];
        return glm::vec3(table[code & 0xffu], table[(code >> 8) & 0xffu], table[(code >> 16) & 0xffu]);
    });
}

glm::vec3 bilinear(const PackedLevel& level, glm::vec2 st) {
    BilinearTaps t;
    if (!bilinearTaps(st, level.width(), level.height(), t)) return glm::vec3(1.0f);
    return level.blend(t);
}

glm::vec2 bilinearLuminanceGradient(const PackedLevel& level, glm::vec2 st) {
    BilinearTaps t;
    if (!bilinearTaps(st, level.width(), level.height(), t)) return glm::vec2(0.0f);
    const auto lum = [&level](std::size_t x, std::size_t y) {
        const glm::vec3 c = level.texel(x, y);
        return 0.212671f * c.x + 0.715160f * c.y + 0.072169f * c.z;
    };
    const float f00 = lum(t.x0, t.y0), f10 = lum(t.x1, t.y0), f01 = lum(t.x0, t.y1), f11 = lum(t.x1, t.y1);
    const float ax = t.ax, ay = t.ay;
    // Per texel, then per unit of u and v (a texel is 1 / side of the texture).
    const float dx = (1.0f - ay) * (f10 - f00) + ay * (f11 - f01);
    const float dy = (1.0f - ax) * (f01 - f00) + ax * (f11 - f10);
    return {dx * static_cast<float>(level.width()), dy * static_cast<float>(level.height())};
}

glm::vec3 filteredLookup(const std::vector<PackedLevel>& chain, glm::vec2 st, glm::vec2 duvA, glm::vec2 duvB) {
    if (chain.empty()) return glm::vec3(1.0f);
    const glm::vec2 size(static_cast<float>(chain[0].width()), static_cast<float>(chain[0].height()));
    const int levels = static_cast<int>(chain.size());
    const FootprintProbes p = footprintProbes(duvA * size, duvB * size, levels);
    const int l0 = static_cast<int>(p.level);
    const float f = p.level - static_cast<float>(l0);
    const bool blendLevels = f > 0.0f && l0 + 1 < levels;
    glm::vec3 sum(0.0f);
    for (int i = 0; i < p.count; ++i) {
        const float offset = static_cast<float>(i) - 0.5f * static_cast<float>(p.count - 1);
        const glm::vec2 at = st + offset * p.step / size;
        glm::vec3 c = bilinear(chain[static_cast<std::size_t>(l0)], at);
        if (blendLevels) c = (1.0f - f) * c + f * bilinear(chain[static_cast<std::size_t>(l0 + 1)], at);
        sum += c;
    }
    return sum / static_cast<float>(p.count);
}

void coneFootprint(const glm::vec3& dir, const glm::vec3& normal, float width, glm::vec3& axisA, glm::vec3& axisB) {
    // A footprint at most this many times longer than wide: beyond it (grazing rays) the texture
    // is averaged across the minor axis too.
    constexpr float kMinCosine = 1.0f / 64.0f;
    glm::vec3 across = glm::cross(normal, dir);
    const float len = glm::length(across);
    if (!(len > 1e-6f)) {  // normal incidence: any tangent pair
        across = std::abs(normal.x) < 0.9f ? glm::cross(normal, glm::vec3(1, 0, 0)) : glm::cross(normal, glm::vec3(0, 1, 0));
        across = glm::normalize(across);
    } else {
        across /= len;
    }
    const glm::vec3 along = glm::cross(across, normal);  // unit: across and normal are orthonormal
    const float cosine = std::max(std::abs(glm::dot(dir, normal)), kMinCosine);
    axisA = width * across;
    axisB = (width / cosine) * along;
}

glm::vec2 worldToUv(const glm::vec3& w, const glm::vec3& e1, const glm::vec3& e2, const glm::vec2& duv1,
                    const glm::vec2& duv2) {
    const float a11 = glm::dot(e1, e1), a12 = glm::dot(e1, e2), a22 = glm::dot(e2, e2);
    const float det = a11 * a22 - a12 * a12;
    if (!(det > 1e-12f * a11 * a22) || !std::isfinite(det)) return glm::vec2(0.0f);
    const float b1 = glm::dot(w, e1), b2 = glm::dot(w, e2);
    const float a = (b1 * a22 - b2 * a12) / det, b = (a11 * b2 - a12 * b1) / det;
    return a * duv1 + b * duv2;
}

}  // namespace aamap
