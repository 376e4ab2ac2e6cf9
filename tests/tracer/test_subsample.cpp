// Block sums, the strata mappings and the paper's adaptive subsampling, on synthetic images.
#include <cmath>
#include <limits>
#include <random>

#include <gtest/gtest.h>

#include "core/image_io.h"
#include "tests/tracer/synthetic_source.h"
#include "tracer/block_sums.h"
#include "tracer/strategies/subsample.h"

namespace aamap {
namespace {

using testing::runStrategy;
using testing::strategy;
using testing::SyntheticSource;

TEST(BlockSums, MatchBruteForceWithClampingAndNaN) {
    const int w = 13, h = 9;
    ImageGrey map(w, h);
    std::mt19937 rng(3);
    std::uniform_real_distribution<float> u(-0.5f, 1.5f);
    for (float& v : map.pixels()) v = u(rng);
    map.at(4, 4) = std::numeric_limits<float>::quiet_NaN();
    const BlockSums sums(map);
    auto value = [&](int x, int y) {
        const float a = map.at(x, y);
        return std::isnan(a) ? 1.0 : std::clamp(static_cast<double>(a), 0.0, 1.0);
    };
    for (int y0 = 0; y0 < h; y0 += 2)
        for (int x0 = 0; x0 < w; x0 += 3)
            for (int y1 = y0; y1 < h; y1 += 3)
                for (int x1 = x0; x1 < w; x1 += 2) {
                    double expected = 0.0;
                    for (int y = y0; y <= y1; ++y)
                        for (int x = x0; x <= x1; ++x) expected += value(x, y);
                    EXPECT_NEAR(sums.sum(x0, y0, x1, y1), expected, 1e-9);
                }
    EXPECT_EQ(sums.sum(5, 5, 4, 5), 0.0);                         // empty
    EXPECT_NEAR(sums.sum(-3, -3, 100, 100), sums.sum(0, 0, w - 1, h - 1), 1e-12);  // clipped
}

TEST(BlockSums, ZeroBlocksSumToExactlyZero) {
    // Large and tiny values around a zero block: the double table alone could leave a residue.
    ImageGrey map(64, 64, 0.0f);
    for (int y = 0; y < 64; ++y)
        for (int x = 0; x < 64; ++x)
            if (x < 20 || y < 20) map.at(x, y) = (x * 7 + y * 13) % 5 == 0 ? 0.9999f : 1e-7f * static_cast<float>(x + 1);
    const BlockSums sums(map);
    for (int y0 = 20; y0 < 64; y0 += 5)
        for (int x0 = 20; x0 < 64; x0 += 7) EXPECT_EQ(sums.sum(x0, y0, 63, 63), 0.0);
    EXPECT_GT(sums.sum(19, 20, 19, 20), 0.0);
    EXPECT_THROW(BlockSums::fromTables(2, 2, {}, {}), std::invalid_argument);
}

TEST(StrataMapping, PaperAndLinearInRays) {
    EXPECT_EQ(stratification(0.5f, 6, StrataMapping::Paper), 4);
    EXPECT_EQ(stratification(0.0f, 6, StrataMapping::LinearRays), 1);
    EXPECT_EQ(stratification(1.0f, 6, StrataMapping::LinearRays), 6);
    EXPECT_EQ(stratification(0.5f, 6, StrataMapping::LinearRays), 4);   // sqrt(18.5) = 4.3
    EXPECT_EQ(stratification(0.25f, 6, StrataMapping::LinearRays), 3);  // sqrt(9.75) = 3.1
    EXPECT_EQ(stratification(0.1f, 32, StrataMapping::LinearRays), 10);  // sqrt(103.3)
    EXPECT_EQ(stratification(std::numeric_limits<float>::quiet_NaN(), 5, StrataMapping::LinearRays), 5);
    for (int n : {1, 2, 7, 32, kMaxStrata})
        for (float a = 0.0f; a <= 1.0f; a += 0.05f) {
            const int k = stratification(a, n, StrataMapping::LinearRays);
            EXPECT_GE(k, 1);
            EXPECT_LE(k, n);
        }
    StrataMapping m{};
    EXPECT_TRUE(parse("linear-rays", m));
    EXPECT_EQ(m, StrataMapping::LinearRays);
    EXPECT_FALSE(parse("linear", m));
}

TEST(Subsample, GridLinesCoverAnySize) {
    EXPECT_EQ(gridLines(10, 4), (std::vector<int>{0, 4, 8, 9}));
    EXPECT_EQ(gridLines(9, 4), (std::vector<int>{0, 4, 8}));
    EXPECT_EQ(gridLines(5, 100), (std::vector<int>{0, 4}));
    EXPECT_EQ(gridLines(1, 8), (std::vector<int>{0}));
}

TEST(Subsample, InterpolateBlockIsBilinear) {
    ImageRGB img(5, 4, glm::vec3(-1.0f));
    img.at(0, 0) = glm::vec3(0.0f);
    img.at(4, 0) = glm::vec3(4.0f);
    img.at(0, 3) = glm::vec3(6.0f);
    img.at(4, 3) = glm::vec3(10.0f);  // f = x + 2y
    interpolateBlock(img, {0, 0, 4, 3});
    for (int y = 1; y < 3; ++y)
        for (int x = 1; x < 4; ++x) EXPECT_NEAR(img.at(x, y).x, static_cast<float>(x + 2 * y), 1e-5f);
    EXPECT_EQ(img.at(2, 0), glm::vec3(-1.0f));  // borders are left to the line interpolation
}

glm::vec3 ramp(float fx, float fy) { return {0.25f + 0.5f * fx, 3.0f - 0.125f * fy, fx + fy}; }
glm::vec3 rampAtCentre(int x, int y) { return ramp(static_cast<float>(x) + 0.5f, static_cast<float>(y) + 0.5f); }

TEST(Subsample, HugeThresholdTracesOnlyTheGridAndIsExactOnARamp) {
    const int w = 37, h = 21;  // not divisible by s
    const ImageGrey map(w, h, 1.0f);
    for (int s : {1, 4, 8, 16, 64}) {
        const SyntheticSource src(w, h, ramp, true);
        StrategySettings st = strategy("aamap-subsample", 1, &map);
        st.params.set("spacing", s);
        st.params.set("threshold", std::numeric_limits<double>::infinity());
        st.params.set("gradient_tolerance", kGradientToleranceOff);  // the map alone, as a config says it
        const StrategyImages out = runStrategy(st, src);
        const std::vector<int> xs = gridLines(w, s), ys = gridLines(h, s);
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x) {
                const bool grid = std::count(xs.begin(), xs.end(), x) && std::count(ys.begin(), ys.end(), y);
                EXPECT_EQ(out.traced.at(x, y), grid ? 1 : 0) << x << "," << y << " s=" << s;
                EXPECT_EQ(src.calls(x, y), grid ? 1u : 0u);
                EXPECT_EQ(out.primaryRays.at(x, y), grid ? 1 : 0);
                const glm::vec3 d = out.image.at(x, y) - rampAtCentre(x, y);
                EXPECT_LT(std::abs(d.x) + std::abs(d.y) + std::abs(d.z), 1e-4f) << x << "," << y << " s=" << s;
            }
    }
}

TEST(Subsample, RefinesOnlyWhereTheMapIsNonZeroWithoutCracks) {
    const int w = 40, h = 33;
    ImageGrey map(w, h, 0.0f);
    map.at(13, 21) = 0.3f;
    const SyntheticSource src(w, h, ramp, true);
    StrategySettings st = strategy("aamap-subsample", 3, &map);
    st.params.set("spacing", 8);
    st.params.set("gradient_tolerance", std::numeric_limits<double>::infinity());  // the map alone
    const StrategyImages out = runStrategy(st, src);
    EXPECT_EQ(out.traced.at(13, 21), 1);
    EXPECT_EQ(out.primaryRays.at(13, 21), 4);  // k = 1 + round(0.3 * 2) = 2
    std::uint64_t traced = 0;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            traced += out.traced.at(x, y);
            // Only the blocks around (13, 21) are refined.
            if (x > 24 || y < 8) {
                EXPECT_EQ(out.traced.at(x, y), (x % 8 == 0 || x == w - 1) && (y % 8 == 0 || y == h - 1));
            }
            // Linear everywhere: T-junctions between refined and coarse blocks leave no cracks.
            const glm::vec3 d = out.image.at(x, y) - rampAtCentre(x, y);
            EXPECT_LT(std::abs(d.x) + std::abs(d.y) + std::abs(d.z), 1e-4f) << x << "," << y;
        }
    EXPECT_LT(traced, static_cast<std::uint64_t>(w * h) / 4);
    EXPECT_EQ(src.totalCalls(), testing::sumOf(out.primaryRays));
}

TEST(Subsample, AllOnesIsUniformBitForBit) {
    const int w = 19, h = 11, n = 3;
    const ImageGrey ones(w, h, 1.0f);
    const SyntheticSource a(w, h, ramp), b(w, h, ramp);
    StrategySettings st = strategy("aamap-subsample", n, &ones);
    st.params.set("spacing", 5);
    const StrategyImages sub = runStrategy(st, a, 3);
    const StrategyImages uni = runStrategy(strategy("uniform", n), b, 1);
    EXPECT_TRUE(sub.image == uni.image);
    EXPECT_TRUE(sub.primaryRays == uni.primaryRays);
    EXPECT_TRUE(sub.traced == uni.traced);
}

TEST(Subsample, ExtremesGiveFiniteImagesAndHonestCounts) {
    struct Case {
        int w, h, n, s;
        double t;
        float mapValue;
    };
    const double inf = std::numeric_limits<double>::infinity();
    const Case cases[] = {{1, 1, 2, 8, 0, 1.0f},  {3, 7, 2, 8, 0, 0.5f},  {3, 7, 2, 2, inf, 1.0f},
                          {10, 6, 1, 64, 0, 1.0f}, {17, 9, 32, 4, 0, 0.0f}, {17, 9, 32, 64, 0.5, 1.0f},
                          {9, 9, 4, 1, 0, 1.0f},  {8, 8, 3, 8, 1e30, 0.7f}};
    for (const Case& c : cases) {
        ImageGrey map(c.w, c.h, c.mapValue);
        if (c.mapValue > 0.0f) map.at(0, 0) = 0.0f;  // exact zeros next to non-zero values
        const SyntheticSource src(c.w, c.h, ramp);
        StrategySettings st = strategy("aamap-subsample", c.n, &map);
        st.params.set("spacing", c.s);
        st.params.set("threshold", c.t);
        st.params.set("mapping", std::string(toString(c.n == 32 ? StrataMapping::LinearRays : StrataMapping::Paper)));
        const StrategyImages out = runStrategy(st, src);
        for (const glm::vec3& v : out.image.pixels()) EXPECT_TRUE(std::isfinite(v.x + v.y + v.z));
        EXPECT_EQ(src.totalCalls(), testing::sumOf(out.primaryRays)) << c.w << "x" << c.h;
        for (int y = 0; y < c.h; ++y)
            for (int x = 0; x < c.w; ++x) {
                EXPECT_EQ(out.traced.at(x, y) != 0, out.primaryRays.at(x, y) > 0);
                EXPECT_EQ(src.calls(x, y), out.primaryRays.at(x, y));
            }
        EXPECT_EQ(out.traced.at(0, 0), 1);
        EXPECT_EQ(out.traced.at(c.w - 1, c.h - 1), 1);
    }
}

TEST(Subsample, RejectsBadSettings) {
    const ImageGrey map(8, 8, 0.0f);
    StrategySettings st = strategy("aamap-subsample", 2, &map);
    st.params.set("spacing", 0);
    EXPECT_THROW(makeStrategy(st, 8, 8), std::invalid_argument);
    st.params.set("spacing", 65);
    EXPECT_THROW(makeStrategy(st, 8, 8), std::invalid_argument);
    st.params.set("spacing", 8);
    st.params.set("threshold", -1.0);
    EXPECT_THROW(makeStrategy(st, 8, 8), std::invalid_argument);
    st.params.set("threshold", 0.0);
    st.aamap = nullptr;
    EXPECT_THROW(makeStrategy(st, 8, 8), std::invalid_argument);
    st.aamap = &map;
    const BlockSums other(ImageGrey(9, 8, 0.0f));
    st.blockSums = &other;  // tables of another size
    EXPECT_THROW(makeStrategy(st, 8, 8), std::invalid_argument);
}

TEST(Subsample, GivenBlockSumsDecideTheSplitsAndAreNamed) {
    // The map asks to refine everything, the given tables (as the GPU pass hands them over) say
    // all blocks are empty: the tables decide, so only the grid is traced.
    const int w = 17, h = 9;
    const ImageGrey ones(w, h, 1.0f);
    const ImageGrey zeros(w, h, 0.0f);
    const BlockSums given(zeros);
    StrategySettings st = strategy("aamap-subsample", 2, &ones);
    st.params.set("spacing", 8);
    st.params.set("gradient_tolerance", std::numeric_limits<double>::infinity());  // the map alone
    const SyntheticSource a(w, h, [](float fx, float) { return glm::vec3(fx); }, true);
    const StrategyImages cpu = runStrategy(st, a);
    st.blockSums = &given;
    const SyntheticSource b(w, h, [](float fx, float) { return glm::vec3(fx); }, true);
    const StrategyImages gpu = runStrategy(st, b);
    const SubsamplePlan grid = planSubsampling(given, 8, 0.0);
    EXPECT_TRUE(gpu.traced == grid.traced);
    EXPECT_EQ(testing::sumOf(cpu.primaryRays), static_cast<std::uint64_t>(w * h * 4));  // all refined
    EXPECT_NE(makeStrategy(st, w, h)->describe().find("block-sums=given"), std::string::npos);
    st.blockSums = nullptr;
    EXPECT_NE(makeStrategy(st, w, h)->describe().find("block-sums=cpu"), std::string::npos);
}

// Gradient rounds. A point lamp at height d over a plane: irradiance ~ d / (r^2 + d^2)^(3/2), a
// steep smooth hot spot that no aamap flags. Peak 0.8, so nothing clips at exposure 1.
constexpr float kLampX = 27.3f, kLampY = 30.6f, kLampHeight = 9.0f;
glm::vec3 hotSpot(float fx, float fy) {
    const float r2 = (fx - kLampX) * (fx - kLampX) + (fy - kLampY) * (fy - kLampY);
    const float falloff = std::pow(1.0f + r2 / (kLampHeight * kLampHeight), -1.5f);
    return glm::vec3(0.8f, 0.7f, 0.6f) * falloff + glm::vec3(0.02f);
}

// The largest display error of `test` against the exact pixel-centre values, in 8-bit code
// values (RMS over R, G, B), as predictedInterpolationError() measures it.
float maxDisplayError(const ImageRGB& test, const SyntheticSource::Radiance& f, float exposure = 1.0f) {
    float worst = 0.0f;
    for (int y = 0; y < test.height(); ++y)
        for (int x = 0; x < test.width(); ++x) {
            const glm::vec3 exact = f(static_cast<float>(x) + 0.5f, static_cast<float>(y) + 0.5f);
            float squared = 0.0f;
            for (int c = 0; c < 3; ++c) {
                const float d = displayEncode(test.at(x, y)[c], exposure) - displayEncode(exact[c], exposure);
                squared += d * d;
            }
            worst = std::max(worst, 255.0f * std::sqrt(squared / 3.0f));
        }
    return worst;
}

std::uint64_t tracedCount(const StrategyImages& out) {
    std::uint64_t n = 0;
    for (std::uint8_t t : out.traced.pixels()) n += t;
    return n;
}

TEST(SubsampleGradients, PredictedErrorIsZeroOnBilinearAndSeesACentredBump) {
    ImageRGB img(9, 9, glm::vec3(0.0f));
    for (int y = 0; y < 9; ++y)
        for (int x = 0; x < 9; ++x) img.at(x, y) = glm::vec3(0.01f * static_cast<float>(x * y) + 0.1f);  // bilinear
    const Block b{0, 0, 8, 8};
    EXPECT_LT(predictedInterpolationError(img, b, 1.0f), 1e-4f);
    img.at(4, 4) += glm::vec3(0.2f);  // the centre, between four corners of which none sees it
    const float expected = displayEncode(img.at(4, 4).x, 1.0f) - displayEncode(img.at(4, 4).x - 0.2f, 1.0f);
    EXPECT_NEAR(predictedInterpolationError(img, b, 1.0f), 255.0f * expected, 1e-4f);  // code values
    // Halves: a block one pixel wide probes only the midpoints of its long sides.
    EXPECT_EQ(splitBlock({3, 0, 4, 8}).size(), 2u);
    EXPECT_LT(predictedInterpolationError(img, {0, 0, 1, 8}, 1.0f), 1e-4f);
    // Saturated in display space: any radiance above white is white, so no error.
    EXPECT_EQ(predictedInterpolationError(img, b, 1000.0f), 0.0f);
}

TEST(SubsampleGradients, SteepFalloffStaysWithinTheToleranceOnlyWithGradientRounds) {
    const int w = 64, h = 56;
    const ImageGrey zeros(w, h, 0.0f);  // the map sees nothing
    const double tolerance = kDefaultGradientTolerance;
    for (int spacing : {8, 16}) {
        SCOPED_TRACE(spacing);
        StrategySettings st = strategy("aamap-subsample", 1, &zeros);
        st.params.set("spacing", spacing);
        const SyntheticSource refined(w, h, hotSpot, true);
        const StrategyImages with = runStrategy(st, refined);
        st.params.set("gradient_tolerance", std::numeric_limits<double>::infinity());
        const SyntheticSource mapOnly(w, h, hotSpot, true);
        const StrategyImages without = runStrategy(st, mapOnly);
        const float errorWith = maxDisplayError(with.image, hotSpot);
        const float errorWithout = maxDisplayError(without.image, hotSpot);
        // The probes bound the error where they are, and between them a smooth falloff errs less
        // (here at most 1.06 code values, against 36 and 66 without the rounds).
        EXPECT_LT(errorWith, tolerance);
        EXPECT_GT(errorWithout, 10.0 * tolerance);
        // Rays only near the spot: far fewer than every pixel.
        EXPECT_LT(tracedCount(with), static_cast<std::uint64_t>(w * h) / 2);
        EXPECT_GT(tracedCount(with), tracedCount(without));
        EXPECT_EQ(refined.totalCalls(), testing::sumOf(with.primaryRays));
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x) EXPECT_EQ(refined.calls(x, y), with.primaryRays.at(x, y));
    }
}

// A block the plan would interpolate traces the corners its split adds, once; in a flat (or
// linear) image they match the prediction, so no block is split further.
Image<std::uint8_t> gridAndOneSplit(int w, int h, int spacing) {
    const SubsamplePlan plan = planSubsampling(BlockSums(ImageGrey(w, h, 0.0f)), spacing, 0.0);
    Image<std::uint8_t> expected = plan.traced;
    for (const Block& b : plan.interpolated)
        for (const Block& part : splitBlock(b))
            for (const auto& [x, y] : {std::pair{part.x0, part.y0}, std::pair{part.x1, part.y0},
                                       std::pair{part.x0, part.y1}, std::pair{part.x1, part.y1}})
                expected.at(x, y) = 1;
    return expected;
}

TEST(SubsampleGradients, FlatAndLinearImagesAreNeverSplitBeyondTheProbes) {
    const int w = 37, h = 21;
    const ImageGrey zeros(w, h, 0.0f);
    const SyntheticSource::Radiance flat = [](float, float) { return glm::vec3(0.3f, 0.5f, 0.1f); };
    for (int spacing : {4, 8, 16}) {
        SCOPED_TRACE(spacing);
        const Image<std::uint8_t> expected = gridAndOneSplit(w, h, spacing);
        for (double tolerance : {0.0, kDefaultGradientTolerance}) {
            StrategySettings st = strategy("aamap-subsample", 2, &zeros);
            st.params.set("spacing", spacing);
            st.params.set("gradient_tolerance", tolerance);
            const SyntheticSource constant(w, h, flat);  // jittered: a constant is exact anyway
            const StrategyImages out = runStrategy(st, constant);
            EXPECT_TRUE(out.traced == expected);
            EXPECT_EQ(constant.totalCalls(), tracedCount(out));  // k = 1 where the map is 0
            for (const glm::vec3& v : out.image.pixels()) EXPECT_EQ(v, flat(0.0f, 0.0f));
        }
        StrategySettings st = strategy("aamap-subsample", 2, &zeros);
        st.params.set("spacing", spacing);
        const SyntheticSource linear(w, h, ramp, true);
        const StrategyImages out = runStrategy(st, linear);
        EXPECT_TRUE(out.traced == expected);
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x) {
                const glm::vec3 d = out.image.at(x, y) - rampAtCentre(x, y);
                EXPECT_LT(std::abs(d.x) + std::abs(d.y) + std::abs(d.z), 1e-4f) << x << "," << y;
            }
    }
}

TEST(SubsampleGradients, DecidedInDisplaySpace) {
    const int w = 64, h = 56;
    const ImageGrey zeros(w, h, 0.0f);
    StrategySettings st = strategy("aamap-subsample", 1, &zeros);
    st.params.set("spacing", 16);
    const SyntheticSource normal(w, h, hotSpot, true);
    const std::uint64_t atOne = tracedCount(runStrategy(st, normal));
    // Every value far above white: the display is flat, so only the probes are traced.
    st.exposure = 1000.0f;
    const SyntheticSource bright(w, h, hotSpot, true);
    const StrategyImages white = runStrategy(st, bright);
    EXPECT_TRUE(white.traced == gridAndOneSplit(w, h, 16));
    // Dim: the same radiance differences are smaller on the display, fewer splits.
    st.exposure = 0.05f;
    const SyntheticSource dim(w, h, hotSpot, true);
    const StrategyImages dark = runStrategy(st, dim);
    EXPECT_LT(tracedCount(dark), atOne);
    EXPECT_LT(maxDisplayError(dark.image, hotSpot, 0.05f), 2.0 * kDefaultGradientTolerance);
    for (float bad : {0.0f, -1.0f, std::numeric_limits<float>::quiet_NaN(), std::numeric_limits<float>::infinity()}) {
        st.exposure = bad;
        EXPECT_THROW(makeStrategy(st, w, h), std::invalid_argument);
    }
}

TEST(SubsampleGradients, BitIdenticalForAnyThreadCount) {
    const int w = 61, h = 47;
    ImageGrey map(w, h, 0.0f);
    for (int y = 30; y < 36; ++y) map.at(50, y) = 0.6f;  // map-driven splits beside gradient ones
    for (int spacing : {8, 16}) {
        StrategySettings st = strategy("aamap-subsample", 3, &map);
        st.params.set("spacing", spacing);
        const SyntheticSource a(w, h, hotSpot), b(w, h, hotSpot), c(w, h, hotSpot);  // jittered
        const StrategyImages one = runStrategy(st, a, 1), two = runStrategy(st, b, 2), five = runStrategy(st, c, 5);
        EXPECT_TRUE(one.image == two.image && one.image == five.image);
        EXPECT_TRUE(one.primaryRays == two.primaryRays && one.primaryRays == five.primaryRays);
        EXPECT_TRUE(one.traced == two.traced && one.traced == five.traced);
        EXPECT_EQ(a.totalCalls(), testing::sumOf(one.primaryRays));
        EXPECT_EQ(c.totalCalls(), a.totalCalls());
        const Image<std::uint8_t> firstProbes = gridAndOneSplit(w, h, spacing);
        std::uint64_t probesOnly = 0;  // the rounds went deeper than the first probes
        for (std::uint8_t t : firstProbes.pixels()) probesOnly += t;
        EXPECT_GT(tracedCount(one), probesOnly);
    }
}

}  // namespace
}  // namespace aamap
