// Pixel filters on their own (tracer/pixel_filter.h): each filter's cumulative distribution against
// the numerical integral of the filter, its inverse against the CDF, the range and monotonicity of
// the offsets, and the default box as the identity. What a render does with them:
// tests/tracer/test_film_sampling.cpp.
#include <algorithm>
#include <cmath>
#include <random>
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

// Pixel d's weight is the filter's mass over [d - 1/2, d + 1/2]: symmetric, summing to 1, and
// the same as the numerical integral of the filter over the cell.
TEST(PixelFilter, PixelKernelIsTheFiltersMassPerPixelCell) {
    for (const PixelFilterSettings& s : filters()) {
        const PixelFilter f(s);
        const std::vector<double>& k = f.pixelKernel();
        const int R = f.reach();
        ASSERT_EQ(k.size(), static_cast<std::size_t>(2 * R + 1)) << name(f);
        EXPECT_GE(R + 0.5, f.radius()) << name(f) << ": the kernel reaches every cell the filter meets";
        double sum = 0.0;
        for (int d = -R; d <= R; ++d) {
            const double w = k[static_cast<std::size_t>(d + R)];
            sum += w;
            EXPECT_NEAR(w, k[static_cast<std::size_t>(R - d)], 1e-12) << name(f) << " d = " << d;
            const double r = f.radius();  // the integral stops at the filter's edge
            const double mass = integratedCdf(f, std::min(d + 0.5, r)) - integratedCdf(f, std::max(d - 0.5, -r));
            EXPECT_NEAR(w, mass, 1e-8) << name(f) << " d = " << d;
        }
        EXPECT_NEAR(sum, 1.0, 1e-12) << name(f);
    }
    EXPECT_EQ(PixelFilter().pixelKernel(), std::vector<double>{1.0});
}

// Independent noise, uniform in [0, 1) (variance 1/12), the same in every channel.
ImageRGB uniformNoise(int width, int height, unsigned seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    ImageRGB noise(width, height);
    for (glm::vec3& p : noise.pixels()) p = glm::vec3(u(rng));
    return noise;
}

// A constant image stays constant everywhere, the border included (renormalised weights); the
// pixel box leaves every image as it is.
TEST(PixelFilter, ConvolutionKeepsConstantsAndTheBoxIsTheIdentity) {
    const ImageRGB noise = uniformNoise(9, 7, 12345u);
    EXPECT_EQ(PixelFilter().convolve(noise), noise);
    for (const PixelFilterSettings& s : filters()) {
        const PixelFilter f(s);
        const ImageRGB flat = f.convolve(ImageRGB(9, 7, glm::vec3(0.25f, 1.0f, 3.0f)));
        for (int y = 0; y < 7; ++y)
            for (int x = 0; x < 9; ++x) {
                EXPECT_NEAR(flat.at(x, y).x, 0.25f, 1e-6f) << name(f) << " at " << x << "," << y;
                EXPECT_NEAR(flat.at(x, y).z, 3.0f, 1e-6f) << name(f) << " at " << x << "," << y;
            }
    }
}

// Away from the border, independent pixel noise of variance v comes out with variance
// v (sum of K^2)^2 (the 2D kernel's squared weights, per axis): the noise reduction that sharing
// samples with neighbours buys. Measured on 256^2 pixels of uniform noise (v = 1/12).
TEST(PixelFilter, ConvolutionScalesIndependentNoiseBySumOfSquaredWeights) {
    const int n = 256;
    const ImageRGB noise = uniformNoise(n, n, 7u);
    for (const PixelFilterSettings& s : filters()) {
        const PixelFilter f(s);
        double k2 = 0.0;
        for (double w : f.pixelKernel()) k2 += w * w;
        const ImageRGB out = f.convolve(noise);
        const int R = f.reach();
        double sum = 0.0, sum2 = 0.0;
        int count = 0;
        for (int y = R; y < n - R; ++y)
            for (int x = R; x < n - R; ++x) {
                sum += out.at(x, y).x;
                sum2 += static_cast<double>(out.at(x, y).x) * out.at(x, y).x;
                ++count;
            }
        const double mean = sum / count, variance = sum2 / count - mean * mean;
        // Sampling error of a variance estimate from ~65k pixels, correlated over the kernel's
        // width: a few percent.
        EXPECT_NEAR(variance / (k2 * k2 / 12.0), 1.0, 0.06) << name(f);
    }
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
