// The baselines' defining rules, on synthetic radiance functions: rpict's midpoint criterion,
// supersample-and-filter, the Cycles-style variance stop rule and pbrt-v2's shape-id trigger.
#include <cmath>
#include <limits>

#include <gtest/gtest.h>

#include "tests/tracer/synthetic_source.h"
#include "tracer/strategies/hybrid.h"
#include "tracer/strategies/rpict.h"
#include "tracer/strategies/shape_id.h"
#include "tracer/strategies/variance.h"

namespace aamap {
namespace {

using testing::runStrategy;
using testing::strategy;
using testing::sumOf;
using testing::SyntheticSource;

const float kInf = std::numeric_limits<float>::infinity();

TEST(Rpict, DiffersIsRadiancesRelativeBigdiffOnColourAndDepth) {
    const glm::vec3 one(1.0f);
    EXPECT_FALSE(rpictDiffers(one, 2.0f, glm::vec3(1.04f, 1.0f, 0.97f), 2.0f, 0.05));
    EXPECT_TRUE(rpictDiffers(one, 2.0f, glm::vec3(1.0f, 1.06f, 1.0f), 2.0f, 0.05));
    EXPECT_TRUE(rpictDiffers(glm::vec3(0.0f), 2.0f, glm::vec3(0.0f, 0.0f, 1e-6f), 2.0f, 0.5));  // relative to 0
    EXPECT_FALSE(rpictDiffers(one, 2.0f, one, 2.09f, 0.05));
    EXPECT_TRUE(rpictDiffers(one, 2.0f, one, 2.11f, 0.05));  // depth alone
    EXPECT_TRUE(rpictDiffers(one, 2.0f, one, kInf, 0.05));   // a miss next to a hit
    EXPECT_FALSE(rpictDiffers(one, kInf, one, kInf, 0.0));   // two misses agree
    EXPECT_TRUE(rpictDiffers(glm::vec3(std::nanf("")), 1.0f, one, 1.0f, 1e9));
    EXPECT_FALSE(rpictDiffers(glm::vec3(0.0f), 1.0f, one * 5.0f, 1.0f, std::numeric_limits<double>::infinity()));
}

TEST(Rpict, TracesTheMidpointOnlyWhereTheEndsDiffer) {
    // One row, -ps 8: a step at x = 5 is found by bisection 0-8 -> 4 -> 6 -> 5.
    const SyntheticSource src(9, 1, [](float fx, float) { return glm::vec3(fx >= 5.0f ? 2.0f : 1.0f); }, true);
    StrategySettings st = strategy("rpict", 1);
    st.params.set("spacing", 8);
    st.params.set("threshold", 0.05);
    const StrategyImages out = runStrategy(st, src);
    const int expected[9] = {1, 0, 0, 0, 1, 1, 1, 0, 1};
    for (int x = 0; x < 9; ++x) {
        EXPECT_EQ(out.traced.at(x, 0), expected[x]) << x;
        EXPECT_EQ(src.calls(x, 0), static_cast<std::uint64_t>(expected[x]));
        EXPECT_EQ(out.image.at(x, 0).x, x >= 5 ? 2.0f : 1.0f) << x;  // interpolated between equal ends
    }
    EXPECT_EQ(src.probes(), 5u);  // every traced pixel asks for its depth
}

TEST(Rpict, AtMostOneRayPerPixelAndLinearBetweenSimilarEnds) {
    const int w = 29, h = 19;
    auto f = [](float fx, float fy) { return glm::vec3(1.0f + 0.01f * fx, 2.0f + 0.02f * fy, 3.0f); };
    for (double t : {0.0, 0.05, 1e9}) {
        const SyntheticSource src(w, h, f, true);
        StrategySettings st = strategy("rpict", 4);  // n is ignored: one ray
        st.params.set("spacing", 4);
        st.params.set("threshold", t);
        const StrategyImages out = runStrategy(st, src);
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x) {
                EXPECT_LE(src.calls(x, y), 1u);
                EXPECT_EQ(src.calls(x, y), out.primaryRays.at(x, y));
                EXPECT_EQ(out.traced.at(x, y), out.primaryRays.at(x, y));
                const glm::vec3 d = out.image.at(x, y) - f(x + 0.5f, y + 0.5f);
                EXPECT_LT(std::abs(d.x) + std::abs(d.y), 1e-5f);
            }
        if (t == 0.0) {
            EXPECT_EQ(src.totalCalls(), static_cast<std::uint64_t>(w * h));  // all differ
        }
        if (t == 1e9) {
            EXPECT_EQ(src.totalCalls(), 8u * 6u);                           // only the grid
        }
    }
}

TEST(Supersample, FactorOneBoxIsUniformAndFiltersAreNormalised) {
    const int w = 11, h = 7, n = 2;
    auto f = [](float fx, float fy) { return glm::vec3(std::sin(fx) + 2.0f, fy, 1.0f); };
    const SyntheticSource a(w, h, f), b(w, h, f);
    StrategySettings st = strategy("supersample", n);
    st.params.set("supersample", 1);
    const StrategyImages one = runStrategy(st, a);
    const StrategyImages uni = runStrategy(strategy("uniform", n), b);
    EXPECT_TRUE(one.image == uni.image);
    EXPECT_TRUE(one.primaryRays == uni.primaryRays);

    // A constant stays constant under both filters, at f^2 n^2 rays per pixel.
    for (const std::string filter : {"box", "gaussian"})
        for (int factor : {2, 3}) {
            const SyntheticSource c(w, h, [](float, float) { return glm::vec3(0.3f, 0.6f, 0.9f); });
            st.params.set("supersample", factor);
            st.params.set("filter", filter);
            st.params.set("filter_radius", filter == "gaussian" ? 0.6 : 1.0);
            const StrategyImages out = runStrategy(st, c);
            for (const glm::vec3& v : out.image.pixels()) EXPECT_NEAR(v.y, 0.6f, 1e-6f);
            for (auto r : out.primaryRays.pixels()) EXPECT_EQ(r, factor * factor * n * n);
            EXPECT_EQ(c.totalCalls(), sumOf(out.primaryRays));
        }
}

TEST(Supersample, GaussianBlursAStepAndBoxDoesNot) {
    const int w = 8, h = 2;
    auto step = [](float fx, float) { return glm::vec3(fx >= 4.0f ? 1.0f : 0.0f); };
    StrategySettings st = strategy("supersample", 1);
    st.params.set("supersample", 2);
    const SyntheticSource a(w, h, step);
    const StrategyImages box = runStrategy(st, a);
    EXPECT_EQ(box.image.at(3, 0).x, 0.0f);
    EXPECT_EQ(box.image.at(4, 0).x, 1.0f);
    st.params.set("filter", "gaussian");
    const SyntheticSource b(w, h, step);
    const StrategyImages gauss = runStrategy(st, b);
    EXPECT_GT(gauss.image.at(3, 0).x, 0.01f);
    EXPECT_LT(gauss.image.at(4, 0).x, 0.99f);
    EXPECT_EQ(gauss.image.at(0, 0).x, 0.0f);
}

TEST(Variance, ErrorStrataAndDilation) {
    EXPECT_EQ(varianceError(glm::dvec3(0.0), glm::dvec3(0.0)), 0.0);
    EXPECT_EQ(varianceError(glm::dvec3(0.5), glm::dvec3(0.5)), 0.0);
    EXPECT_NEAR(varianceError(glm::dvec3(1.0, 1.0, 2.0), glm::dvec3(1.1, 0.9, 2.0)), 0.2 / (1e-4 + 2.0), 1e-12);
    for (int n : {1, 2, 3, 4, 6, 16}) {
        std::vector<int> seen(static_cast<std::size_t>(n * n), 0);
        for (int q : varianceOrder(n)) ++seen[static_cast<std::size_t>(q)];
        for (int s : seen) EXPECT_EQ(s, 1);  // a permutation
        EXPECT_EQ(varianceOrder(n), varianceOrder(n));
    }
    Image<std::uint8_t> a(5, 4, 0);
    a.at(0, 0) = 1;
    const auto d = dilate3x3(a);
    EXPECT_EQ(d.at(1, 1), 1);
    EXPECT_EQ(d.at(2, 0), 0);
    EXPECT_EQ(d.at(0, 2), 0);
}

TEST(Variance, StopsWhereConvergedAndDilatesTheRest) {
    const int w = 9, h = 7, n = 6;
    // Constant except one pixel of loud noise in [0, 100): only it (and its 3 x 3 neighbourhood,
    // by dilation) gets more than the minimum.
    auto f = [](float fx, float fy) {
        if (static_cast<int>(fx) != 4 || static_cast<int>(fy) != 3) return glm::vec3(0.5f);
        const float h = std::sin(fx * 12.9898f + fy * 78.233f) * 43758.5453f;
        return glm::vec3(100.0f * (h - std::floor(h)));
    };
    const SyntheticSource src(w, h, f);
    StrategySettings st = strategy("variance", n);
    st.params.set("min_samples", 4);
    st.params.set("sample_step", 4);
    st.params.set("noise_threshold", 0.01);
    const StrategyImages out = runStrategy(st, src);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const bool near = std::abs(x - 4) <= 1 && std::abs(y - 3) <= 1;
            EXPECT_EQ(out.primaryRays.at(x, y), near ? n * n : 4) << x << "," << y;
            EXPECT_EQ(src.calls(x, y), out.primaryRays.at(x, y));
            if (!near) {
                EXPECT_EQ(out.image.at(x, y), glm::vec3(0.5f));
            }
        }
    // Threshold 0: nothing converges, every pixel takes n^2 and matches uniform.
    const SyntheticSource a(w, h, f), b(w, h, f);
    st.params.set("noise_threshold", 0.0);
    const StrategyImages all = runStrategy(st, a);
    const StrategyImages uni = runStrategy(strategy("uniform", n), b);
    EXPECT_TRUE(all.primaryRays == uni.primaryRays);
    for (std::size_t i = 0; i < all.image.size(); ++i)
        EXPECT_NEAR(all.image.pixels()[i].x, uni.image.pixels()[i].x, 1e-6f);
}

TEST(ShapeId, SupersamplesExactlyWhereShapesDiffer) {
    EXPECT_FALSE(shapesDiffer({3, 3, 3, 3}));
    EXPECT_TRUE(shapesDiffer({3, 3, kNoShape, 3}));
    EXPECT_EQ(shapeIdMinStrata(4, 6), 2);
    EXPECT_EQ(shapeIdMinStrata(8, 6), 2);
    EXPECT_EQ(shapeIdMinStrata(9, 2), 2);
    EXPECT_EQ(shapeIdMinStrata(1, 6), 1);

    const int w = 10, h = 3, n = 4;
    auto shape = [](float fx, float) { return fx < 5.5f ? 1u : 2u; };  // an edge inside pixel 5
    auto f = [](float fx, float) { return glm::vec3(fx < 5.5f ? 0.2f : 0.8f); };
    const SyntheticSource src(w, h, f, false, shape), uniSrc(w, h, f);
    StrategySettings st = strategy("shape-id", n);
    st.params.set("min_samples", 4);
    const StrategyImages out = runStrategy(st, src);
    const StrategyImages uni = runStrategy(strategy("uniform", n), uniSrc);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            EXPECT_EQ(out.primaryRays.at(x, y), x == 5 ? 4 + n * n : 4) << x;
            EXPECT_EQ(src.calls(x, y), out.primaryRays.at(x, y));
            if (x == 5) {
                EXPECT_EQ(out.image.at(x, y), uni.image.at(x, y));  // the first 4 are discarded
            }
            else EXPECT_EQ(out.image.at(x, y), f(static_cast<float>(x), 0.0f));
        }
    EXPECT_EQ(src.probes(), static_cast<std::uint64_t>(w * h * 4));
}

TEST(Hybrid, StartsAtTheMapsStrataAndStopsAtConvergence) {
    EXPECT_EQ(hybridStartSamples(0.0f, 4, 1), 1);  // unflagged: one ray
    EXPECT_EQ(hybridStartSamples(0.01f, 4, 1), 2);  // flagged: at least a half buffer
    EXPECT_EQ(hybridStartSamples(0.5f, 4, 3), 9);
    EXPECT_EQ(hybridStartSamples(std::nanf(""), 4, 4), 16);  // unsure: look
    EXPECT_EQ(hybridStartSamples(1.0f, 1, 1), 1);
    const glm::dvec3 a(1.0), b(1.5);
    EXPECT_TRUE(hybridConverged(a, b, 16, 4, 0.0));   // n^2 reached
    EXPECT_FALSE(hybridConverged(a, a, 1, 4, 1.0));   // no half buffer yet
    EXPECT_TRUE(hybridConverged(a, a, 4, 4, 0.01));   // no contrast
    EXPECT_FALSE(hybridConverged(a, b, 4, 4, 0.01));  // contrast
    EXPECT_FALSE(hybridConverged(a, a, 4, 4, 0.0));   // threshold 0 never converges early
}

TEST(Hybrid, TheMapSaysWhereToLookContrastWhereToStop) {
    // Columns 0-5 unflagged, 6-11 flagged with a = 1/3 (k = 2 of n = 4). A step runs through
    // pixels 3 (unflagged: one ray regardless) and 10 (flagged: refined to n^2); the rest is flat.
    const int w = 12, h = 3, n = 4;
    auto f = [](float fx, float) {
        if (fx >= 3.0f && fx < 4.0f) return glm::vec3(fx < 3.5f ? 1.0f : 3.0f);
        return glm::vec3(fx < 10.5f ? 1.0f : 3.0f);
    };
    ImageGrey map(w, h, 0.0f);
    for (int y = 0; y < h; ++y)
        for (int x = 6; x < w; ++x) map.at(x, y) = 1.0f / 3.0f;
    const SyntheticSource src(w, h, f);
    StrategySettings st = strategy("hybrid", n, &map);
    st.params.set("noise_threshold", 0.01);
    st.params.set("sample_step", 3);
    const StrategyImages out = runStrategy(st, src);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const std::uint64_t expected = x < 6 ? 1 : x == 10 ? 16 : 4;
            EXPECT_EQ(out.primaryRays.at(x, y), expected) << x << "," << y;
            EXPECT_EQ(src.calls(x, y), expected) << x << "," << y;  // counted by the source itself
            EXPECT_EQ(out.traced.at(x, y), 1);
        }
    EXPECT_GT(out.image.at(10, 0).x, 1.5f);  // the step's mean, from all 16 strata
    EXPECT_LT(out.image.at(10, 0).x, 2.5f);
}

TEST(Hybrid, AllOnesWithThresholdZeroIsUniform) {
    const int w = 7, h = 5, n = 3;
    auto f = [](float fx, float fy) { return glm::vec3(std::sin(fx * 1.3f) + 2.0f, fy, 1.0f); };
    const ImageGrey ones(w, h, 1.0f);
    const SyntheticSource a(w, h, f), b(w, h, f);
    StrategySettings st = strategy("hybrid", n, &ones);
    st.params.set("noise_threshold", 0.0);
    const StrategyImages hybrid = runStrategy(st, a);
    const StrategyImages uniform = runStrategy(strategy("uniform", n), b);
    EXPECT_TRUE(hybrid.primaryRays == uniform.primaryRays);
    for (std::size_t i = 0; i < hybrid.image.size(); ++i) {
        const glm::vec3 d = hybrid.image.pixels()[i] - uniform.image.pixels()[i];
        EXPECT_LT(std::abs(d.x) + std::abs(d.y) + std::abs(d.z), 1e-5f);  // same strata, another order
    }
}

TEST(Baselines, RejectBadSettings) {
    StrategySettings st = strategy("supersample", 255);
    EXPECT_THROW(makeStrategy(st, 4, 4), std::invalid_argument);  // 4 * 255^2 rays overflow the map
    st.strata = 2;
    st.params.set("supersample", 0);
    EXPECT_THROW(makeStrategy(st, 4, 4), std::invalid_argument);
    st.params.set("supersample", 2);
    st.params.set("filter_radius", 0.0);
    EXPECT_THROW(makeStrategy(st, 4, 4), std::invalid_argument);
    st = strategy("variance", 2);
    st.params.set("sample_step", 0);
    EXPECT_THROW(makeStrategy(st, 4, 4), std::invalid_argument);
    st = strategy("rpict", 1);
    st.params.set("threshold", -0.1);
    EXPECT_THROW(makeStrategy(st, 4, 4), std::invalid_argument);
    st = strategy("hybrid", 2);
    EXPECT_THROW(makeStrategy(st, 4, 4), std::invalid_argument);  // no map
    const ImageGrey map(4, 4, 0.5f);
    st.aamap = &map;
    st.params.set("sample_step", 0);
    EXPECT_THROW(makeStrategy(st, 4, 4), std::invalid_argument);
    for (const char* name :
         {"uniform", "aamap", "aamap-subsample", "rpict", "supersample", "variance", "shape-id", "hybrid"})
        EXPECT_NE(findStrategy(name), nullptr) << name;
    EXPECT_EQ(findStrategy("adaptive"), nullptr);
    st = strategy("supersample", 2);
    st.params.set("filter", "lanczos");
    EXPECT_THROW(makeStrategy(st, 4, 4), std::invalid_argument);
    st = strategy("uniform", 2);
    st.params.set("spacing", 4);  // another strategy's parameter
    EXPECT_THROW(makeStrategy(st, 4, 4), std::invalid_argument);
}

}  // namespace
}  // namespace aamap
