// Pixel filters on their own (tracer/pixel_filter.h): each filter's cumulative distribution against
// the numerical integral of the filter, its inverse against the CDF, the range and monotonicity of
// the offsets, and the default box as the identity. What a render does with them:
// tests/tracer/test_film_sampling.cpp.
#include <cmath>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "tracer/pixel_filter.h"

namespace aamap {
namespace {

std::vector<PixelFilterSettings> filters() {
    return {{PixelFilterType::Box, 0.0f, 0.5f},      {PixelFilterType::Box, 1.25f, 0.5f},
            {PixelFilterType::Tent, 0.0f, 0.5f},     {PixelFilterType::Tent, 1.5f, 0.5f},
            {PixelFilterType::Gaussian, 0.0f, 0.5f}, {PixelFilterType::Gaussian, 1.5f, 0.5f},
            {PixelFilterType::Gaussian, 1.0f, 0.3f}, {PixelFilterType::Gaussian, 0.0f, 0.1f}};
}

std::string name(const PixelFilter& f) { return fmt::format("{} r={}", toString(f.type()), f.radius()); }

// Composite Simpson's rule of the filter from -r to x, over its total.
double integratedCdf(const PixelFilter& f, double x) {
    const double r = f.radius();
    auto integral = [&](double to) {
        const int n = 20000;  // even
        const double h = (to + r) / n;
        double sum = f.evaluate1D(-r) + f.evaluate1D(to);
        for (int i = 1; i < n; ++i) sum += (i % 2 == 1 ? 4.0 : 2.0) * f.evaluate1D(-r + i * h);
        return sum * h / 3.0;
    };
    return integral(x) / integral(r);
}

TEST(PixelFilter, DefaultRadiiAreTheFiltersOwn) {
    EXPECT_EQ(PixelFilter({PixelFilterType::Box, 0.0f, 0.5f}).radius(), 0.5f);
    EXPECT_EQ(PixelFilter({PixelFilterType::Tent, 0.0f, 0.5f}).radius(), 1.0f);
    EXPECT_EQ(PixelFilter({PixelFilterType::Gaussian, 0.0f, 0.5f}).radius(), 2.0f);  // 4 sigma, as Mitsuba
    EXPECT_EQ(PixelFilter({PixelFilterType::Gaussian, 0.0f, 0.25f}).radius(), 1.0f);
    EXPECT_THROW(PixelFilter({PixelFilterType::Gaussian, 1.0f, 0.0f}), std::invalid_argument);
    EXPECT_THROW(PixelFilter({PixelFilterType::Tent, -1.0f, 0.5f}), std::invalid_argument);
}

TEST(PixelFilter, CdfIsTheFiltersNormalisedIntegral) {
    for (const PixelFilterSettings& s : filters()) {
        const PixelFilter f(s);
        const double r = f.radius();
        EXPECT_DOUBLE_EQ(f.cdf1D(-r), 0.0) << name(f);
        EXPECT_NEAR(f.cdf1D(r), 1.0, 1e-12) << name(f);
        EXPECT_NEAR(f.cdf1D(0.0), 0.5, 1e-12) << name(f) << ": symmetric";
        EXPECT_EQ(f.evaluate1D(1.0001 * r), 0.0) << name(f);
        for (int i = 1; i < 40; ++i) {
            const double x = r * (2.0 * i / 40 - 1.0) * 0.999;
            EXPECT_NEAR(f.cdf1D(x), integratedCdf(f, x), 1e-8) << name(f) << " at " << x;
        }
    }
}

TEST(PixelFilter, OffsetInvertsTheCdfAndIsMonotoneWithinTheRadius) {
    for (const PixelFilterSettings& s : filters()) {
        const PixelFilter f(s);
        const float r = f.radius();
        float previous = -r;
        for (int i = 0; i <= 4096; ++i) {
            const float u = std::min(static_cast<float>(i) / 4096.0f, 0x1.fffffep-1f);
            const float x = f.offset(u);
            ASSERT_GE(x, -r) << name(f) << " u " << u;
            ASSERT_LE(x, r) << name(f) << " u " << u;
            ASSERT_GE(x, previous) << name(f) << ": not monotone at u " << u;
            previous = x;
            // The CDF of the offset is u again, to float precision of the offset (times the
            // density, at most 1/r-ish per unit of offset).
            EXPECT_NEAR(f.cdf1D(x), u, 4e-7 / r + 1e-7) << name(f) << " u " << u;
        }
        EXPECT_NEAR(f.offset(0.5f), 0.0f, 1e-6f) << name(f);
    }
}

TEST(PixelFilter, DefaultBoxIsTheIdentityBitForBit) {
    const PixelFilter box;
    EXPECT_TRUE(box.isPixelBox());
    for (float u : {0.0f, 0.1f, 0.5f, 0.7312f, 0x1.fffffep-1f}) {
        const glm::vec2 p = box.positionInPixel({u, 1.0f - u});
        EXPECT_EQ(p.x, u);
        EXPECT_EQ(p.y, 1.0f - u);
    }
    EXPECT_FALSE(PixelFilter({PixelFilterType::Box, 1.0f, 0.5f}).isPixelBox());
    EXPECT_FALSE(PixelFilter({PixelFilterType::Tent, 0.5f, 0.5f}).isPixelBox());
}

TEST(PixelFilter, NamesRoundTrip) {
    for (PixelFilterType t : {PixelFilterType::Box, PixelFilterType::Tent, PixelFilterType::Gaussian}) {
        PixelFilterType back = PixelFilterType::Box;
        EXPECT_TRUE(parse(toString(t), back));
        EXPECT_EQ(back, t);
    }
    PixelFilterType t = PixelFilterType::Tent;
    EXPECT_FALSE(parse("lanczos", t));
    EXPECT_EQ(t, PixelFilterType::Tent);
}

}  // namespace
}  // namespace aamap
