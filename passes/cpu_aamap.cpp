// The aamap filter chain on the CPU, following glsl/shared/aamap_filter.h.
//
// Scalar mode is the readable reference: one pixel at a time, every neighbour clamped to the edge.
// Parallel mode splits rows into TBB bands and computes the same values bit for bit:
// - Laplacian: L = (sum of the 25 window values) - 25 g(p), which makes the sum separable: each
//   row's 5-wide sums are computed once and reused by the 5 output rows that see them
//   (row-sliding, 8 adds per pixel instead of 48). For grey in [0, 4] (the chain's grey is in
//   [0, 1]) the sums are in 32-bit fixed point (units of 2^-24, 8 lanes with AVX2): exact in any
//   order, |L| within 24 units (1.4e-6) of the shader's difference sum and correctly rounded when
//   the values lie on the 2^-24 grid; a constant image gives exactly 0. Any other image (HDR
//   grey above 4, negatives, NaN) takes the same scheme in double, where 25 floats spanning up to
//   24 binades sum exactly. Both modes use the same arithmetic, so they agree bit for bit. The
//   GPU sums 24 float differences and differs by its own rounding (< 5e-6 for inputs in [0,1]).
// - Box blur: register-blocked vector code over interior rows (8 float lanes with AVX2 where the
//   CPU has it, else 4 with SSE); each pixel sums its taps in the shader's order (dy, then dx)
//   from 0, so both modes and the GPU agree bit for bit. Borders reuse the scalar code.
#include "passes/cpu_aamap.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
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

// --- 5x5 Laplacian, exactly summed --------------------------------------------------------------

// Sum of the 5 values of row `row` centred on column x (clamped), in dx order.
inline double rowSum5(const float* row, int w, int x) {
    double s = static_cast<double>(row[clampIndex(x - 2, w)]);
    for (int dx = -1; dx <= 2; ++dx) s += static_cast<double>(row[clampIndex(x + dx, w)]);
    return s;
}

float laplacianAt(const float* g, int w, int h, int x, int y) {
    static_assert(kLaplacianRadius == 2, "the row-sliding Laplacian is written for the 5x5 window");
    const auto row = [&](int yy) { return g + static_cast<std::size_t>(clampIndex(yy, h)) * w; };
    double box = rowSum5(row(y - 2), w, x);
    for (int dy = -1; dy <= 2; ++dy) box += rowSum5(row(y + dy), w, x);
    const double centre = static_cast<double>(g[static_cast<std::size_t>(y) * w + x]);
    return std::fabs(static_cast<float>(box - 25.0 * centre));
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

// --- Row-sliding Laplacian -----------------------------------------------------------------------
// A band of output rows [y0, y1) is computed in column tiles of at most kTileColumns: each input
// row clamp(r), r in [y0-2, y1+2), is widened to double with its clamped 2-column margins (`wide`),
// summed 5 wide once (`rowSums`, a ring of the 5 rows an output row needs), and each output row
// adds its 5 row sums and subtracts 25 centres. Plain loops over restrict pointers: the compiler
// vectorises them (4 doubles per AVX2 register). The scratch is per thread and reused (no
// allocation per call); a tile's 6 rows of doubles (192 KiB) stay in L2 while the band streams.

constexpr int kTileColumns = 4096;
// Ring rows 320 bytes apart beyond a power of two: otherwise the 5 rows the inner loop reads and
// writes map to the same L1 sets (and 4K-alias the store), measured 5% slower.
constexpr int kRowStride = kTileColumns + 40;
constexpr int kBandRows = 64;  // rows per TBB task at least: 4 extra row sums per band (6% at most)

struct LaplacianScratch {
    std::vector<double> wide = std::vector<double>(kTileColumns + 4);
    std::vector<double> rowSums = std::vector<double>(5 * static_cast<std::size_t>(kRowStride));
};

#define AAMAP_ALWAYS_INLINE inline __attribute__((always_inline))

// wide[0, n+4) = row clamp(r), columns x0-2 .. x0+n+1 (clamped), as doubles.
AAMAP_ALWAYS_INLINE void widenRow(const float* g, int w, int h, int r, int x0, int n, double* __restrict wide) {
    const float* src = g + static_cast<std::size_t>(clampIndex(r, h)) * w;
    // Only columns outside [0, w) (2 at most per side) need clamping.
    const int inLo = std::max(0, 2 - x0), inHi = std::min(n + 4, w - x0 + 2);
    for (int i = 0; i < inLo; ++i) wide[i] = static_cast<double>(src[0]);
    const float* __restrict in = src + x0 - 2;
    for (int i = inLo; i < inHi; ++i) wide[i] = static_cast<double>(in[i]);
    for (int i = inHi; i < n + 4; ++i) wide[i] = static_cast<double>(src[w - 1]);
}

// out[x0, x0+n) of rows [y0, y1); n <= kTileColumns.
AAMAP_ALWAYS_INLINE void laplacianTileImpl(const float* g, int w, int h, int y0, int y1, int x0, int n, float* out,
                                           LaplacianScratch& scratch) {
    double* __restrict wide = scratch.wide.data();
    // The ring of 5-wide row sums: sums[k] holds row y - 2 + k while output row y is computed.
    double* sums[5];
    for (int k = 0; k < 5; ++k) sums[k] = scratch.rowSums.data() + static_cast<std::size_t>(k) * kRowStride;
    for (int k = 0; k < 4; ++k) {
        widenRow(g, w, h, y0 - 2 + k, x0, n, wide);
        double* __restrict s = sums[k];
        for (int i = 0; i < n; ++i) s[i] = wide[i] + wide[i + 1] + wide[i + 2] + wide[i + 3] + wide[i + 4];
    }
    for (int y = y0; y < y1; ++y) {
        widenRow(g, w, h, y + 2, x0, n, wide);
        const double* __restrict s0 = sums[0];
        const double* __restrict s1 = sums[1];
        const double* __restrict s2 = sums[2];
        const double* __restrict s3 = sums[3];
        double* __restrict s4 = sums[4];
        const float* __restrict centre = g + static_cast<std::size_t>(y) * w + x0;
        float* __restrict o = out + static_cast<std::size_t>(y) * w + x0;
#pragma GCC unroll 2
        for (int i = 0; i < n; ++i) {
            const double newest = wide[i] + wide[i + 1] + wide[i + 2] + wide[i + 3] + wide[i + 4];
            s4[i] = newest;
            const double box = s0[i] + s1[i] + s2[i] + s3[i] + newest;
            o[i] = std::fabs(static_cast<float>(box - 25.0 * static_cast<double>(centre[i])));
        }
        double* const oldest = sums[0];
        for (int k = 0; k < 4; ++k) sums[k] = sums[k + 1];
        sums[4] = oldest;
    }
}

// --- Register-blocked interior rows (box blur) -------------------------------------------------
// Interior rows (every tap in range) run 8 (AVX2) or 4 (SSE) pixels per vector and several vectors at a time, so the
// accumulators stay in registers and independent add chains overlap. Each lane sums
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

struct PlainTerm {  // blur tap: e(p+o)
    template <class V>
    AAMAP_ALWAYS_INLINE V operator()(V src, V) const { return src; }
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

// --- Row-sliding Laplacian in exact integer arithmetic --------------------------------------------
// The same row-sliding scheme on 8 int32 lanes (AVX2) instead of 4 doubles: each grey value g in
// [0, kFixedMax] becomes q = trunc(g * 2^24), which is exact for every float in [2^-1, kFixedMax]
// (and 0), and below 2^-1 within one unit (2^-24). Integer sums are exact in any order, so
// L = (sum of the 25 window q) - 25 q(p) is the exact difference sum of the q, and the result
// |float(L)| * 2^-24 is its correctly rounded value. Each of the 24 differences q(p+o) - q(p) is
// within one unit of the exact difference (both truncations lie in [0, 1) units), so
// |L * 2^-24 - exact L| < 24 * 2^-24 = 1.43e-6 before the final rounding, and 0 when every window
// value is a multiple of 2^-24 (a constant image gives exactly 0). Range: q <= 2^26, so 25 q
// <= 1.68e9 and |L| <= 24 * 2^26 = 1.61e9 fit int32. An image with any value outside [0, kFixedMax]
// (or a NaN) takes the exact double path above instead, in both modes.

constexpr float kFixedMax = 4.0f;
constexpr float kFixedScale = 16777216.0f;        // 2^24
constexpr float kFixedUnit = 1.0f / kFixedScale;  // 2^-24

// Clamped first so the conversion is always defined; a clamped value is reported by the caller.
AAMAP_ALWAYS_INLINE float clampFixed(float v) {
    v = v > 0.0f ? v : 0.0f;  // a NaN becomes 0
    return v < kFixedMax ? v : kFixedMax;
}
AAMAP_ALWAYS_INLINE std::int32_t toFixed(float v) { return static_cast<std::int32_t>(clampFixed(v) * kFixedScale); }
AAMAP_ALWAYS_INLINE float fromFixedMagnitude(std::int32_t l) { return std::fabs(static_cast<float>(l)) * kFixedUnit; }

bool inFixedRange(const ImageGrey& g) {
    for (float v : g.pixels())
        if (!(v >= 0.0f && v <= kFixedMax)) return false;
    return true;
}

// Scalar reference on the image converted to fixed point (q = toFixed(g), row-major).
float laplacianFixedAt(const std::int32_t* q, int w, int h, int x, int y) {
    std::int32_t box = 0;
    for (int dy = -2; dy <= 2; ++dy) {
        const std::int32_t* row = q + static_cast<std::size_t>(clampIndex(y + dy, h)) * w;
        for (int dx = -2; dx <= 2; ++dx) box += row[clampIndex(x + dx, w)];
    }
    return fromFixedMagnitude(box - 25 * q[static_cast<std::size_t>(y) * w + x]);
}

struct FixedScratch {
    std::vector<std::int32_t> rows = std::vector<std::int32_t>(3 * static_cast<std::size_t>(kRowStride));
    std::vector<std::int32_t> rowSums = std::vector<std::int32_t>(5 * static_cast<std::size_t>(kRowStride));
};

// q[0, n+4) = row clamp(r), columns x0-2 .. x0+n+1 (clamped), as fixed point; returns whether a
// value was outside [0, kFixedMax] (clamped here; the caller then discards the results).
// Written with vector types: GCC does not vectorise the plain loop (the compare and clamp).
template <int Bytes>
AAMAP_ALWAYS_INLINE bool fixedRow(const float* g, int w, int h, int r, int x0, int n, std::int32_t* __restrict q) {
    using V = Lanes<Bytes>;
    using B = typename LaneTypes<Bytes>::Bits;
    constexpr int L = Bytes / static_cast<int>(sizeof(float));
    const float* src = g + static_cast<std::size_t>(clampIndex(r, h)) * w;
    const int inLo = std::max(0, 2 - x0), inHi = std::min(n + 4, w - x0 + 2);
    const float* __restrict in = src + x0 - 2;
    B clampedLanes{};
    int i = inLo;
    for (; i + L <= inHi; i += L) {
        const V v = loadLanes<V>(in + i);
        V c = v > V{} ? v : V{};  // a NaN becomes 0
        c = c < kFixedMax ? c : V{} + kFixedMax;
        clampedLanes |= v != c;
        const B fixed = __builtin_convertvector(c * kFixedScale, B);
        std::memcpy(q + i, &fixed, sizeof fixed);
    }
    int clamped = 0;
    for (int k = 0; k < L; ++k) clamped |= clampedLanes[k];
    for (; i < inHi; ++i) {
        clamped |= in[i] != clampFixed(in[i]);
        q[i] = toFixed(in[i]);
    }
    for (int i = 0; i < inLo; ++i) q[i] = toFixed(src[0]);
    for (int i = inHi; i < n + 4; ++i) q[i] = toFixed(src[w - 1]);
    return clamped != 0;
}

// out[x0, x0+n) of rows [y0, y1); returns false if an input was out of range.
template <int Bytes>
AAMAP_ALWAYS_INLINE bool laplacianFixedTileImpl(const float* g, int w, int h, int y0, int y1, int x0, int n,
                                                float* out, FixedScratch& scratch) {
    // Rings: sums[k] holds the 5-wide sums of row y - 2 + k, rows[k] the fixed-point row y + k
    // (rows[0] gives the centres) while output row y is computed.
    std::int32_t* sums[5];
    std::int32_t* rows[3];
    for (int k = 0; k < 5; ++k) sums[k] = scratch.rowSums.data() + static_cast<std::size_t>(k) * kRowStride;
    for (int k = 0; k < 3; ++k) rows[k] = scratch.rows.data() + static_cast<std::size_t>(k) * kRowStride;
    bool clamped = false;
    for (int k = 0; k < 4; ++k) {
        std::int32_t* __restrict q = rows[k < 2 ? 0 : k - 2];
        clamped |= fixedRow<Bytes>(g, w, h, y0 - 2 + k, x0, n, q);
        std::int32_t* __restrict s = sums[k];
        for (int i = 0; i < n; ++i) s[i] = q[i] + q[i + 1] + q[i + 2] + q[i + 3] + q[i + 4];
    }
    for (int y = y0; y < y1; ++y) {
        clamped |= fixedRow<Bytes>(g, w, h, y + 2, x0, n, rows[2]);
        const std::int32_t* __restrict q = rows[2];
        const std::int32_t* __restrict c = rows[0] + 2;
        const std::int32_t* __restrict s0 = sums[0];
        const std::int32_t* __restrict s1 = sums[1];
        const std::int32_t* __restrict s2 = sums[2];
        const std::int32_t* __restrict s3 = sums[3];
        std::int32_t* __restrict s4 = sums[4];
        float* __restrict o = out + static_cast<std::size_t>(y) * w + x0;
        for (int i = 0; i < n; ++i) {
            const std::int32_t newest = q[i] + q[i + 1] + q[i + 2] + q[i + 3] + q[i + 4];
            s4[i] = newest;
            const std::int32_t box = s0[i] + s1[i] + s2[i] + s3[i] + newest;
            o[i] = fromFixedMagnitude(box - 25 * c[i]);
        }
        std::int32_t* const oldestSums = sums[0];
        for (int k = 0; k < 4; ++k) sums[k] = sums[k + 1];
        sums[4] = oldestSums;
        std::int32_t* const oldestRow = rows[0];
        rows[0] = rows[1];
        rows[1] = rows[2];
        rows[2] = oldestRow;
    }
    return !clamped;
}

// Chosen at run time: AVX2 where the CPU has it (4 vectors = 32 pixels in flight), else the
// baseline SSE build (4 vectors = 16 pixels). Streaming (non-temporal) stores for large outputs
// were tried and measured slower here, so the stores stay plain.
#define AAMAP_ROW_VARIANTS(attr, suffix, Bytes, K)                                                        \
    attr void laplacianTile##suffix(const float* g, int w, int h, int y0, int y1, int x0, int n, float* out, \
                                    LaplacianScratch& scratch) {                                        \
        laplacianTileImpl(g, w, h, y0, y1, x0, n, out, scratch);                                         \
    }                                                                                                   \
    attr bool laplacianFixedTile##suffix(const float* g, int w, int h, int y0, int y1, int x0, int n, float* out, \
                                         FixedScratch& scratch) {                                        \
        return laplacianFixedTileImpl<Bytes>(g, w, h, y0, y1, x0, n, out, scratch);                             \
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
#define laplacianTileAvx2 laplacianTileBase
#define laplacianFixedTileAvx2 laplacianFixedTileBase
#define blurRowAvx2 blurRowBase
#endif
#undef AAMAP_ROW_VARIANTS

// A clamped stencil of the given radius: scalar everywhere, or vectorised interior rows plus
// scalar borders. `atPixel(x, y)` and `interiorRow(y, out)` compute the same values.
template <class AtPixel, class InteriorRow>
void stencil(ImageGrey& out, int w, int h, int radius, Mode mode, AtPixel&& atPixel, InteriorRow&& interiorRow) {
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
}

// The filters write into `out`, reallocating it only when its size differs: a caller that keeps
// its output image between calls pays no allocation and no zero-fill (64 MiB at 4096^2).
void prepareOutput(const ImageGrey& in, ImageGrey& out, const char* what) {
    if (&in == &out) throw std::invalid_argument(std::string(what) + ": the output must not be the input");
    if (out.width() != in.width() || out.height() != in.height()) out = ImageGrey(in.width(), in.height());
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

void laplacianMagnitudeInto(const ImageGrey& grey, ImageGrey& out, Mode mode) {
    prepareOutput(grey, out, "laplacianMagnitude");
    const int w = grey.width(), h = grey.height();
    const float* g = grey.data();
    float* o = out.data();
    if (mode == Mode::Scalar) {
        if (!inFixedRange(grey)) {
            for (int y = 0; y < h; ++y)
                for (int x = 0; x < w; ++x) o[static_cast<std::size_t>(y) * w + x] = laplacianAt(g, w, h, x, y);
            return;
        }
        std::vector<std::int32_t> q(grey.size());
        std::transform(grey.pixels().begin(), grey.pixels().end(), q.begin(), toFixed);
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x) o[static_cast<std::size_t>(y) * w + x] = laplacianFixedAt(q.data(), w, h, x, y);
        return;
    }
    // Integer path; every input is read by some band, so `outOfRange` is set iff the image has a
    // value outside [0, kFixedMax], and then the whole image is recomputed in double (rare: the
    // chain's grey is in [0, 1]).
    std::atomic<bool> outOfRange{false};
    const auto fixedTile = kHaveAvx2 ? laplacianFixedTileAvx2 : laplacianFixedTileBase;
    tbb::parallel_for(tbb::blocked_range<int>(0, h, kBandRows), [&](const tbb::blocked_range<int>& rows) {
        thread_local FixedScratch scratch;
        for (int x0 = 0; x0 < w; x0 += kTileColumns)
            if (!fixedTile(g, w, h, rows.begin(), rows.end(), x0, std::min(kTileColumns, w - x0), o, scratch))
                outOfRange.store(true, std::memory_order_relaxed);
    });
    if (!outOfRange.load()) return;
    const auto tile = kHaveAvx2 ? laplacianTileAvx2 : laplacianTileBase;
    tbb::parallel_for(tbb::blocked_range<int>(0, h, kBandRows), [&](const tbb::blocked_range<int>& rows) {
        thread_local LaplacianScratch scratch;
        for (int x0 = 0; x0 < w; x0 += kTileColumns)
            tile(g, w, h, rows.begin(), rows.end(), x0, std::min(kTileColumns, w - x0), o, scratch);
    });
}

ImageGrey laplacianMagnitude(const ImageGrey& grey, Mode mode) {
    ImageGrey out;
    laplacianMagnitudeInto(grey, out, mode);
    return out;
}

void flatGate(const ImageGrey& grey, ImageGrey& edges, float flatRange, Mode mode) {
    if (grey.width() != edges.width() || grey.height() != edges.height())
        throw std::invalid_argument("flatGate: grey and edges differ in size");
    if (!(flatRange > 0.0f)) return;
    static_assert(AAMAP_FLAT_GATE_RADIUS == 1, "the flat gate is written for the 3x3 window");
    const int w = grey.width(), h = grey.height();
    const float* g = grey.data();
    // Per row: the column-wise min and max over rows y-1..y+1, then over three columns. Min and
    // max are exact in any order, so this decides as the shader's window does.
    forRows(h, mode, [&](int y0, int y1) {
        std::vector<float> lo(static_cast<std::size_t>(w)), hi(static_cast<std::size_t>(w));
        for (int y = y0; y < y1; ++y) {
            const float* above = g + static_cast<std::size_t>(clampIndex(y - 1, h)) * w;
            const float* row = g + static_cast<std::size_t>(y) * w;
            const float* below = g + static_cast<std::size_t>(clampIndex(y + 1, h)) * w;
            for (int x = 0; x < w; ++x) {
                lo[x] = std::min(std::min(above[x], row[x]), below[x]);
                hi[x] = std::max(std::max(above[x], row[x]), below[x]);
            }
            float* e = edges.data() + static_cast<std::size_t>(y) * w;
            for (int x = 0; x < w; ++x) {
                const int l = clampIndex(x - 1, w), r = clampIndex(x + 1, w);
                const float span = std::max(std::max(hi[l], hi[x]), hi[r]) - std::min(std::min(lo[l], lo[x]), lo[r]);
                if (!(span >= flatRange)) e[x] = 0.0f;
            }
        }
    });
}

void boxBlurInto(const ImageGrey& edges, int radius, ImageGrey& out, Mode mode) {
    if (radius < 0) throw std::invalid_argument("boxBlur: negative radius " + std::to_string(radius));
    prepareOutput(edges, out, "boxBlur");
    const int w = edges.width(), h = edges.height();
    const float* e = edges.data();
    stencil(
        out, w, h, radius, mode, [&](int x, int y) { return blurAt(e, w, h, x, y, radius); },
        [&](int y, float* row) {
            thread_local std::vector<const float*> taps;  // reused across rows and calls
            (kHaveAvx2 ? blurRowAvx2 : blurRowBase)(e, w, h, y, radius, row, taps);
        });
}

ImageGrey boxBlur(const ImageGrey& edges, int radius, Mode mode) {
    ImageGrey out;
    boxBlurInto(edges, radius, out, mode);
    return out;
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
    flatGate(result.grey, result.laplacian, params.flatRange, mode);
    const ImageGrey blurred = boxBlur(result.laplacian, params.blurRadius, mode);
    const ImageGrey map = deadZone(blurred, params.noiseFloor, params.gain, mode);
    result.aamap = reduceMax(map, width, height, mode);
    return result;
}

}  // namespace aamap::cpu
