#include "passes/cpu_subpixel.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include <glm/common.hpp>

#include "core/image_io.h"
#include "glsl/shared/subpixel_map.h"

namespace aamap::cpu {

namespace {

// Step 3's test on one adjacent pair of samples.
bool geometryDiffers(const GeometryImages& g, int ax, int ay, int bx, int by) {
    const glm::vec4 na = g.normalDepth.at(ax, ay), nb = g.normalDepth.at(bx, by);
    const bool ca = na.w > 0.0f, cb = nb.w > 0.0f;
    if (ca != cb) return true;
    if (!ca) return false;
    const glm::vec4 ia = g.ids.at(ax, ay), ib = g.ids.at(bx, by);
    if (ia.x != ib.x || ia.y != ib.y) return true;  // object, material
    if (na.x * nb.x + na.y * nb.y + na.z * nb.z < static_cast<float>(SUBPIXEL_CREASE_COS)) return true;
    const float za = 1.0f / na.w, zb = 1.0f / nb.w;
    return std::abs(za - zb) > static_cast<float>(SUBPIXEL_DEPTH_TOLERANCE) * std::max(za, zb);
}

float maxOf(glm::vec3 v) { return std::max(v.r, std::max(v.g, v.b)); }

constexpr int kSteps[4][2] = {{1, 0}, {0, 1}, {-1, 0}, {0, -1}};

// own(q) of rule 2': an inside pair of pixel (qx, qy)'s samples differs.
bool ownGeometry(const GeometryImages& g, int k, int qx, int qy) {
    for (int j = 0; j < k; ++j)
        for (int i = 0; i < k; ++i) {
            const int sx = k * qx + i, sy = k * qy + j;
            if (i + 1 < k && geometryDiffers(g, sx, sy, sx + 1, sy)) return true;
            if (j + 1 < k && geometryDiffers(g, sx, sy, sx, sy + 1)) return true;
        }
    return false;
}

// border(p, p + step) of rule 2': a boundary pair between the pixel and that neighbour differs.
bool borderGeometry(const GeometryImages& g, int k, int px, int py, int dx, int dy) {
    for (int t = 0; t < k; ++t) {
        const int ox = dx != 0 ? (dx > 0 ? k - 1 : 0) : t, oy = dx != 0 ? t : (dy > 0 ? k - 1 : 0);
        const int sx = k * px + ox, sy = k * py + oy;
        if (geometryDiffers(g, sx, sy, sx + dx, sy + dy)) return true;
    }
    return false;
}

}  // namespace

SubpixelImages subpixelMap(const ImageRGB& colour, const GeometryImages& g, int k, float exposure, float tolerance,
                           bool shared) {
    if (k < SUBPIXEL_MIN_K || k > SUBPIXEL_MAX_K)
        throw std::invalid_argument("subpixelMap: k must be in [" + std::to_string(SUBPIXEL_MIN_K) + ", " +
                                    std::to_string(SUBPIXEL_MAX_K) + "], got " + std::to_string(k));
    const int Ws = g.normalDepth.width(), Hs = g.normalDepth.height();
    const int colourScale = shared ? 1 : k;
    if (Ws <= 0 || Hs <= 0 || Ws % k != 0 || Hs % k != 0 || colour.width() * k != Ws * colourScale ||
        colour.height() * k != Hs * colourScale || g.ids.width() != Ws || g.ids.height() != Hs)
        throw std::invalid_argument("subpixelMap: empty or mismatched images, or a size not a multiple of k");
    const int W = Ws / k, H = Hs / k;
    SubpixelImages out{ImageGrey(W, H, 0.0f), ImageGrey(W, H, 0.0f)};
    const auto display = [&](glm::vec3 rgb) {
        return glm::vec3(displayEncode(rgb.r, exposure), displayEncode(rgb.g, exposure), displayEncode(rgb.b, exposure));
    };
    const auto store = [&](int x, int y, float error) {
        out.error.at(x, y) = error;
        out.map.at(x, y) = error > tolerance ? 1.0f - tolerance / error : 0.0f;
    };
    if (shared) {  // rule 2'
        for (int y = 0; y < H; ++y)
            for (int x = 0; x < W; ++x) {
                const glm::vec3 dp = display(colour.at(x, y));
                const bool ownP = ownGeometry(g, k, x, y);
                bool geometry = ownP;
                glm::vec3 diff[4];
                for (int n = 0; n < 4; ++n) {
                    const int qx = x + kSteps[n][0], qy = y + kSteps[n][1];
                    diff[n] = glm::vec3(0.0f);
                    if (qx < 0 || qy < 0 || qx >= W || qy >= H) continue;
                    const bool border = borderGeometry(g, k, x, y, kSteps[n][0], kSteps[n][1]);
                    geometry = geometry || border;
                    if (!ownP && !border && ownGeometry(g, k, qx, qy)) continue;  // q's edge, q's step
                    diff[n] = display(colour.at(qx, qy)) - dp;
                }
                float error = 0.0f;
                for (int axis = 0; axis < 2; ++axis) {
                    const glm::vec3 a = diff[axis], b = -diff[axis + 2];
                    for (int c = 0; c < 3; ++c) {
                        float e = 0.5f * std::abs(a[c] - b[c]);
                        if (a[c] * b[c] > 0.0f) e += 0.25f * std::min(std::abs(a[c]), std::abs(b[c]));
                        error = std::max(error, e);
                    }
                }
                if (geometry) error = std::max(error, static_cast<float>(SUBPIXEL_GEOMETRY_ERROR) * tolerance);
                store(x, y, error);
            }
        return out;
    }
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) {
            glm::vec3 sum(0.0f);  // row-major, as the shader's
            for (int j = 0; j < k; ++j)
                for (int i = 0; i < k; ++i) sum += colour.at(k * x + i, k * y + j);
            const glm::vec3 mean = display(sum / static_cast<float>(k * k));
            float own = 0.0f;  // sum of the samples' deviations, row-major
            float error = 0.0f;
            bool geometry = false;
            for (int j = 0; j < k; ++j)
                for (int i = 0; i < k; ++i) {
                    const int sx = k * x + i, sy = k * y + j;
                    const glm::vec3 ds = display(colour.at(sx, sy));
                    own += maxOf(glm::abs(ds - mean));
                    for (int n = 0; n < 4; ++n) {
                        const int oi = i + kSteps[n][0], oj = j + kSteps[n][1];
                        const bool inside = oi >= 0 && oj >= 0 && oi < k && oj < k;
                        if (inside && n >= 2) continue;  // pairs inside the pixel once (right and down)
                        const int rx = k * x + oi, ry = k * y + oj;
                        if (rx < 0 || ry < 0 || rx >= Ws || ry >= Hs) continue;
                        if (!inside) error = std::max(error, 0.5f * maxOf(glm::abs(display(colour.at(rx, ry)) - ds)));
                        if (!geometry && geometryDiffers(g, sx, sy, rx, ry)) geometry = true;
                    }
                }
            error = std::max(error, own / static_cast<float>(k * k));
            if (geometry) error = std::max(error, static_cast<float>(SUBPIXEL_GEOMETRY_ERROR) * tolerance);
            store(x, y, error);
        }
    return out;
}

}  // namespace aamap::cpu
