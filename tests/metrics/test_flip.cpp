// FLIP: filter kernels, properties that hold by construction, HDR-FLIP, magma, determinism.
#include <algorithm>
#include <cmath>
#include <numeric>
#include <stdexcept>

#include <gtest/gtest.h>
#include <tbb/task_arena.h>

#include "eval/metrics/flip.h"
#include "eval/metrics/flip_color.h"
#include "eval/metrics/flip_feature.h"
#include "eval/metrics/flip_filters.h"
#include "eval/metrics/magma.h"
#include "patterns.h"

namespace aamap::metrics {
namespace {

float sum(const std::vector<float>& v) { return std::accumulate(v.begin(), v.end(), 0.0f); }

TEST(Flip, DefaultPixelsPerDegree) {
    EXPECT_NEAR(kDefaultPpd, 67.0206f, 1e-3f);
    EXPECT_NEAR(pixelsPerDegree(1.0f, 1000.0f, 1.0f), 1000.0f * 3.14159265f / 180.0f, 1e-3f);
}

TEST(Flip, CsfKernelsSumToOneIn2D) {
    for (float ppd : {kDefaultPpd, 30.0f, 120.0f}) {
        const flip::SpatialFilters f = flip::makeSpatialFilters(ppd);
        ASSERT_EQ(f.y.size(), std::size_t(2 * f.radius + 1));
        // Separable: the 2D kernel sums to the square of the 1D sum; Cz is two separable terms.
        EXPECT_NEAR(sum(f.y) * sum(f.y), 1.0f, 1e-5f);
        EXPECT_NEAR(sum(f.cx) * sum(f.cx), 1.0f, 1e-5f);
        EXPECT_NEAR(sum(f.cz1) * sum(f.cz1) + sum(f.cz2) * sum(f.cz2), 1.0f, 1e-5f);
        for (int i = 0; i < f.radius; ++i) EXPECT_FLOAT_EQ(f.y[i], f.y[f.y.size() - 1 - i]);  // even
    }
    // Radius: 3 sigma of the widest Gaussian (b = 0.04), at 67 PPD ceil(9.05) = 10.
    EXPECT_EQ(flip::spatialFilterRadius(kDefaultPpd), 10);
}

TEST(Flip, FeatureKernelsAreNormalised) {
    const flip::FeatureFilter f = flip::makeFeatureFilter(kDefaultPpd);
    EXPECT_NEAR(f.sigma, 0.5f * 0.082f * kDefaultPpd, 1e-5f);
    EXPECT_EQ(f.radius, 9);  // ceil(3 * 2.748)
    EXPECT_NEAR(sum(f.gauss), 1.0f, 1e-5f);
    float pos1 = 0, neg1 = 0, pos2 = 0, neg2 = 0;
    for (std::size_t i = 0; i < f.d1.size(); ++i) {
        (f.d1[i] > 0 ? pos1 : neg1) += f.d1[i];
        (f.d2[i] > 0 ? pos2 : neg2) += f.d2[i];
        EXPECT_FLOAT_EQ(f.d1[i], -f.d1[f.d1.size() - 1 - i]);  // odd
        EXPECT_FLOAT_EQ(f.d2[i], f.d2[f.d2.size() - 1 - i]);   // even
    }
    EXPECT_NEAR(pos1, 1.0f, 1e-5f);
    EXPECT_NEAR(neg1, -1.0f, 1e-5f);
    EXPECT_NEAR(pos2, 1.0f, 1e-5f);
    EXPECT_NEAR(neg2, -1.0f, 1e-5f);
}

TEST(Flip, ColourConversionsRoundTrip) {
    const glm::vec3 rgb{0.2f, 0.5f, 0.9f};
    const glm::vec3 back = flip::xyzToLinearRgb(flip::ycxczToXyz(flip::linearRgbToYcxcz(rgb)));
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(back[k], rgb[k], 1e-5f);
    const glm::vec3 whiteLab = flip::xyzToLab(flip::linearRgbToXyz(glm::vec3(1.0f)));
    EXPECT_NEAR(whiteLab.x, 100.0f, 1e-3f);
    EXPECT_NEAR(whiteLab.y, 0.0f, 1e-3f);
    EXPECT_NEAR(whiteLab.z, 0.0f, 1e-3f);
}

TEST(Flip, IdenticalImagesGiveExactlyZero) {
    const ImageRGB img = test::randomImage(40, 30, 7);
    for (const FlipResult& r : {flipLdr(img, img), flipHdr(img, img)}) {
        for (float v : r.errorMap.pixels()) ASSERT_EQ(v, 0.0f);
        EXPECT_EQ(r.mean, 0.0);
        EXPECT_EQ(r.fractionAbove, 0.0);
    }
}

TEST(Flip, ErrorLiesInUnitInterval) {
    const ImageRGB a = test::randomImage(48, 32, 8);
    const ImageRGB b = test::randomImage(48, 32, 9);
    ImageRGB extreme(48, 32);
    for (int y = 0; y < 32; ++y)
        for (int x = 0; x < 48; ++x) extreme.at(x, y) = ((x + y) % 2) ? glm::vec3(0, 1, 0) : glm::vec3(0, 0, 1);
    for (const auto& [r, t] : {std::pair{a, b}, std::pair{a, extreme}, std::pair{extreme, ImageRGB(48, 32)}}) {
        for (const FlipResult& res : {flipLdr(r, t), flipHdr(r, t)}) {
            for (float v : res.errorMap.pixels()) {
                ASSERT_GE(v, 0.0f);
                ASSERT_LE(v, 1.0f);
            }
            EXPECT_GT(res.mean, 0.0);
        }
    }
}

TEST(Flip, BlackAgainstWhiteIsNearOne) {
    // Flat images: no features, so FLIP is the redistributed colour difference, ~0.967.
    const FlipResult r = flipLdr(ImageRGB(24, 24, glm::vec3(0.0f)), ImageRGB(24, 24, glm::vec3(1.0f)));
    EXPECT_GT(r.mean, 0.95);
    EXPECT_LE(r.mean, 1.0);
    EXPECT_EQ(r.fractionAbove, 1.0);
}

TEST(Flip, LdrFlipIsSymmetric) {
    // Every step depends on |r - t| or (r - t)^2, so swapping the images changes nothing.
    const ImageRGB a = test::scene(64, 48);
    const ImageRGB b = test::scene(64, 48, 1.0f);
    EXPECT_EQ(flipLdr(a, b).errorMap, flipLdr(b, a).errorMap);
    // HDR-FLIP is only symmetric once the exposure range no longer comes from the reference.
    FlipOptions o;
    o.startExposure = -2.0f;
    o.stopExposure = 1.0f;
    EXPECT_EQ(flipHdr(a, b, o).errorMap, flipHdr(b, a, o).errorMap);
}

TEST(Flip, FeatureDifferenceSeesShiftedEdgesNotFlatChanges) {
    const flip::FeatureFilter f = flip::makeFeatureFilter(kDefaultPpd);
    auto ycc = [](const ImageRGB& img) {
        ImageRGB out(img.width(), img.height());
        for (std::size_t i = 0; i < img.size(); ++i) out.pixels()[i] = flip::linearRgbToYcxcz(img.pixels()[i]);
        return out;
    };
    const ImageGrey flat = flip::featureDifference(ycc(ImageRGB(16, 16, glm::vec3(0.2f))),
                                                   ycc(ImageRGB(16, 16, glm::vec3(0.7f))), f);
    for (float v : flat.pixels()) EXPECT_NEAR(v, 0.0f, 1e-3f);
    const ImageGrey shifted = flip::featureDifference(ycc(test::scene(64, 48)), ycc(test::scene(64, 48, 1.0f)), f);
    EXPECT_GT(*std::max_element(shifted.pixels().begin(), shifted.pixels().end()), 0.2f);
}

TEST(Flip, DisplayAndSrgbEntryPointsAgreeWithLinear) {
    const ImageRGB a = test::scene(40, 30);
    const ImageRGB b = test::scene(40, 30, 0.5f);
    EXPECT_EQ(flipDisplay(a, b).errorMap, flipLdr(a, b).errorMap);
    ImageRGB half = a;
    for (auto& p : half.pixels()) p *= 0.5f;
    ImageRGB halfB = b;
    for (auto& p : halfB.pixels()) p *= 0.5f;
    EXPECT_EQ(flipDisplay(half, halfB, 2.0f).errorMap, flipLdr(a, b).errorMap);
    auto encode = [](const ImageRGB& img) {
        ImageRGB out = img;
        for (auto& p : out.pixels())
            for (int k = 0; k < 3; ++k) p[k] = 1.055f * std::pow(p[k], 1.0f / 2.4f) - 0.055f;
        return out;
    };
    EXPECT_NEAR(flipLdrSrgb(encode(a), encode(b)).mean, flipLdr(a, b).mean, 1e-5);
}

TEST(Flip, HdrExposureRangeFollowsTheReference) {
    ImageRGB ref(8, 8, glm::vec3(1.0f));
    ref.at(0, 0) = glm::vec3(16.0f);  // max luminance 16, median 1
    const ExposureRange r = automaticExposureRange(ref, ToneMapper::Aces);
    EXPECT_NEAR(r.stop - r.start, 4.0f, 1e-4f);  // log2(16 / 1)
    // At the start exposure the brightest pixel tone maps to 0.85.
    EXPECT_NEAR(toneMapHdr(glm::vec3(16.0f * std::exp2(r.start)), ToneMapper::Aces).x, 0.85f, 1e-4f);
    const FlipResult res = flipHdr(ref, ImageRGB(8, 8, glm::vec3(0.5f)));
    EXPECT_EQ(res.numExposures, 4);
    EXPECT_FLOAT_EQ(res.startExposure, r.start);
    EXPECT_FLOAT_EQ(res.stopExposure, r.stop);
    for (float v : res.exposureMap.pixels()) EXPECT_TRUE(v >= 0.0f && v <= 1.0f);
    EXPECT_EQ(automaticExposureRange(ImageRGB(4, 4), ToneMapper::Hable).start, 0.0f);  // all black
    FlipOptions bad;
    bad.startExposure = 2.0f;
    bad.stopExposure = 1.0f;
    EXPECT_THROW(flipHdr(ref, ref, bad), std::invalid_argument);
}

TEST(Flip, ToneMappersAreMonotoneAndBounded) {
    for (ToneMapper tm : {ToneMapper::Aces, ToneMapper::Hable, ToneMapper::Reinhard}) {
        float prev = -1.0f;
        for (float x : {0.0f, 0.01f, 0.1f, 1.0f, 10.0f, 100.0f}) {
            const float v = toneMapHdr(glm::vec3(x), tm).x;
            EXPECT_GT(v, prev);
            prev = v;
        }
        EXPECT_NEAR(toneMapHdr(glm::vec3(0.0f), tm).x, 0.0f, 1e-6f);
        EXPECT_LT(toneMapHdr(glm::vec3(1e4f), tm).x, 1.3f);
    }
}

TEST(Flip, MagmaMapEndsAndRange) {
    EXPECT_NEAR(magmaSrgb(0.0f).x, 0.001462f, 1e-6f);
    EXPECT_NEAR(magmaSrgb(1.0f).z, 0.749504f, 1e-6f);
    EXPECT_EQ(magmaSrgb(std::nanf("")), magmaSrgb(0.0f));
    const FlipResult r = flipLdr(test::scene(20, 10), test::scene(20, 10, 2.0f));
    const ImageRGB m = flipMagma(r);
    ASSERT_EQ(m.width(), 20);
    for (const glm::vec3& c : m.pixels())
        for (int k = 0; k < 3; ++k) EXPECT_TRUE(c[k] >= 0.0f && c[k] <= 1.0f);
}

TEST(Flip, RejectsBadInput) {
    EXPECT_THROW(flipLdr(ImageRGB(4, 4), ImageRGB(5, 4)), std::invalid_argument);
    EXPECT_THROW(flipLdr(ImageRGB(), ImageRGB()), std::invalid_argument);
    FlipOptions o;
    o.ppd = 0.0f;
    EXPECT_THROW(flipLdr(ImageRGB(4, 4), ImageRGB(4, 4), o), std::invalid_argument);
}

TEST(Flip, DeterministicAcrossThreadCounts) {
    const ImageRGB a = test::scene(96, 64);
    const ImageRGB b = test::randomImage(96, 64, 11);
    FlipResult one, many;
    tbb::task_arena(1).execute([&] { one = flipHdr(a, b); });
    tbb::task_arena(4).execute([&] { many = flipHdr(a, b); });
    EXPECT_EQ(one.errorMap, many.errorMap);
    EXPECT_EQ(one.mean, many.mean);
    EXPECT_EQ(one.fractionAbove, many.fractionAbove);
}

}  // namespace
}  // namespace aamap::metrics
