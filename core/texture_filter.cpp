#include "core/texture_filter.h"

#include <algorithm>
#include <cmath>
#include <cstddef>

#include <glm/geometric.hpp>

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

int wrap(long i, int n) {
    const long k = i % n;
    return static_cast<int>(k < 0 ? k + n : k);
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

// The four texels around st (wrapped) and the weights between them; false for a non-finite st.
struct BilinearTaps {
    std::size_t i00, i10, i01, i11;  // indices into MipLevel::rgb: (x0, y0), (x1, y0), (x0, y1), (x1, y1)
    float ax, ay;
};
bool bilinearTaps(const MipLevel& level, glm::vec2 st, BilinearTaps& t) {
    const float x = st.x * static_cast<float>(level.width) - 0.5f, y = st.y * static_cast<float>(level.height) - 0.5f;
    if (!std::isfinite(x) || !std::isfinite(y)) return false;
    const float fx = std::floor(x), fy = std::floor(y);
    t.ax = x - fx;
    t.ay = y - fy;
    const long ix = static_cast<long>(fx), iy = static_cast<long>(fy);
    const std::size_t w = static_cast<std::size_t>(level.width);
    const std::size_t x0 = wrap(ix, level.width), x1 = wrap(ix + 1, level.width);
    const std::size_t y0 = wrap(iy, level.height), y1 = wrap(iy + 1, level.height);
    t.i00 = y0 * w + x0;
    t.i10 = y0 * w + x1;
    t.i01 = y1 * w + x0;
    t.i11 = y1 * w + x1;
    return true;
}

}  // namespace

glm::vec3 bilinear(const MipLevel& level, glm::vec2 st) {
    BilinearTaps t;
    if (!bilinearTaps(level, st, t)) return glm::vec3(1.0f);
    const glm::vec3 top = (1.0f - t.ax) * level.rgb[t.i00] + t.ax * level.rgb[t.i10];
    const glm::vec3 bottom = (1.0f - t.ax) * level.rgb[t.i01] + t.ax * level.rgb[t.i11];
    return (1.0f - t.ay) * top + t.ay * bottom;
}

glm::vec2 bilinearLuminanceGradient(const MipLevel& level, glm::vec2 st) {
    BilinearTaps t;
    if (!bilinearTaps(level, st, t)) return glm::vec2(0.0f);
    const auto lum = [&level](std::size_t i) {
        const glm::vec3& c = level.rgb[i];
        return 0.212671f * c.x + 0.715160f * c.y + 0.072169f * c.z;
    };
    const float f00 = lum(t.i00), f10 = lum(t.i10), f01 = lum(t.i01), f11 = lum(t.i11);
    const float ax = t.ax, ay = t.ay;
    // Per texel, then per unit of u and v (a texel is 1 / side of the texture).
    const float dx = (1.0f - ay) * (f10 - f00) + ay * (f11 - f01);
    const float dy = (1.0f - ax) * (f01 - f00) + ax * (f11 - f10);
    return {dx * static_cast<float>(level.width), dy * static_cast<float>(level.height)};
}

glm::vec3 filteredLookup(const std::vector<MipLevel>& chain, glm::vec2 st, glm::vec2 duvA, glm::vec2 duvB) {
    if (chain.empty()) return glm::vec3(1.0f);
    const glm::vec2 size(static_cast<float>(chain[0].width), static_cast<float>(chain[0].height));
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
