#pragma once
// Counter-based random numbers: every value is a pure function of
// (pixel index, sample index, seed, dimension), so an image does not depend on the thread count,
// the tile order or on how many numbers another pixel consumed. Replaying one sample
// (--debug-pixel x,y,s) only needs those four integers.
#include <algorithm>
#include <cmath>
#include <cstdint>

#include <glm/vec2.hpp>

namespace aamap {

// A 64-bit finaliser (Stafford's variant 13 of the MurmurHash3 mix, as in SplitMix64): every input
// bit affects every output bit, which is what a counter-based generator needs.
constexpr std::uint64_t mix64(std::uint64_t x) {
    x ^= x >> 30;
    x *= 0xbf58476d1ce4e5b9ULL;
    x ^= x >> 27;
    x *= 0x94d049bb133111ebULL;
    x ^= x >> 31;
    return x;
}

// Where each consumer of random numbers draws from. Dimensions only need to be distinct; they are
// hashed, not used as offsets. A 2D draw uses `dim` and `dim + 1`.
namespace dims {
constexpr std::uint64_t kFilm = 0;  // 2D: jitter inside the pixel's stratum
// Area light `light` (< 2^24), light sample `sample` (< 2^23) at bounce `depth` (< 2^15).
constexpr std::uint64_t areaLight(int depth, int light, int sample) {
    return (1ull << 63) | (static_cast<std::uint64_t>(depth) << 48) | (static_cast<std::uint64_t>(light) << 24) |
           (2ull * static_cast<std::uint64_t>(sample));
}
}  // namespace dims

class Sampler {
public:
    Sampler() = default;  // unkeyed: for arrays whose entries are assigned before use
    // The key for (pixel, sample, seed) is hashed once; each draw then costs one mix.
    Sampler(std::uint64_t pixelIndex, std::uint32_t sampleIndex, std::uint64_t seed)
        : key_(mix64(mix64(mix64(seed + 0x9e3779b97f4a7c15ULL) ^ pixelIndex) ^ sampleIndex)) {}

    // An independent stream for branch `index` of a sample's ray tree (direct mode's glossy rays):
    // the branches below it then draw their own numbers for the same dimensions.
    Sampler branch(std::uint64_t index) const {
        Sampler s;
        s.key_ = mix64(key_ ^ (0x8cb92ba72f3d8dd7ULL * (index + 1)));
        return s;
    }

    std::uint64_t bits(std::uint64_t dim) const { return mix64(key_ ^ dimSalt(dim)); }
    // What bits() mixes into the key for `dim`: SIMD draws (tracer/path_simd.cpp) hash the same.
    static constexpr std::uint64_t dimSalt(std::uint64_t dim) { return 0xd1b54a32d192ed03ULL * (dim + 1); }
    std::uint64_t key() const { return key_; }

    // Uniform in [0, 1): the top 24 bits, so the value is exact in a float and never rounds to 1.
    float get1D(std::uint64_t dim) const { return static_cast<float>(bits(dim) >> 40) * 0x1p-24f; }
    glm::vec2 get2D(std::uint64_t dim) const { return {get1D(dim), get1D(dim + 1)}; }

    // One jittered point in stratum (sx, sy) of a k x k grid over [0,1)^2. Guaranteed to lie in
    // [sx/k, (sx+1)/k) x [sy/k, (sy+1)/k) (float rounding is corrected at the stratum borders).
    glm::vec2 stratified2D(std::uint64_t dim, int sx, int sy, int k) const {
        const glm::vec2 r = get2D(dim);
        return {inStratum(sx, r.x, k), inStratum(sy, r.y, k)};
    }

    // The same point without the border correction, for consumers that do not need the strict
    // one-per-stratum guarantee (light samples): a float multiply instead of double divisions.
    glm::vec2 jittered2D(std::uint64_t dim, int sx, int sy, float invK) const {
        const glm::vec2 r = get2D(dim);
        return {std::min((static_cast<float>(sx) + r.x) * invK, kOneMinusUlp),
                std::min((static_cast<float>(sy) + r.y) * invK, kOneMinusUlp)};
    }

    static constexpr float kOneMinusUlp = 0x1.fffffep-1f;  // largest float below 1

    // (sx + r) / k, rounded into the stratum [s/k, (s+1)/k) as a float.
    static float inStratum(int s, float r, int k) {
        const double lo = static_cast<double>(s) / k;
        const double hi = static_cast<double>(s + 1) / k;
        float v = static_cast<float>((s + static_cast<double>(r)) / k);
        if (static_cast<double>(v) >= hi) v = std::nextafter(v, 0.0f);
        if (static_cast<double>(v) < lo) v = std::nextafter(v, 1.0f);
        return v;
    }

private:
    std::uint64_t key_ = 0;
};

}  // namespace aamap
