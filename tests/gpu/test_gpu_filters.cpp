// The GPU filter passes against the CPU reference (passes/cpu_aamap.h) on random images, which
// go up as imported graph resources.
#include <cmath>
#include <random>

#include "gpu_fixture.h"
#include "passes/cpu_aamap.h"
#include "passes/gpu_aamap.h"
#include "tests/common/image_compare.h"

namespace aamap::test {
namespace {

constexpr float kTolerance = 1e-5f;

ImageGrey randomGrey(int w, int h, std::uint32_t seed, float lo = 0.0f, float hi = 1.0f) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> u(lo, hi);
    ImageGrey image(w, h);
    for (float& v : image.pixels()) v = u(rng);
    return image;
}

// Random colours with flat patches and hard edges, so the dead zone passes some texels and
// clamps others, plus values beyond the [0,1] clamp of the display encoding.
ImageRGB randomColour(int w, int h, std::uint32_t seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> u(0.0f, 1.3f);
    ImageRGB image(w, h);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const bool flat = ((x / 7) + (y / 5)) % 3 == 0;
            image.at(x, y) = flat ? glm::vec3(0.25f, 0.5f, 0.125f) : glm::vec3(u(rng), u(rng), u(rng));
        }
    return image;
}

class FilterTest : public GpuTest {};

TEST_F(FilterTest, LaplacianMatchesCpu) {
    passes::GpuAamap gpu(context());
    for (auto [w, h] : {std::pair{67, 45}, std::pair{128, 128}, std::pair{3, 2}, std::pair{1, 1}}) {
        const ImageGrey grey = randomGrey(w, h, 1u + static_cast<std::uint32_t>(w));
        const ImageGrey expected = cpu::laplacianMagnitude(grey, cpu::Mode::Scalar);
        EXPECT_LE(maxAbsDiff(gpu.laplacianMagnitude(grey), expected), kTolerance) << w << "x" << h;
    }
}

TEST_F(FilterTest, FlatGateMatchesCpu) {
    // Flat patches and random texels, so some windows span less than the range and some more.
    passes::GpuAamap gpu(context());
    const ImageGrey grey = cpu::greyscale(randomColour(67, 45, 5u), 1.0f, cpu::Mode::Scalar);
    for (float range : {1.0f / 255.0f, 0.25f, 2.0f}) {
        ImageGrey expected = cpu::laplacianMagnitude(grey, cpu::Mode::Scalar);
        cpu::flatGate(grey, expected, range, cpu::Mode::Scalar);
        const ImageGrey got = gpu.laplacianMagnitude(grey, range);
        EXPECT_LE(maxAbsDiff(got, expected), kTolerance) << range;
        // The same texels are gated: the decision is exact on both sides.
        for (std::size_t i = 0; i < got.size(); ++i)
            ASSERT_EQ(got.pixels()[i] == 0.0f, expected.pixels()[i] == 0.0f) << range << " texel " << i;
    }
}

TEST_F(FilterTest, BlurMatchesCpu) {
    passes::GpuAamap gpu(context());
    const ImageGrey edges = randomGrey(61, 50, 7u);
    for (int radius : {0, 1, 2, 4}) {
        // noiseFloor 0 and gain 1 leave the blur of values in [0,1] untouched.
        const ImageGrey expected = cpu::boxBlur(edges, radius, cpu::Mode::Scalar);
        EXPECT_LE(maxAbsDiff(gpu.blurDeadZone(edges, radius, 0.0f, 1.0f), expected), kTolerance) << "r=" << radius;
    }
}

TEST_F(FilterTest, BlurAndDeadZoneMatchCpu) {
    passes::GpuAamap gpu(context());
    const ImageGrey edges = randomGrey(40, 33, 11u, 0.0f, 0.2f);
    const ImageGrey expected =
        cpu::deadZone(cpu::boxBlur(edges, 1, cpu::Mode::Scalar), 0.05f, 4.0f, cpu::Mode::Scalar);
    EXPECT_LE(maxAbsDiff(gpu.blurDeadZone(edges, 1, 0.05f, 4.0f), expected), kTolerance);
}

TEST_F(FilterTest, ReduceMatchesCpu) {
    passes::GpuAamap gpu(context());
    const ImageGrey map = randomGrey(77, 50, 5u);
    for (auto [w, h] : {std::pair{51, 33}, std::pair{77, 50}, std::pair{20, 49}, std::pair{100, 60}, std::pair{1, 1}}) {
        const ImageGrey expected = cpu::reduceMax(map, w, h, cpu::Mode::Scalar);
        EXPECT_EQ(maxAbsDiff(gpu.reduceMax(map, w, h), expected), 0.0f) << w << "x" << h;  // max is exact
    }
}

TEST_F(FilterTest, GreyscaleMatchesCpu) {
    passes::GpuAamap gpu(context());
    const ImageRGB colour = randomColour(45, 31, 3u);
    for (float exposure : {1.0f, 0.5f, 2.0f}) {
        const ImageGrey expected = cpu::greyscale(colour, exposure, cpu::Mode::Scalar);
        EXPECT_LE(maxAbsDiff(gpu.greyscale(colour, exposure), expected), kTolerance) << "exposure " << exposure;
    }
}

TEST_F(FilterTest, WholeChainMatchesCpu) {
    passes::GpuAamap gpu(context());
    const ImageRGB colour = randomColour(96, 72, 9u);
    FilterParams params;
    const cpu::AamapImages expected = cpu::buildAamap(colour, 64, 48, params, cpu::Mode::Scalar);
    const cpu::AamapImages got = gpu.build(colour, 64, 48, params);
    EXPECT_LE(maxAbsDiff(got.grey, expected.grey), kTolerance);
    EXPECT_LE(maxAbsDiff(got.laplacian, expected.laplacian), kTolerance);
    EXPECT_LE(maxAbsDiff(got.aamap, expected.aamap), kTolerance);
    ASSERT_EQ(gpu.passTimes().size(), 4u);
    // The random patches must exercise both sides of the dead zone.
    int zeros = 0, ones = 0;
    for (float v : got.aamap.pixels()) {
        zeros += v == 0.0f;
        ones += v == 1.0f;
    }
    EXPECT_GT(zeros, 0);
    EXPECT_GT(ones, 0);
}

TEST_F(FilterTest, ConstantImageGivesExactlyZero) {
    passes::GpuAamap gpu(context());
    const ImageRGB colour(90, 70, glm::vec3(0.3f, 0.7f, 0.2f));
    FilterParams params;
    params.noiseFloor = 0.0f;  // no dead zone to hide rounding: zero must come from the Laplacian
    const cpu::AamapImages got = gpu.build(colour, 60, 47, params);
    for (float v : got.laplacian.pixels()) ASSERT_EQ(v, 0.0f);
    for (float v : got.aamap.pixels()) ASSERT_EQ(v, 0.0f);
}

}  // namespace
}  // namespace aamap::test
