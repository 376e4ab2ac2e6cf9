// The CPU filters' output-image variants (laplacianMagnitudeInto, boxBlurInto) and the Laplacian's
// accuracy: same results as the returning calls, the kept image reused, and |L| within the proven
// bound of the shader's difference sum (integer path), correctly rounded on the fixed-point grid
// and outside the fixed-point range (double path).
#include <algorithm>
#include <cmath>
#include <random>
#include <stdexcept>
#include <utility>

#include <gtest/gtest.h>

#include "passes/cpu_aamap.h"
#include "tests/filters/filter_images.h"

namespace aamap::cpu {
namespace {

using test_images::bitIdentical;
using test_images::randomGrey;

// |sum over the 24 off-centre taps of (g(p+o) - g(p))|, clamped to the edge, in long double: exact
// while the window's values span at most 64 bits of significance, as for every image below.
long double exactDifferenceSum(const ImageGrey& g, int x, int y) {
    const auto at = [&](int xx, int yy) {
        return static_cast<long double>(
            g.at(std::clamp(xx, 0, g.width() - 1), std::clamp(yy, 0, g.height() - 1)));
    };
    long double sum = 0.0L;
    for (int dy = -2; dy <= 2; ++dy)
        for (int dx = -2; dx <= 2; ++dx) sum += at(x + dx, y + dy) - at(x, y);
    return std::fabs(sum);
}
float exactLaplacian(const ImageGrey& g, int x, int y) { return static_cast<float>(exactDifferenceSum(g, x, y)); }

// The fixed-point unit of the integer path (passes/cpu_aamap.cpp): grey in [0, 4] becomes
// trunc(g * 2^24).
constexpr double kFixedUnit = 1.0 / 16777216.0;

ImageGrey onFixedGrid(ImageGrey g) {
    for (float& v : g.pixels()) v = static_cast<float>(std::floor(v / kFixedUnit) * kFixedUnit);
    return g;
}

// Any grey in [0, 4]: each of the 24 differences is off by less than one unit before the final
// rounding to float, so |L| is within 24 units plus half an ulp of the result.
TEST(FilterOutputs, LaplacianIsWithinTwentyFourFixedUnitsOfTheExactSum) {
    const ImageGrey g = randomGrey(41, 23, 5);
    for (Mode mode : {Mode::Scalar, Mode::Parallel}) {
        const ImageGrey lap = laplacianMagnitude(g, mode);
        for (int y = 0; y < g.height(); ++y)
            for (int x = 0; x < g.width(); ++x) {
                const float got = lap.at(x, y);
                const double halfUlp = 0.5 * (std::nextafter(got, 1e9f) - got);
                ASSERT_LE(std::fabs(got - exactDifferenceSum(g, x, y)), 24 * kFixedUnit + halfUlp) << x << "," << y;
            }
    }
}

// Grey values on the 2^-24 grid (every float in [0.5, 4], 16-bit and 8-bit sources) are converted
// exactly, so integer sums give the correctly rounded difference sum.
TEST(FilterOutputs, LaplacianIsCorrectlyRoundedOnTheFixedGrid) {
    const ImageGrey g = onFixedGrid(randomGrey(41, 23, 7));
    for (Mode mode : {Mode::Scalar, Mode::Parallel}) {
        const ImageGrey lap = laplacianMagnitude(g, mode);
        for (int y = 0; y < g.height(); ++y)
            for (int x = 0; x < g.width(); ++x) ASSERT_EQ(lap.at(x, y), exactLaplacian(g, x, y)) << x << "," << y;
    }
}

// One value outside [0, 4] sends the whole image through the double path, whose sums are exact
// here (values in [1e-3, 8]: under 53 bits of span), so every pixel is correctly rounded.
TEST(FilterOutputs, LaplacianOutsideTheFixedRangeIsCorrectlyRounded) {
    ImageGrey g = randomGrey(41, 23, 9);
    for (float& v : g.pixels()) v = 1e-3f + 7.999f * v;
    g.at(40, 22) = 8.0f;  // at least one value above 4, far from most pixels' windows
    for (Mode mode : {Mode::Scalar, Mode::Parallel}) {
        const ImageGrey lap = laplacianMagnitude(g, mode);
        for (int y = 0; y < g.height(); ++y)
            for (int x = 0; x < g.width(); ++x) ASSERT_EQ(lap.at(x, y), exactLaplacian(g, x, y)) << x << "," << y;
    }
}

TEST(FilterOutputs, IntoVariantsMatchAndReuseTheImage) {
    // 4100 wide: two column tiles of the row-sliding Laplacian, the second clamped at the right.
    for (auto [w, h] : {std::pair{4100, 37}, std::pair{7, 3}, std::pair{1, 1}, std::pair{64, 300}}) {
        SCOPED_TRACE(testing::Message() << w << "x" << h);
        const ImageGrey g = randomGrey(w, h, static_cast<std::uint32_t>(w * 31 + h));
        const ImageGrey scalar = laplacianMagnitude(g, Mode::Scalar);
        for (Mode mode : {Mode::Scalar, Mode::Parallel}) {
            ImageGrey out(3, 2, 7.0f);  // wrong size: reallocated
            laplacianMagnitudeInto(g, out, mode);
            ASSERT_TRUE(bitIdentical(out, scalar));
            const float* kept = out.data();
            out.pixels().assign(out.size(), -1.0f);  // stale contents must be overwritten
            laplacianMagnitudeInto(g, out, mode);
            EXPECT_EQ(out.data(), kept);  // right size: reused, no allocation
            ASSERT_TRUE(bitIdentical(out, scalar));

            ImageGrey blurred(w, h, -1.0f);
            boxBlurInto(scalar, 1, blurred, mode);
            ASSERT_TRUE(bitIdentical(blurred, boxBlur(scalar, 1, Mode::Scalar)));
        }
    }
}

TEST(FilterOutputs, OutputMustNotBeTheInput) {
    ImageGrey g = randomGrey(8, 8, 1);
    EXPECT_THROW(laplacianMagnitudeInto(g, g), std::invalid_argument);
    EXPECT_THROW(boxBlurInto(g, 1, g), std::invalid_argument);
}

}  // namespace
}  // namespace aamap::cpu
