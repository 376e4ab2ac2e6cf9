// The CPU aamap filter chain: known answers per stage, and Scalar == Parallel bit for bit.
#include <cstring>
#include <limits>
#include <random>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "passes/cpu_aamap.h"
#include "tests/filters/filter_images.h"

namespace aamap::cpu {
namespace {

using test_images::bitIdentical;
using test_images::randomGrey;
using test_images::randomRgb;

constexpr Mode kModes[] = {Mode::Scalar, Mode::Parallel};

const char* name(Mode m) { return m == Mode::Scalar ? "Scalar" : "Parallel"; }

ImageGrey fromRows(const std::vector<std::vector<float>>& rows) {
    ImageGrey img(static_cast<int>(rows[0].size()), static_cast<int>(rows.size()));
    for (int y = 0; y < img.height(); ++y)
        for (int x = 0; x < img.width(); ++x) img.at(x, y) = rows[y][x];
    return img;
}


TEST(Filters, ConstantImageIsExactlyZeroAtEveryStage) {
    const ImageRGB rgb(37, 29, glm::vec3(0.3f, 0.55f, 0.71f));
    for (Mode mode : kModes) {
        SCOPED_TRACE(name(mode));
        const ImageGrey grey = greyscale(rgb, 1.3f, mode);
        for (float v : grey.pixels()) ASSERT_EQ(v, grey.at(0, 0));
        const ImageGrey lap = laplacianMagnitude(grey, mode);
        const ImageGrey blurred = boxBlur(lap, 2, mode);
        const ImageGrey map = deadZone(blurred, 0.0f, 10.0f, mode);  // no floor: any residue would show
        const ImageGrey reduced = reduceMax(map, 24, 19, mode);
        for (const ImageGrey* img : {&lap, &blurred, &map, &reduced})
            for (float v : img->pixels()) ASSERT_EQ(v, 0.0f);
        const AamapImages all = buildAamap(rgb, 20, 20, FilterParams{}, mode);
        for (float v : all.aamap.pixels()) ASSERT_EQ(v, 0.0f);
    }
}

TEST(Filters, GreyscaleIsLumaOfSrgbEncoding) {
    ImageRGB rgb(5, 1);
    rgb.at(0, 0) = {1.0f, 0.0f, 0.0f};
    rgb.at(1, 0) = {0.0f, 0.0f, 0.5f};
    rgb.at(2, 0) = {0.001f, 0.001f, 0.001f};  // 0.002 after exposure: linear segment of the curve
    rgb.at(3, 0) = {5.0f, 5.0f, 5.0f};        // clamped to 1
    rgb.at(4, 0) = {0.25f, 0.25f, 0.25f};     // 0.5 after exposure 2
    for (Mode mode : kModes) {
        const ImageGrey g = greyscale(rgb, 2.0f, mode);
        EXPECT_NEAR(g.at(0, 0), 0.2126f, 1e-6f);
        EXPECT_NEAR(g.at(1, 0), 0.0722f, 1e-6f);
        EXPECT_NEAR(g.at(2, 0), 12.92f * 0.002f, 1e-6f);
        EXPECT_NEAR(g.at(3, 0), 1.0f, 1e-6f);
        EXPECT_NEAR(g.at(4, 0), 0.735357f, 1e-5f);  // sRGB(0.5)
    }
}

TEST(Filters, LaplacianOfLinearRampIsZeroInTheInterior) {
    const int w = 40, h = 33;
    ImageGrey ramp(w, h);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) ramp.at(x, y) = 0.002f * x + 0.005f * y + 0.1f;
    for (Mode mode : kModes) {
        SCOPED_TRACE(name(mode));
        const ImageGrey lap = laplacianMagnitude(ramp, mode);
        for (int y = 2; y < h - 2; ++y)
            for (int x = 2; x < w - 2; ++x) ASSERT_NEAR(lap.at(x, y), 0.0f, 1e-6f) << x << "," << y;
        // Clamp-to-edge breaks the ramp at the border, which is how the edge is noticed at all.
        EXPECT_GT(lap.at(0, h / 2), 1e-3f);
        EXPECT_GT(lap.at(w / 2, h - 1), 1e-3f);
    }
}

// A single 1 in the corner of a 5x5 image. With clamping, tap (dx, dy) of pixel (x, y) lands on
// the corner for count(x) * count(y) taps, count(0..2) = 3, 2, 1: L = that count (the corner
// itself has 16 taps that see 0, so L = -16).
TEST(Filters, HandComputedFiveByFive) {
    ImageGrey img(5, 5, 0.0f);
    img.at(0, 0) = 1.0f;
    const ImageGrey expected = fromRows({{16, 6, 3, 0, 0},  //
                                         {6, 4, 2, 0, 0},
                                         {3, 2, 1, 0, 0},
                                         {0, 0, 0, 0, 0},
                                         {0, 0, 0, 0, 0}});
    for (Mode mode : kModes) {
        SCOPED_TRACE(name(mode));
        const ImageGrey lap = laplacianMagnitude(img, mode);
        EXPECT_TRUE(bitIdentical(lap, expected));
        const ImageGrey blurred = boxBlur(lap, 1, mode);
        EXPECT_EQ(blurred.at(0, 0), 92.0f / 9.0f);  // 4*16 + 2*6 + 2*6 + 4, clamped 3x3 window
        EXPECT_EQ(blurred.at(1, 1), 43.0f / 9.0f);
        EXPECT_EQ(blurred.at(4, 4), 0.0f);
        EXPECT_EQ(blurred.at(3, 3), 1.0f / 9.0f);
    }
}

TEST(Filters, BoxBlurPreservesAConstant) {
    for (Mode mode : kModes)
        for (int r : {0, 1, 2, 3, 12}) {  // 12: window larger than the image
            SCOPED_TRACE(r);
            const int taps = (2 * r + 1) * (2 * r + 1);
            // A dyadic value sums without rounding, so its mean is exact.
            const ImageGrey exact = boxBlur(ImageGrey(23, 17, 0.375f), r, mode);
            for (float v : exact.pixels()) ASSERT_EQ(v, 0.375f);
            // Otherwise each of the taps may round once.
            const float bound = static_cast<float>(taps) * std::numeric_limits<float>::epsilon() * 0.37f;
            const ImageGrey rounded = boxBlur(ImageGrey(23, 17, 0.37f), r, mode);
            for (float v : rounded.pixels()) ASSERT_NEAR(v, 0.37f, bound);
        }
}

TEST(Filters, DeadZoneMapsBelowTheFloorToExactlyZero) {
    const ImageGrey in = fromRows({{0.0f, 0.01f, 0.0199f, 0.02f, 0.3f, 0.5f, 2.0f}});
    for (Mode mode : kModes) {
        const ImageGrey out = deadZone(in, 0.02f, 2.0f, mode);
        for (int x = 0; x <= 3; ++x) EXPECT_EQ(out.at(x, 0), 0.0f) << x;
        EXPECT_NEAR(out.at(4, 0), 2.0f * (0.3f - 0.02f), 1e-6f);
        EXPECT_NEAR(out.at(5, 0), 0.96f, 1e-6f);
        EXPECT_EQ(out.at(6, 0), 1.0f);
    }
}

// Returns the output pixels that are non-zero after reducing a single hot texel.
std::vector<std::pair<int, int>> hotPixels(int ws, int hs, int hx, int hy, int w, int h, Mode mode) {
    ImageGrey map(ws, hs, 0.0f);
    map.at(hx, hy) = 0.75f;
    const ImageGrey out = reduceMax(map, w, h, mode);
    std::vector<std::pair<int, int>> hot;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            if (out.at(x, y) != 0.0f) {
                EXPECT_EQ(out.at(x, y), 0.75f);
                hot.emplace_back(x, y);
            }
    return hot;
}

using Pixels = std::vector<std::pair<int, int>>;

TEST(Filters, ReduceMaxPutsAHotTexelInEveryPixelItOverlaps) {
    for (Mode mode : kModes) {
        SCOPED_TRACE(name(mode));
        // Scale 1.5: output pixel i covers texels [1.5 i, 1.5 i + 1.5).
        EXPECT_EQ(hotPixels(12, 12, 3, 6, 8, 8, mode), (Pixels{{2, 4}}));  // texel 3 lies in [3, 4.5)
        EXPECT_EQ(hotPixels(12, 12, 4, 7, 8, 8, mode), (Pixels{{2, 4}, {3, 4}, {2, 5}, {3, 5}}));  // straddles
        EXPECT_EQ(hotPixels(768, 768, 767, 0, 512, 512, mode), (Pixels{{511, 0}}));
        // Scale 2: exactly one pixel.
        EXPECT_EQ(hotPixels(16, 16, 5, 10, 8, 8, mode), (Pixels{{2, 5}}));
        // Identity.
        EXPECT_EQ(hotPixels(9, 7, 8, 3, 9, 7, mode), (Pixels{{8, 3}}));
        // Upsampling 4 -> 6: texel 1 = [1, 2) overlaps pixels 1 = [2/3, 4/3) and 2 = [4/3, 2);
        // texel 0 = [0, 1) overlaps rows 0 and 1.
        EXPECT_EQ(hotPixels(4, 4, 1, 0, 6, 6, mode), (Pixels{{1, 0}, {2, 0}, {1, 1}, {2, 1}}));
    }
}

TEST(Filters, ReduceMaxAtIdentityIsACopy) {
    const ImageGrey img = randomGrey(31, 18, 7);
    for (Mode mode : kModes) EXPECT_TRUE(bitIdentical(reduceMax(img, 31, 18, mode), img));
}

TEST(Filters, ScalarAndParallelAreBitIdentical) {
    const std::pair<int, int> sizes[] = {{1, 1}, {3, 2}, {4, 6}, {5, 5}, {6, 9}, {131, 77}, {300, 211}};
    std::uint32_t seed = 1234;
    for (auto [w, h] : sizes) {
        SCOPED_TRACE(testing::Message() << w << "x" << h);
        const ImageRGB rgb = randomRgb(w, h, ++seed);
        const ImageGrey gs = greyscale(rgb, 0.9f, Mode::Scalar), gp = greyscale(rgb, 0.9f, Mode::Parallel);
        ASSERT_TRUE(bitIdentical(gs, gp));
        const ImageGrey ls = laplacianMagnitude(gs, Mode::Scalar), lp = laplacianMagnitude(gs, Mode::Parallel);
        ASSERT_TRUE(bitIdentical(ls, lp));
        for (int r : {0, 1, 2, 4}) {
            const ImageGrey bs = boxBlur(ls, r, Mode::Scalar), bp = boxBlur(ls, r, Mode::Parallel);
            ASSERT_TRUE(bitIdentical(bs, bp)) << "radius " << r;
        }
        const ImageGrey ds = deadZone(ls, 0.05f, 0.3f, Mode::Scalar), dp = deadZone(ls, 0.05f, 0.3f, Mode::Parallel);
        ASSERT_TRUE(bitIdentical(ds, dp));
        for (auto [ow, oh] : {std::pair{w, h}, {w * 2 / 3 + 1, h * 2 / 3 + 1}, {w / 2 + 1, h / 2 + 1}, {w + 3, h * 2}}) {
            const ImageGrey rs = reduceMax(ds, ow, oh, Mode::Scalar), rp = reduceMax(ds, ow, oh, Mode::Parallel);
            ASSERT_TRUE(bitIdentical(rs, rp)) << ow << "x" << oh;
        }
        const FilterParams params{1.1f, 1, 0.01f, 0.5f};
        const AamapImages s = buildAamap(rgb, w * 2 / 3 + 1, h * 2 / 3 + 1, params, Mode::Scalar);
        const AamapImages p = buildAamap(rgb, w * 2 / 3 + 1, h * 2 / 3 + 1, params, Mode::Parallel);
        ASSERT_TRUE(bitIdentical(s.grey, p.grey) && bitIdentical(s.laplacian, p.laplacian) &&
                    bitIdentical(s.aamap, p.aamap));
    }
}

TEST(Filters, ReduceMaxModesAgreeOnSignedZeros) {
    // Equal values differing only in sign: both modes must pick the same one.
    std::mt19937 rng(99);
    ImageGrey map(45, 33);
    for (float& v : map.pixels()) v = (rng() % 2) ? 0.0f : -0.0f;
    for (auto [w, h] : {std::pair{30, 22}, {20, 20}, {45, 33}, {60, 50}})
        EXPECT_TRUE(bitIdentical(reduceMax(map, w, h, Mode::Scalar), reduceMax(map, w, h, Mode::Parallel)));
}

TEST(Filters, FlatGateKeepsTheLaplacianOnlyWhereTheGreySpansTheRange) {
    // Columns 0..10 at 0.2 and 11..23 at 0.7 (a step between 10 and 11), and, far to the right, a
    // parabola whose 3x3 windows span under 1/255 but whose Laplacian is not 0.
    const int w = 48, h = 9;
    ImageGrey grey(w, h);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const float d = static_cast<float>(x - 40);
            grey.at(x, y) = x <= 10 ? 0.2f : (x < 32 ? 0.7f : 0.7f + 1e-5f * d * d);
        }
    const float range = 1.0f / 255.0f;
    for (Mode mode : kModes) {
        SCOPED_TRACE(name(mode));
        const ImageGrey plain = laplacianMagnitude(grey, mode);
        ImageGrey gated = plain;
        flatGate(grey, gated, range, mode);
        for (int y = 0; y < h; ++y) {
            // The 5x5 Laplacian answers two texels either side of the step; the gate keeps the two
            // texels whose 3x3 window holds both sides, bit for bit.
            for (int x : {9, 10, 11, 12}) EXPECT_GT(plain.at(x, y), 0.0f) << x;
            for (int x : {10, 11}) EXPECT_EQ(gated.at(x, y), plain.at(x, y)) << x;
            for (int x : {9, 12}) EXPECT_EQ(gated.at(x, y), 0.0f) << x;
            EXPECT_GT(plain.at(40, y), 0.0f);
            for (int x = 30; x < w; ++x) EXPECT_EQ(gated.at(x, y), 0.0f) << x;
        }
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x)
                if (gated.at(x, y) != 0.0f) {
                    EXPECT_TRUE(x == 10 || x == 11) << x << "," << y;
                }
        // flatRange 0 (and below) leaves the Laplacian as it is.
        for (float off : {0.0f, -1.0f}) {
            ImageGrey same = plain;
            flatGate(grey, same, off, mode);
            EXPECT_TRUE(bitIdentical(same, plain));
        }
    }
    ImageGrey wrongSize(w - 1, h);
    EXPECT_THROW(flatGate(grey, wrongSize, range), std::invalid_argument);
}

TEST(Filters, BlackSquareOnWhiteLightsUpOnlyItsBorder) {
    // Snapshot 96x96 (scale 1.5 of 64x64) with a black square over texels [30, 66).
    ImageRGB snapshot(96, 96, glm::vec3(1.0f));
    for (int y = 30; y < 66; ++y)
        for (int x = 30; x < 66; ++x) snapshot.at(x, y) = glm::vec3(0.0f);
    for (Mode mode : kModes) {
        SCOPED_TRACE(name(mode));
        const AamapImages r = buildAamap(snapshot, 64, 64, FilterParams{}, mode);
        ASSERT_EQ(r.aamap.width(), 64);
        ASSERT_EQ(r.aamap.height(), 64);
        // The square's sides fall in output columns/rows 20 (texel 30) and 43 (texel 65).
        for (int t = 20; t <= 43; ++t) {
            EXPECT_GT(r.aamap.at(20, t), 0.0f) << t;
            EXPECT_GT(r.aamap.at(43, t), 0.0f) << t;
            EXPECT_GT(r.aamap.at(t, 20), 0.0f) << t;
            EXPECT_GT(r.aamap.at(t, 43), 0.0f) << t;
        }
        for (int y = 0; y < 64; ++y)
            for (int x = 0; x < 64; ++x) {
                const float v = r.aamap.at(x, y);
                ASSERT_GE(v, 0.0f);
                ASSERT_LE(v, 1.0f);
                // Laplacian (2) + blur (1) reach 3 texels = 2 output pixels; 4 is far.
                const bool inside = x > 20 + 4 && x < 43 - 4 && y > 20 + 4 && y < 43 - 4;
                const bool outside = x < 20 - 4 || x > 43 + 4 || y < 20 - 4 || y > 43 + 4;
                if (inside || outside) {
                    ASSERT_EQ(v, 0.0f) << x << "," << y;
                }
            }
    }
}

TEST(Filters, InvalidArgumentsThrow) {
    const ImageGrey img(4, 4, 0.0f);
    EXPECT_THROW(boxBlur(img, -1), std::invalid_argument);
    EXPECT_THROW(reduceMax(img, 0, 4), std::invalid_argument);
    EXPECT_THROW(reduceMax(ImageGrey{}, 4, 4), std::invalid_argument);
}

}  // namespace
}  // namespace aamap::cpu
