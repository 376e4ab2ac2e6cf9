// Every strategy through Tracer::render: flat colour equals uniform, thread-count independence,
// ray accounting against the integrator's own counters, and the aamap extremes.
#include <cmath>
#include <limits>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include "core/image_io.h"
#include "tests/tracer/scene_builder.h"
#include "tests/tracer/synthetic_source.h"
#include "tracer/strategies/subsample.h"
#include "tracer/tracer.h"

namespace aamap {
namespace {

using testing::strategy;
using testing::sumOf;

TraceSettings settingsFor(int w, int h, int threads) {
    TraceSettings s;
    s.width = w;
    s.height = h;
    s.threads = threads;
    s.seed = 5;
    s.shading.areaLightSamples = 4;
    return s;
}

const std::vector<std::string> kAll = strategyNames();

StrategySettings configured(const std::string& kind, int n, const ImageGrey* map) {
    StrategySettings s = strategy(kind, n, map);
    testing::setIfDeclared(s, "spacing", 4);
    testing::setIfDeclared(s, "threshold", kind == "rpict" ? 0.05 : 0.0);
    testing::setIfDeclared(s, "filter", "gaussian");
    testing::setIfDeclared(s, "min_samples", 4);
    testing::setIfDeclared(s, "sample_step", 2);
    return s;
}

// A map with zeros, ones and values between, NaN included.
ImageGrey mixedMap(int w, int h) {
    ImageGrey map(w, h, 0.0f);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            if ((x / 5 + y / 3) % 3 == 0) map.at(x, y) = static_cast<float>((x * 3 + y) % 7) / 6.0f;
    map.at(w - 1, 0) = std::numeric_limits<float>::quiet_NaN();
    return map;
}

TEST(StrategyRender, FlatColourGivesUniformsImageForEveryStrategy) {
    testing::SceneBuilder b;
    const glm::vec3 ke(0.7f, 1.3f, 2.1f);
    b.areaLightQuad({-50, -50, -1}, {100, 0, 0}, {0, 100, 0}, ke);  // faces +z, fills the view
    const Tracer tracer(b.scene());
    View v;
    v.position = {0, 0, 2};
    v.direction = {0, 0, -1};
    v.horizontalFovDeg = v.verticalFovDeg = 50;
    const int w = 21, h = 13, n = 3;
    const ImageGrey map = mixedMap(w, h);
    const TraceResult uni = tracer.render(v, settingsFor(w, h, 2), strategy("uniform", n));
    for (const std::string& kind : kAll) {
        const TraceResult r = tracer.render(v, settingsFor(w, h, 2), configured(kind, n, &map));
        SCOPED_TRACE(r.strategy);
        for (std::size_t i = 0; i < r.image.size(); ++i) {
            const glm::vec3 d = r.image.pixels()[i] - uni.image.pixels()[i];
            EXPECT_LT(std::abs(d.x) + std::abs(d.y) + std::abs(d.z), 1e-5f);
        }
        EXPECT_EQ(r.rays.primary, sumOf(r.primaryRays));
    }
}

// A point lamp just above a diffuse floor: a steep smooth hot spot, and an aamap of zeros (no
// edge anywhere). Traced pixels of aamap-subsample equal uniform n = 1's bit for bit, so the
// difference to uniform is the interpolation error alone.
// SampleSource::pixelHalves on a radiance that is 1 on the strata of even x + y and 0 on the
// others: the mean is pixel()'s, the difference exactly 1.
TEST(StrategyRender, PixelHalvesSplitTheStrataByParity) {
    const int k = 4;
    const testing::SyntheticSource source(3, 2, [&](float fx, float fy) {
        const int sx = static_cast<int>((fx - std::floor(fx)) * k), sy = static_cast<int>((fy - std::floor(fy)) * k);
        return glm::vec3((sx + sy) % 2 == 0 ? 1.0f : 0.0f);
    });
    for (int y = 0; y < 2; ++y)
        for (int x = 0; x < 3; ++x) {
            const SampleSource::Halves h = source.pixelHalves(x, y, k);
            EXPECT_EQ(h.mean, source.pixel(x, y, k));
            EXPECT_FLOAT_EQ(h.mean.x, 0.5f);
            EXPECT_FLOAT_EQ(h.difference.x, 1.0f);
        }
}

TEST(StrategyRender, SubsampleGradientRoundsFollowAHotSpotTheMapDoesNotSee) {
    testing::SceneBuilder b;
    const auto floor = b.material("floor", glm::vec3(0.5f));
    b.quad({-50, 0, -50}, {0, 0, 100}, {100, 0, 0}, floor);
    b.pointLight({0.1f, 0.3f, -0.05f}, glm::vec3(0.45f, 0.4f, 0.35f));  // peak radiance ~0.8
    const Tracer tracer(b.scene());
    View v;
    v.position = {0, 2, 2};
    v.direction = glm::normalize(glm::vec3(0, -2, -2));
    v.horizontalFovDeg = v.verticalFovDeg = 60;
    const int w = 64, h = 64;
    const ImageGrey zeros(w, h, 0.0f);
    const TraceResult uniform = tracer.render(v, settingsFor(w, h, 2), strategy("uniform", 1));
    auto maxCodeValueError = [&](const ImageRGB& image) {
        float worst = 0.0f;
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x) {
                float squared = 0.0f;
                for (int c = 0; c < 3; ++c) {
                    const float d = displayEncode(image.at(x, y)[c], 1.0f) - displayEncode(uniform.image.at(x, y)[c], 1.0f);
                    squared += d * d;
                }
                worst = std::max(worst, 255.0f * std::sqrt(squared / 3.0f));
            }
        return worst;
    };
    for (int spacing : {8, 16}) {
        SCOPED_TRACE(spacing);
        StrategySettings s = strategy("aamap-subsample", 4, &zeros);
        s.params.set("spacing", spacing);
        const TraceResult refined = tracer.render(v, settingsFor(w, h, 2), s);
        s.params.set("gradient_tolerance", kGradientToleranceOff);
        const TraceResult mapOnly = tracer.render(v, settingsFor(w, h, 2), s);
        std::uint64_t traced = 0;
        for (std::uint8_t t : refined.traced.pixels()) traced += t;
        // The probes hold the error to the tolerance where they are; between them, and where a
        // pixel's jittered sample differs from its neighbours', it may exceed it a little (here
        // 2.6 code values, against 53 and 77 for the map alone).
        EXPECT_LT(maxCodeValueError(refined.image), 2.0f * static_cast<float>(kDefaultGradientTolerance));
        EXPECT_GT(maxCodeValueError(mapOnly.image), 10.0f * static_cast<float>(kDefaultGradientTolerance));
        EXPECT_LT(traced, static_cast<std::uint64_t>(w * h) * 3 / 4);  // the far floor stays interpolated
        EXPECT_EQ(refined.rays.primary, sumOf(refined.primaryRays));
    }
}

class StrategyCornell : public testing::CornellTracerTest {};

// The variance strategy takes its samples in batches (SampleSource::samples, which the tracer
// traces as packets and, in path mode, as paths in lockstep) in its own stratum order; with a
// threshold of 0 it takes every stratum, so each pixel is uniform's mean over the same samples
// summed in another order, with the same rays.
TEST_F(StrategyCornell, VarianceBatchesGiveUniformsSamples) {
    const int w = 20, h = 14, n = 5;
    for (ShadingMode mode : {ShadingMode::Direct, ShadingMode::Path}) {
        SCOPED_TRACE(toString(mode));
        TraceSettings settings = settingsFor(w, h, 2);
        settings.shading.mode = mode;
        StrategySettings all = strategy("variance", n);
        all.params.set("noise_threshold", 0.0);
        all.params.set("min_samples", 8);  // batches of 8, 4, 4, 4, 4 and 1: full and part packets, one ray
        all.params.set("sample_step", 4);
        const TraceResult v = tracer_->render(view(), settings, all);
        const TraceResult u = tracer_->render(view(), settings, strategy("uniform", n));
        EXPECT_EQ(v.rays.total(), u.rays.total());
        EXPECT_TRUE(v.primaryRays == u.primaryRays);
        for (std::size_t i = 0; i < u.image.size(); ++i) {
            const glm::vec3 a = v.image.pixels()[i], b = u.image.pixels()[i];
            for (int c = 0; c < 3; ++c) EXPECT_NEAR(a[c], b[c], 1e-6f * std::max(1.0f, b[c])) << "pixel " << i;
        }
    }
}

TEST_F(StrategyCornell, EveryStrategyIsThreadCountIndependentAndCountsHonestly) {
    const int w = 26, h = 18, n = 3;  // n > 2: shape-id probes its 2 x 2 first samples
    const ImageGrey map = mixedMap(w, h);
    for (const std::string& kind : kAll) {
        const StrategySettings s = configured(kind, n, &map);
        const TraceResult one = tracer_->render(view(), settingsFor(w, h, 1), s);
        const TraceResult three = tracer_->render(view(), settingsFor(w, h, 3), s);
        SCOPED_TRACE(one.strategy);
        EXPECT_FALSE(one.strategy.empty());
        EXPECT_TRUE(one.image == three.image);
        EXPECT_TRUE(one.primaryRays == three.primaryRays);
        EXPECT_TRUE(one.traced == three.traced);
        EXPECT_EQ(one.rays.total(), three.rays.total());
        // The integrator counts primary rays itself; the strategy records them per pixel.
        EXPECT_EQ(one.rays.primary, sumOf(one.primaryRays));
        std::uint64_t traced = 0;
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x) {
                EXPECT_EQ(one.traced.at(x, y) != 0, one.primaryRays.at(x, y) > 0);
                traced += one.traced.at(x, y);
                const glm::vec3 c = one.image.at(x, y);
                EXPECT_TRUE(std::isfinite(c.x + c.y + c.z));
            }
        // Probe rays (depth, shape id) are the only "other" rays of direct shading.
        if (kind == "rpict") {
            EXPECT_EQ(one.rays.other, traced);
        }
        if (kind == "shape-id") {
            EXPECT_EQ(one.rays.other, static_cast<std::uint64_t>(w * h * 4));
        }
        if (kind == "uniform") {
            EXPECT_EQ(one.rays.other, 0u);
        }
        if (kind == "rpict") {
            EXPECT_LT(traced, static_cast<std::uint64_t>(w * h));
        } else if (kind == "aamap-subsample") {
            // At 26 x 18 every 4 x 4 block of the box holds an edge or a falloff steeper than the
            // gradient tolerance, so its rounds may trace every pixel; the synthetic tests
            // (test_subsample.cpp, SubsampleGradients) cover thread counts with pixels left to
            // interpolate.
            EXPECT_LE(traced, static_cast<std::uint64_t>(w * h));
        } else {
            EXPECT_EQ(traced, static_cast<std::uint64_t>(w * h));
        }
    }
}

TEST_F(StrategyCornell, AllOnesSubsamplingReproducesUniformBitForBit) {
    const int w = 23, h = 17, n = 3;
    const ImageGrey ones(w, h, 1.0f);
    StrategySettings s = strategy("aamap-subsample", n, &ones);
    s.params.set("spacing", 16);
    const TraceResult a = tracer_->render(view(), settingsFor(w, h, 2), s);
    const TraceResult u = tracer_->render(view(), settingsFor(w, h, 2), strategy("uniform", n));
    EXPECT_TRUE(a.image == u.image);
    EXPECT_TRUE(a.primaryRays == u.primaryRays);
    EXPECT_EQ(a.rays.total(), u.rays.total());
    s.params.set("mapping", std::string(toString(StrataMapping::LinearRays)));  // a = 1 gives n under either mapping
    EXPECT_TRUE(tracer_->render(view(), settingsFor(w, h, 2), s).image == u.image);
}

TEST_F(StrategyCornell, ExtremeSizesAndParametersStayFinite) {
    struct Case {
        int w, h, n, s;
        double t;
        float a;
    };
    const Case cases[] = {{1, 1, 2, 8, 0.0, 1.0f}, {3, 7, 2, 64, 0.0, 0.0f}, {3, 7, 1, 2, 1e30, 1.0f},
                          {5, 4, 32, 8, 0.0, 1.0f}};
    for (const Case& c : cases) {
        const ImageGrey map(c.w, c.h, c.a);
        for (const std::string& kind : kAll) {
            StrategySettings s = configured(kind, c.n, &map);
            testing::setIfDeclared(s, "spacing", c.s);
            testing::setIfDeclared(s, "threshold", c.t);
            if (kind == "supersample" && c.n == 32) s.params.set("supersample", 1);  // 16-bit ray map
            const TraceResult r = tracer_->render(view(), settingsFor(c.w, c.h, 2), s);
            SCOPED_TRACE(r.strategy + " " + std::to_string(c.w) + "x" + std::to_string(c.h));
            for (const glm::vec3& v : r.image.pixels()) EXPECT_TRUE(std::isfinite(v.x + v.y + v.z));
            EXPECT_EQ(r.rays.primary, sumOf(r.primaryRays));
            EXPECT_GE(r.rays.primary, 1u);
        }
    }
}

}  // namespace
}  // namespace aamap
