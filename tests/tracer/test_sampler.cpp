#include <cmath>
#include <cstdint>
#include <set>
#include <vector>

#include <gtest/gtest.h>

#include "tracer/sampler.h"

namespace aamap {
namespace {

TEST(Sampler, OneSamplePerStratumForEveryK) {
    for (std::uint64_t seed : {1ull, 7ull, 123456789ull}) {
        for (std::uint64_t pixel : {0ull, 1ull, 511ull, 262143ull}) {
            for (int k = 1; k <= 8; ++k) {
                std::vector<int> hits(static_cast<std::size_t>(k * k), 0);
                for (int sy = 0; sy < k; ++sy) {
                    for (int sx = 0; sx < k; ++sx) {
                        const Sampler s(pixel, static_cast<std::uint32_t>(sy * k + sx), seed);
                        const glm::vec2 p = s.stratified2D(dims::kFilm, sx, sy, k);
                        ASSERT_GE(p.x, 0.0f);
                        ASSERT_LT(p.x, 1.0f);
                        ASSERT_GE(p.y, 0.0f);
                        ASSERT_LT(p.y, 1.0f);
                        const int cx = static_cast<int>(std::floor(static_cast<double>(p.x) * k));
                        const int cy = static_cast<int>(std::floor(static_cast<double>(p.y) * k));
                        ASSERT_EQ(cx, sx) << "k=" << k;
                        ASSERT_EQ(cy, sy) << "k=" << k;
                        ++hits[static_cast<std::size_t>(cy * k + cx)];
                    }
                }
                for (int h : hits) EXPECT_EQ(h, 1) << "k=" << k;
            }
        }
    }
}

TEST(Sampler, StratumBordersSurviveFloatRounding) {
    const float rMax = 1.0f - 0x1p-24f;  // the largest value get1D can return
    for (int k = 1; k <= 255; ++k) {
        for (int s = 0; s < k; ++s) {
            for (float r : {0.0f, rMax}) {
                const float v = Sampler::inStratum(s, r, k);
                ASSERT_GE(static_cast<double>(v), static_cast<double>(s) / k) << k << " " << s;
                ASSERT_LT(static_cast<double>(v), static_cast<double>(s + 1) / k) << k << " " << s;
            }
        }
    }
}

TEST(Sampler, SameKeySameValueAndKeysAreIndependent) {
    const Sampler a(42, 3, 1), b(42, 3, 1);
    for (std::uint32_t d = 0; d < 64; ++d) EXPECT_EQ(a.bits(d), b.bits(d));
    EXPECT_EQ(a.get1D(5), b.get1D(5));

    const Sampler otherSeed(42, 3, 2), otherPixel(43, 3, 1), otherSample(42, 4, 1);
    int sameSeed = 0, samePixel = 0, sameSample = 0, sameDim = 0;
    for (std::uint32_t d = 0; d < 64; ++d) {
        sameSeed += a.get1D(d) == otherSeed.get1D(d);
        samePixel += a.get1D(d) == otherPixel.get1D(d);
        sameSample += a.get1D(d) == otherSample.get1D(d);
        sameDim += a.get1D(d) == a.get1D(d + 1);
    }
    EXPECT_EQ(sameSeed, 0);
    EXPECT_EQ(samePixel, 0);
    EXPECT_EQ(sameSample, 0);
    EXPECT_EQ(sameDim, 0);
}

TEST(Sampler, UniformEnough) {
    // Mean and a 16-bin histogram over many keys: catches a broken mix, not subtle bias.
    constexpr int kCount = 1 << 16;
    std::vector<int> bins(16, 0);
    double sum = 0.0;
    for (int i = 0; i < kCount; ++i) {
        const float u = Sampler(static_cast<std::uint64_t>(i), 0, 9).get1D(dims::kFilm);
        ASSERT_GE(u, 0.0f);
        ASSERT_LT(u, 1.0f);
        sum += u;
        ++bins[static_cast<std::size_t>(u * 16)];
    }
    EXPECT_NEAR(sum / kCount, 0.5, 0.005);
    for (int b : bins) EXPECT_NEAR(b, kCount / 16, kCount / 16 * 0.05);
}

TEST(Sampler, AreaLightDimensionsAreDistinct) {
    std::set<std::uint64_t> seen;
    for (int depth = 0; depth < 4; ++depth)
        for (int light = 0; light < 8; ++light)
            for (int j = 0; j < 64; ++j) {
                const std::uint64_t d = dims::areaLight(depth, light, j);
                EXPECT_TRUE(seen.insert(d).second);
                EXPECT_TRUE(seen.insert(d + 1).second);
                EXPECT_NE(d, dims::kFilm);
                EXPECT_NE(d, dims::kFilm + 1);
            }
}

}  // namespace
}  // namespace aamap
