// The aamap filter chain on the CPU, following glsl/shared/aamap_filter.h.
//
// Scalar mode is the readable reference: one pixel at a time, every neighbour clamped to the edge.
// Parallel mode splits rows into TBB blocks. Interior rows (no clamping needed) run
// register-blocked vector code (8 float lanes with AVX2 where the CPU has it, else 4 with SSE;
// several vectors at a time): each pixel still sums its taps in the same order (dy, then dx) starting from 0, so both
// modes give bit-identical results. Borders reuse the scalar per-pixel code.
#include "passes/cpu_aamap.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>


#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
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

// --- Register-blocked interior rows ------------------------------------------------------------
// Interior rows (every tap in range) run 8 (AVX2) or 4 (SSE) pixels per vector and several vectors at a time, so the
// accumulators and centres stay in registers and independent add chains overlap. Each lane sums
// its taps in the order of `taps` starting from 0: the scalar order, so the results are the same
// bit for bit (no multiplies, so no FMA contraction either).

// The vector helpers are always inlined and file-local, so the AVX argument-passing ABI that GCC
// warns about never applies (the warning comes at the end of the file, hence no push/pop).
#pragma GCC diagnostic ignored "-Wpsabi"
// `Bytes` of float lanes: 32 = one AVX register, 16 = one SSE register (the baseline build; GCC
// spills 32-byte vectors it cannot hold in one register).
// (Spelled out per size: GCC drops vector_size on alias templates with a dependent size.)
template <int Bytes>
struct LaneTypes;
template <>
struct LaneTypes<16> {
    using Floats = float __attribute__((vector_size(16)));
    using Bits = std::int32_t __attribute__((vector_size(16)));
};
template <>
struct LaneTypes<32> {
    using Floats = float __attribute__((vector_size(32)));
    using Bits = std::int32_t __attribute__((vector_size(32)));
};
template <int Bytes>
using Lanes = typename LaneTypes<Bytes>::Floats;
#define AAMAP_ALWAYS_INLINE inline __attribute__((always_inline))

template <class V>
AAMAP_ALWAYS_INLINE V loadLanes(const float* p) {
    V v;
    std::memcpy(&v, p, sizeof v);
    return v;
}
template <class V>
AAMAP_ALWAYS_INLINE void storeLanes(float* p, V v) {
    std::memcpy(p, &v, sizeof v);
}

struct DiffTerm {  // Laplacian tap: g(p+o) - g(p)
    template <class V>
    AAMAP_ALWAYS_INLINE V operator()(V src, V centre) const { return src - centre; }
};
struct PlainTerm {  // blur tap: e(p+o)
    template <class V>
    AAMAP_ALWAYS_INLINE V operator()(V src, V) const { return src; }
};
struct AbsFinish {  // |sum|: clear the sign bit, as std::fabs does
    template <class V>
    AAMAP_ALWAYS_INLINE V operator()(V v) const {
        using Bits = typename LaneTypes<sizeof(V)>::Bits;
        return reinterpret_cast<V>(reinterpret_cast<Bits>(v) & 0x7fffffff);
    }
};
struct DivideFinish {  // sum / count, one division
    float count;
    template <class V>
    AAMAP_ALWAYS_INLINE V operator()(V v) const { return v / count; }
};

// out[i] = finish(sum over t of term(taps[t][i], centre[i])) for i in [0, n) in blocks of K
// vectors; returns where it stopped (the caller finishes the few left with scalar code).
template <int Bytes, int K, class Term, class Finish>
AAMAP_ALWAYS_INLINE int tapRow(const float* const* taps, int tapCount, const float* centre, float* out, int n,
                               Term term, Finish finish) {
    using V = Lanes<Bytes>;
    constexpr int L = Bytes / static_cast<int>(sizeof(float));
    int i = 0;
    for (; i + K * L <= n; i += K * L) {
        V c[K], acc[K];
        for (int k = 0; k < K; ++k) {
            c[k] = loadLanes<V>(centre + i + k * L);
            acc[k] = V{};
        }
        for (int t = 0; t < tapCount; ++t) {
            const float* src = taps[t] + i;
            for (int k = 0; k < K; ++k) acc[k] += term(loadLanes<V>(src + k * L), c[k]);
        }
        for (int k = 0; k < K; ++k) storeLanes(out + i + k * L, finish(acc[k]));
    }
    for (; i + L <= n; i += L) {
        const V c = loadLanes<V>(centre + i);
        V acc{};
        for (int t = 0; t < tapCount; ++t) acc += term(loadLanes<V>(taps[t] + i), c);
        storeLanes(out + i, finish(acc));
    }
    return i;
}

// Interior row y, columns [R, w-R): the 24 off-centre taps in row-major order.
template <int Bytes, int K>
AAMAP_ALWAYS_INLINE void laplacianRowImpl(const float* g, int w, int h, int y, float* out) {
    constexpr int R = kLaplacianRadius;
    const float* taps[(2 * R + 1) * (2 * R + 1) - 1];
    int count = 0;
    for (int dy = -R; dy <= R; ++dy)
        for (int dx = -R; dx <= R; ++dx)
            if (dx != 0 || dy != 0) taps[count++] = g + static_cast<std::ptrdiff_t>(y + dy) * w + R + dx;
    const float* centre = g + static_cast<std::size_t>(y) * w + R;
    const int n = w - 2 * R;
    for (int i = tapRow<Bytes, K>(taps, count, centre, out + R, n, DiffTerm{}, AbsFinish{}); i < n; ++i)
        out[R + i] = laplacianAt(g, w, h, R + i, y);
}

// Interior row y of the box blur, columns [r, w-r), taps in row-major order.
template <int Bytes, int K>
AAMAP_ALWAYS_INLINE void blurRowImpl(const float* e, int w, int h, int y, int radius, float* out,
                                     std::vector<const float*>& taps) {
    taps.clear();
    for (int dy = -radius; dy <= radius; ++dy)
        for (int dx = -radius; dx <= radius; ++dx)
            taps.push_back(e + static_cast<std::ptrdiff_t>(y + dy) * w + radius + dx);
    const int side = 2 * radius + 1;
    const float count = static_cast<float>(side * side);
    const int n = w - 2 * radius;
    const int done = tapRow<Bytes, K>(taps.data(), static_cast<int>(taps.size()), taps[0], out + radius, n,
                                      PlainTerm{}, DivideFinish{count});
    for (int i = done; i < n; ++i) out[radius + i] = blurAt(e, w, h, radius + i, y, radius);
}

// Chosen at run time: AVX2 where the CPU has it (4 vectors = 32 pixels in flight), else the
// baseline SSE build (4 vectors = 16 pixels). Streaming (non-temporal) stores for large outputs
// were tried and measured slower here, so the stores stay plain.
#define AAMAP_ROW_VARIANTS(attr, suffix, Bytes, K)                                                        \
    attr void laplacianRow##suffix(const float* g, int w, int h, int y, float* out) {                    \
        laplacianRowImpl<Bytes, K>(g, w, h, y, out);                                                     \
    }                                                                                                   \
    attr void blurRow##suffix(const float* e, int w, int h, int y, int radius, float* out,              \
                              std::vector<const float*>& taps) {                                       \
        blurRowImpl<Bytes, K>(e, w, h, y, radius, out, taps);                                           \
    }
AAMAP_ROW_VARIANTS(, Base, 16, 4)
#if defined(__x86_64__)
AAMAP_ROW_VARIANTS(__attribute__((target("avx2"))), Avx2, 32, 4)
const bool kHaveAvx2 = (__builtin_cpu_init(), __builtin_cpu_supports("avx2"));
#else
constexpr bool kHaveAvx2 = false;
#define laplacianRowAvx2 laplacianRowBase
#define blurRowAvx2 blurRowBase
#endif
#undef AAMAP_ROW_VARIANTS

// A clamped stencil of the given radius: scalar everywhere, or vectorised interior rows plus
// scalar borders. `atPixel(x, y)` and `interiorRow(y, out)` compute the same values.
template <class AtPixel, class InteriorRow>
ImageGrey stencil(int w, int h, int radius, Mode mode, AtPixel&& atPixel, InteriorRow&& interiorRow) {
    ImageGrey out(w, h);
    const bool vectorised = mode == Mode::Parallel && w > 2 * radius;
    forRows(h, mode, [&](int y0, int y1) {
        for (int y = y0; y < y1; ++y) {
            float* row = out.data() + static_cast<std::size_t>(y) * w;
            if (!vectorised || y < radius || y >= h - radius) {
                for (int x = 0; x < w; ++x) row[x] = atPixel(x, y);
                continue;
            }
            interiorRow(y, row);
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
        [&](int y, float* out) { (kHaveAvx2 ? laplacianRowAvx2 : laplacianRowBase)(g, w, h, y, out); });
}

ImageGrey boxBlur(const ImageGrey& edges, int radius, Mode mode) {
    if (radius < 0) throw std::invalid_argument("boxBlur: negative radius " + std::to_string(radius));
    const int w = edges.width(), h = edges.height();
    const float* e = edges.data();
    // One tap list per thread, reused across rows (the radius is not a compile-time constant).
    tbb::enumerable_thread_specific<std::vector<const float*>> taps;
    return stencil(
        w, h, radius, mode, [&](int x, int y) { return blurAt(e, w, h, x, y, radius); },
        [&](int y, float* out) { (kHaveAvx2 ? blurRowAvx2 : blurRowBase)(e, w, h, y, radius, out, taps.local()); });
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
