// aamap quality: recall, precision, flagged fraction on hand-made maps.
#include <stdexcept>

#include <gtest/gtest.h>

#include "eval/metrics/map_quality.h"
#include "patterns.h"

namespace aamap::metrics {
namespace {

TEST(MapQuality, HandMade4x4) {
    // True aliasing (FLIP > 0.1): (0,0) (1,0) (2,0) (0,1). (3,0) is exactly 0.1: not above.
    ImageGrey flip(4, 4, 0.0f);
    flip.at(0, 0) = 0.5f;
    flip.at(1, 0) = 0.2f;
    flip.at(2, 0) = 0.9f;
    flip.at(0, 1) = 0.11f;
    flip.at(3, 0) = 0.1f;
    // Flagged (aamap > 0): (0,0) (1,0) (1,1) (2,2) (3,3); (3,2) is negative, not flagged.
    ImageGrey aamap(4, 4, 0.0f);
    aamap.at(0, 0) = 1.0f;
    aamap.at(1, 0) = 0.3f;
    aamap.at(1, 1) = 0.01f;
    aamap.at(2, 2) = 2.0f;
    aamap.at(3, 3) = 1.0f;
    aamap.at(3, 2) = -1.0f;

    const MapQuality q = mapQuality(flip, aamap);
    EXPECT_EQ(q.pixels, 16u);
    EXPECT_EQ(q.truePixels, 4u);
    EXPECT_EQ(q.flaggedPixels, 5u);
    EXPECT_EQ(q.truePositives, 2u);
    EXPECT_DOUBLE_EQ(q.recall, 0.5);
    EXPECT_DOUBLE_EQ(q.precision, 0.4);
    EXPECT_DOUBLE_EQ(q.flaggedFraction, 5.0 / 16.0);
    EXPECT_DOUBLE_EQ(q.trueFraction, 4.0 / 16.0);

    // A lower threshold makes (3,0) true as well.
    EXPECT_EQ(mapQuality(flip, aamap, 0.05f).truePixels, 5u);
}

TEST(MapQuality, EmptyDenominatorsReadAsNoMissesAndNoFalseAlarms) {
    const ImageGrey zero(4, 4, 0.0f);
    const ImageGrey all(4, 4, 1.0f);
    // Nothing aliased, everything flagged: recall 1 (nothing to find), precision 0.
    MapQuality q = mapQuality(zero, all);
    EXPECT_DOUBLE_EQ(q.recall, 1.0);
    EXPECT_DOUBLE_EQ(q.precision, 0.0);
    EXPECT_DOUBLE_EQ(q.flaggedFraction, 1.0);
    // Everything aliased, nothing flagged: recall 0, precision 1 (no false alarm).
    q = mapQuality(all, zero);
    EXPECT_DOUBLE_EQ(q.recall, 0.0);
    EXPECT_DOUBLE_EQ(q.precision, 1.0);
    EXPECT_DOUBLE_EQ(q.flaggedFraction, 0.0);
}

TEST(MapQuality, FromImages) {
    const ImageRGB ref = test::scene(48, 32);
    const ImageRGB oneRay = test::scene(48, 32, 1.0f);  // edges moved: visible differences
    const ImageGrey none(48, 32, 0.0f);
    MapQuality q = mapQuality(ref, ref, none);
    EXPECT_EQ(q.truePixels, 0u);
    EXPECT_DOUBLE_EQ(q.recall, 1.0);
    q = mapQuality(oneRay, ref, ImageGrey(48, 32, 1.0f));
    EXPECT_GT(q.truePixels, 0u);
    EXPECT_DOUBLE_EQ(q.recall, 1.0);
    EXPECT_DOUBLE_EQ(q.precision, q.trueFraction);
    MapQualityOptions hdr;
    hdr.range = FlipRange::Hdr;
    EXPECT_GT(mapQuality(oneRay, ref, none, hdr).truePixels, 0u);
}

TEST(MapQuality, OwnRecallCountsOnlyTruePixelsThatDifferThemselves) {
    ImageGrey flip(4, 1, 0.5f);  // all four truly aliased by FLIP
    ImageGrey aamap(4, 1, 0.0f);
    aamap.at(0, 0) = aamap.at(2, 0) = 1.0f;
    Image<std::uint8_t> own(4, 1, 0);
    own.at(0, 0) = own.at(1, 0) = 1;  // (2,0) and (3,0) equal the reference: FLIP spread there
    const MapQuality q = mapQuality(flip, aamap, 0.1f, &own);
    EXPECT_EQ(q.truePixels, 4u);
    EXPECT_EQ(q.truePositives, 2u);
    EXPECT_DOUBLE_EQ(q.recall, 0.5);
    EXPECT_EQ(q.ownTruePixels, 2u);
    EXPECT_EQ(q.ownTruePositives, 1u);
    EXPECT_DOUBLE_EQ(q.ownRecall, 0.5);
    own.pixels().assign(4, 0);  // nothing differs: nothing own to find
    EXPECT_DOUBLE_EQ(mapQuality(flip, aamap, 0.1f, &own).ownRecall, 1.0);
    EXPECT_EQ(mapQuality(flip, aamap, 0.1f).ownTruePixels, 4u);  // no mask: T' = T
}

// A black-to-white step moved by one pixel: FLIP is above 0.1 on pixels beside the moved one where
// both images are equal, and those are exactly the true pixels that are not own.
TEST(MapQuality, ShiftedHighContrastStepSpreadsFlipBeyondTheDifferingPixels) {
    ImageRGB ref(32, 8, glm::vec3(0.0f)), oneRay(32, 8, glm::vec3(0.0f));
    for (int y = 0; y < 8; ++y)
        for (int x = 0; x < 32; ++x) {
            if (x >= 16) ref.at(x, y) = glm::vec3(1.0f);
            if (x >= 17) oneRay.at(x, y) = glm::vec3(1.0f);
        }
    const Image<std::uint8_t> own = ownDisplayDifference(oneRay, ref, 1.0f);
    for (int y = 0; y < 8; ++y)
        for (int x = 0; x < 32; ++x) EXPECT_EQ(own.at(x, y), x == 16 ? 1 : 0) << x;
    const MapQuality q = mapQuality(oneRay, ref, ImageGrey(32, 8, 0.0f));
    EXPECT_EQ(q.ownTruePixels, 8u);          // the moved column
    EXPECT_GT(q.truePixels, q.ownTruePixels);  // and FLIP's spread beside it
    EXPECT_DOUBLE_EQ(q.ownRecall, 0.0);
}

TEST(MapQuality, RejectsMismatchedSizes) {
    EXPECT_THROW(mapQuality(ImageGrey(4, 4), ImageGrey(4, 3)), std::invalid_argument);
    const Image<std::uint8_t> own(4, 3, 0);
    EXPECT_THROW(mapQuality(ImageGrey(4, 4), ImageGrey(4, 4), 0.1f, &own), std::invalid_argument);
    EXPECT_THROW(mapQuality(ImageGrey(), ImageGrey()), std::invalid_argument);
}

}  // namespace
}  // namespace aamap::metrics
