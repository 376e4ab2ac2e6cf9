// The aamap filter chain on the CPU, following glsl/shared/aamap_filter.h.
//
// Scalar mode is the readable reference: one pixel at a time, every neighbour clamped to the edge.
// Parallel mode splits rows into TBB blocks. In the interior, where no clamping is needed, the
// stencils run tap-outer / pixel-inner over a row of accumulators, so the inner loop is a plain
// vectorisable `acc[i] += src[i] - centre[i]`. Each pixel still sums its taps in the same order
// (dy, then dx) starting from 0, so both modes give bit-identical results. Borders reuse the
// scalar per-pixel code.
#include "passes/cpu_aamap.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

namespace aamap::cpu {
namespace {

constexpr float kLumaR = static_cast<float>(AAMAP_LUMA_R);
constexpr float kLumaG = static_cast<float>(AAMAP_LUMA_G);
constexpr float kLumaB = static_cast<float>(AAMAP_LUMA_B);
constexpr int kLaplacianRadius = AAMAP_LAPLACIAN_RADIUS;
constexpr int kRowGrain = 8;  // rows per TBB task at least: keeps per-task overhead small

// Branch-free forms so the compiler can use max/min instructions; a NaN becomes 0.
inline float clamp01(float v) {
    v = v > 0.0f ? v : 0.0f;
    return v < 1.0f ? v : 1.0f;
}
inline float maxOf(float a, float b) { return b > a ? b : a; }
inline int clampIndex(int i, int n) { return std::min(std::max(i, 0), n - 1); }

// The standard sRGB encoding curve (IEC 61966-2-1).
inline float srgbEncode(float c) {
    return c <= 0.0031308f ? 12.92f * c : 1.055f * std::pow(c, 1.0f / 2.4f) - 0.055f;
}

inline float greyOf(const glm::vec3& rgb, float exposure) {
    const float r = srgbEncode(clamp01(exposure * rgb.r));
    const float g = srgbEncode(clamp01(exposure * rgb.g));
    const float b = srgbEncode(clamp01(exposure * rgb.b));
    return kLumaR * r + kLumaG * g + kLumaB * b;
}

// Runs body(y0, y1) over all rows, on TBB or inline.
template <class Body>
void forRows(int height, Mode mode, Body&& body) {
    if (mode == Mode::Scalar) {
        body(0, height);
        return;
    }
    tbb::parallel_for(tbb::blocked_range<int>(0, height, kRowGrain),
                      [&](const tbb::blocked_range<int>& r) { body(r.begin(), r.end()); });
}

// --- 5x5 Laplacian in difference form --------------------------------------------------------

float laplacianAt(const float* g, int w, int h, int x, int y) {
    const float centre = g[static_cast<std::size_t>(y) * w + x];
    float sum = 0.0f;
    for (int dy = -kLaplacianRadius; dy <= kLaplacianRadius; ++dy) {
        const float* row = g + static_cast<std::size_t>(clampIndex(y + dy, h)) * w;
        for (int dx = -kLaplacianRadius; dx <= kLaplacianRadius; ++dx) {
            if (dx == 0 && dy == 0) continue;
            sum += row[clampIndex(x + dx, w)] - centre;
        }
    }
    return std::fabs(sum);
}

// Interior row y (all taps in range), columns [R, w-R). `acc` holds w - 2R floats.
void laplacianInteriorRow(const float* g, int w, int y, float* __restrict out, float* __restrict acc) {
    constexpr int R = kLaplacianRadius;
    const int n = w - 2 * R;
    const float* __restrict centre = g + static_cast<std::size_t>(y) * w + R;
    std::fill(acc, acc + n, 0.0f);
    for (int dy = -R; dy <= R; ++dy) {
        const float* row = g + static_cast<std::size_t>(y + dy) * w + R;
        for (int dx = -R; dx <= R; ++dx) {
            if (dx == 0 && dy == 0) continue;
            const float* __restrict src = row + dx;
            for (int i = 0; i < n; ++i) acc[i] += src[i] - centre[i];
        }
    }
    for (int i = 0; i < n; ++i) out[R + i] = std::fabs(acc[i]);
}

// --- Box blur ----------------------------------------------------------------------------------

float blurAt(const float* e, int w, int h, int x, int y, int radius) {
    float sum = 0.0f;
    for (int dy = -radius; dy <= radius; ++dy) {
        const float* row = e + static_cast<std::size_t>(clampIndex(y + dy, h)) * w;
        for (int dx = -radius; dx <= radius; ++dx) sum += row[clampIndex(x + dx, w)];
    }
    const int side = 2 * radius + 1;
    return sum / static_cast<float>(side * side);
}

void blurInteriorRow(const float* e, int w, int y, int radius, float* __restrict out, float* __restrict acc) {
    const int n = w - 2 * radius;
    std::fill(acc, acc + n, 0.0f);
    for (int dy = -radius; dy <= radius; ++dy) {
        const float* row = e + static_cast<std::size_t>(y + dy) * w + radius;
        for (int dx = -radius; dx <= radius; ++dx) {
            const float* __restrict src = row + dx;
            for (int i = 0; i < n; ++i) acc[i] += src[i];
        }
    }
    const int side = 2 * radius + 1;
    const float count = static_cast<float>(side * side);
    for (int i = 0; i < n; ++i) out[radius + i] = acc[i] / count;
}

// A clamped stencil of the given radius: scalar everywhere, or vectorised interior rows plus
// scalar borders. `atPixel(x, y)` and `interiorRow(y, out, acc)` compute the same values.
template <class AtPixel, class InteriorRow>
ImageGrey stencil(int w, int h, int radius, Mode mode, AtPixel&& atPixel, InteriorRow&& interiorRow) {
    ImageGrey out(w, h);
    const bool vectorised = mode == Mode::Parallel && w > 2 * radius;
    forRows(h, mode, [&](int y0, int y1) {
        std::vector<float> acc(vectorised ? static_cast<std::size_t>(w - 2 * radius) : 0);
        for (int y = y0; y < y1; ++y) {
            float* row = out.data() + static_cast<std::size_t>(y) * w;
            if (!vectorised || y < radius || y >= h - radius) {
                for (int x = 0; x < w; ++x) row[x] = atPixel(x, y);
                continue;
            }
            interiorRow(y, row, acc.data());
            for (int x = 0; x < radius; ++x) {
                row[x] = atPixel(x, y);
                row[w - 1 - x] = atPixel(w - 1 - x, y);
            }
        }
    });
    return out;
}

// --- Max reduction -----------------------------------------------------------------------------

// Snapshot texels [lo, hi) whose footprint overlaps output pixel i's footprint
// [i*src/dst, (i+1)*src/dst) with non-zero length.
struct Span {
    int lo, hi;
};
std::vector<Span> footprints(int src, int dst) {
    std::vector<Span> spans(static_cast<std::size_t>(dst));
    const std::int64_t s = src, d = dst;
    for (std::int64_t i = 0; i < d; ++i) {
        const std::int64_t lo = i * s / d;                  // floor of the interval start
        const std::int64_t hi = ((i + 1) * s + d - 1) / d;  // ceil of the interval end
        spans[static_cast<std::size_t>(i)] = {static_cast<int>(lo), static_cast<int>(hi)};
    }
    return spans;
}

void requireImage(const ImageGrey& image, const char* what) {
    if (image.width() <= 0 || image.height() <= 0) throw std::invalid_argument(std::string(what) + ": empty image");
}

}  // namespace

ImageGrey greyscale(const ImageRGB& rgb, float exposure, Mode mode) {
    ImageGrey out(rgb.width(), rgb.height());
    const int w = rgb.width();
    forRows(rgb.height(), mode, [&](int y0, int y1) {
        const std::size_t begin = static_cast<std::size_t>(y0) * w, end = static_cast<std::size_t>(y1) * w;
        for (std::size_t i = begin; i < end; ++i) out.data()[i] = greyOf(rgb.data()[i], exposure);
    });
    return out;
}

ImageGrey laplacianMagnitude(const ImageGrey& grey, Mode mode) {
    const int w = grey.width(), h = grey.height();
    const float* g = grey.data();
    return stencil(
        w, h, kLaplacianRadius, mode, [&](int x, int y) { return laplacianAt(g, w, h, x, y); },
        [&](int y, float* out, float* acc) { laplacianInteriorRow(g, w, y, out, acc); });
}

ImageGrey boxBlur(const ImageGrey& edges, int radius, Mode mode) {
    if (radius < 0) throw std::invalid_argument("boxBlur: negative radius " + std::to_string(radius));
    const int w = edges.width(), h = edges.height();
    const float* e = edges.data();
    return stencil(
        w, h, radius, mode, [&](int x, int y) { return blurAt(e, w, h, x, y, radius); },
        [&](int y, float* out, float* acc) { blurInteriorRow(e, w, y, radius, out, acc); });
}

ImageGrey deadZone(const ImageGrey& blurred, float noiseFloor, float gain, Mode mode) {
    ImageGrey out(blurred.width(), blurred.height());
    const int w = blurred.width();
    forRows(blurred.height(), mode, [&](int y0, int y1) {
        const std::size_t begin = static_cast<std::size_t>(y0) * w, end = static_cast<std::size_t>(y1) * w;
        const float* __restrict in = blurred.data();
        float* __restrict o = out.data();
        for (std::size_t i = begin; i < end; ++i) o[i] = clamp01(gain * (in[i] - noiseFloor));
    });
    return out;
}

ImageGrey reduceMax(const ImageGrey& map, int width, int height, Mode mode) {
    requireImage(map, "reduceMax");
    if (width <= 0 || height <= 0) throw std::invalid_argument("reduceMax: non-positive output size");
    const int ws = map.width(), hs = map.height();
    const std::vector<Span> xs = footprints(ws, width), ys = footprints(hs, height);
    ImageGrey out(width, height);
    const float* m = map.data();
    constexpr float kLowest = -std::numeric_limits<float>::infinity();

    // Both modes visit texels column by column (x, then y): max is exact and keeps the first of
    // equal values (which matters for +0 and -0), so the same visiting order makes them agree bit for bit.
    if (mode == Mode::Scalar) {
        for (int y = 0; y < height; ++y)
            for (int x = 0; x < width; ++x) {
                float v = kLowest;
                for (int i = xs[x].lo; i < xs[x].hi; ++i)
                    for (int j = ys[y].lo; j < ys[y].hi; ++j) v = maxOf(v, m[static_cast<std::size_t>(j) * ws + i]);
                out.at(x, y) = v;
            }
        return out;
    }
    // Separable: a vectorised max over the rows of the output row's footprint, then over columns.
    forRows(height, mode, [&](int y0, int y1) {
        std::vector<float> column(static_cast<std::size_t>(ws));
        float* __restrict col = column.data();
        for (int y = y0; y < y1; ++y) {
            std::fill(col, col + ws, kLowest);
            for (int j = ys[y].lo; j < ys[y].hi; ++j) {
                const float* __restrict src = m + static_cast<std::size_t>(j) * ws;
                for (int i = 0; i < ws; ++i) col[i] = maxOf(col[i], src[i]);
            }
            float* dst = out.data() + static_cast<std::size_t>(y) * width;
            for (int x = 0; x < width; ++x) {
                float v = kLowest;
                for (int i = xs[x].lo; i < xs[x].hi; ++i) v = maxOf(v, col[i]);
                dst[x] = v;
            }
        }
    });
    return out;
}

AamapImages buildAamap(const ImageRGB& snapshot, int width, int height, const FilterParams& params, Mode mode) {
    if (snapshot.empty()) throw std::invalid_argument("buildAamap: empty snapshot");
    AamapImages result;
    result.grey = greyscale(snapshot, params.exposure, mode);
    result.laplacian = laplacianMagnitude(result.grey, mode);
    const ImageGrey blurred = boxBlur(result.laplacian, params.blurRadius, mode);
    const ImageGrey map = deadZone(blurred, params.noiseFloor, params.gain, mode);
    result.aamap = reduceMax(map, width, height, mode);
    return result;
}

}  // namespace aamap::cpu
