// MSE / RMSE / PSNR / % of pixels in error, in the Display and Linear spaces.
#include <cmath>
#include <limits>
#include <stdexcept>

#include <gtest/gtest.h>
#include <tbb/task_arena.h>

#include "eval/metrics/pixel_error.h"
#include "patterns.h"

namespace aamap::metrics {
namespace {

TEST(PixelError, IdenticalImagesHaveZeroMseAndInfinitePsnr) {
    const ImageRGB img = test::randomImage(17, 9, 1);
    for (const PixelError& e : {pixelErrorDisplay(img, img), pixelErrorLinear(img, img)}) {
        EXPECT_EQ(e.mse, 0.0);
        EXPECT_EQ(e.rmse, 0.0);
        EXPECT_EQ(e.psnr, std::numeric_limits<double>::infinity());
        EXPECT_EQ(e.pixelsInError, 0u);
        EXPECT_EQ(e.fractionInError, 0.0);
    }
}

TEST(PixelError, KnownOffsetInLinearSpace) {
    const ImageRGB ref(8, 4, glm::vec3(0.2f));
    const ImageRGB test(8, 4, glm::vec3(0.3f));
    const PixelError e = pixelErrorLinear(ref, test);
    EXPECT_NEAR(e.mse, 0.01, 1e-8);
    EXPECT_NEAR(e.rmse, 0.1, 1e-7);
    EXPECT_NEAR(e.psnr, 20.0, 1e-5);
    EXPECT_EQ(e.fractionInError, 1.0);

    PixelErrorOptions o;
    o.space = ErrorSpace::Linear;
    o.peak = 10.0;  // another peak shifts PSNR by 20 log10(10) dB
    EXPECT_NEAR(pixelError(ref, test, o).psnr, 40.0, 1e-5);
}

TEST(PixelError, DisplaySpaceAppliesExposureClampAndSrgb) {
    const ImageRGB black(4, 4, glm::vec3(0.0f));
    const ImageRGB quarter(4, 4, glm::vec3(0.25f));
    const ImageRGB bright(4, 4, glm::vec3(7.0f));
    EXPECT_NEAR(pixelErrorDisplay(black, quarter, 4.0f).mse, 1.0, 1e-6);  // exposure 4: white
    EXPECT_NEAR(pixelErrorDisplay(black, bright).mse, 1.0, 1e-6);  // clamped to 1 (float OETF: 1 - 6e-8)
    EXPECT_NEAR(pixelErrorDisplay(black, bright).psnr, 0.0, 1e-5);
    EXPECT_NEAR(pixelErrorLinear(black, bright).mse, 49.0, 1e-9);         // linear: not clamped
    // 0.25 linear is sRGB ~0.5371 on the display.
    const double enc = 1.055 * std::pow(0.25, 1.0 / 2.4) - 0.055;
    EXPECT_NEAR(pixelErrorDisplay(black, quarter).mse, enc * enc, 1e-6);
}

TEST(PixelError, NonFiniteValuesReadAsBlack) {
    const ImageRGB black(3, 3, glm::vec3(0.0f));
    ImageRGB bad = black;
    bad.at(1, 1) = {std::numeric_limits<float>::quiet_NaN(), std::numeric_limits<float>::infinity(), 0.0f};
    EXPECT_EQ(pixelErrorDisplay(black, bad).mse, 0.0);
    EXPECT_EQ(pixelErrorLinear(black, bad).mse, 0.0);
}

TEST(PixelError, FractionInErrorUsesThePerPixelChannelMean) {
    // Linear space so the squared errors are exact: 0.01^2 = 1e-4 > (2/255)^2, 0.005^2 < it.
    const ImageRGB ref(4, 2, glm::vec3(0.0f));
    ImageRGB test(4, 2, glm::vec3(0.005f));
    for (int x = 0; x < 4; ++x) test.at(x, 0) = glm::vec3(0.01f);
    PixelErrorOptions o;
    o.space = ErrorSpace::Linear;
    PixelError e = pixelError(ref, test, o);
    EXPECT_EQ(e.pixelsInError, 4u);
    EXPECT_DOUBLE_EQ(e.fractionInError, 0.5);
    // A difference in one channel only counts a third.
    ImageRGB oneChannel = ref;
    oneChannel.at(0, 0) = {0.01f, 0.0f, 0.0f};
    EXPECT_EQ(pixelError(ref, oneChannel, o).pixelsInError, 0u);
    // The threshold is a parameter.
    o.errorThreshold = 1e-6;
    EXPECT_EQ(pixelError(ref, test, o).pixelsInError, 8u);
    EXPECT_NEAR(kDefaultErrorThreshold, 6.151e-5, 1e-8);
}

TEST(PixelError, SquaredErrorMapAveragesToMse) {
    const ImageRGB a = test::randomImage(13, 7, 2);
    const ImageRGB b = test::randomImage(13, 7, 3);
    const ImageGrey map = squaredErrorMap(a, b);
    double sum = 0.0;
    for (float v : map.pixels()) sum += v;
    EXPECT_NEAR(sum / double(map.size()), pixelErrorDisplay(a, b).mse, 1e-6);
}

TEST(PixelError, RejectsMismatchedOrEmptyImages) {
    EXPECT_THROW(pixelErrorLinear(ImageRGB(4, 4), ImageRGB(4, 5)), std::invalid_argument);
    EXPECT_THROW(pixelErrorLinear(ImageRGB(), ImageRGB()), std::invalid_argument);
}

TEST(PixelError, DeterministicAcrossThreadCounts) {
    const ImageRGB a = test::randomImage(101, 67, 4);
    const ImageRGB b = test::randomImage(101, 67, 5);
    PixelError one, many;
    tbb::task_arena(1).execute([&] { one = pixelErrorDisplay(a, b); });
    tbb::task_arena(4).execute([&] { many = pixelErrorDisplay(a, b); });
    EXPECT_EQ(one.mse, many.mse);
    EXPECT_EQ(one.pixelsInError, many.pixelsInError);
}

}  // namespace
}  // namespace aamap::metrics
