// The worst-region crops of the report: greedy, non-overlapping windows by summed error.
#include <algorithm>
#include <cstdlib>

#include <gtest/gtest.h>

#include "eval/metrics/worst_regions.h"

namespace aamap::metrics {
namespace {

void fillSquare(ImageGrey& img, int x0, int y0, int side, float v) {
    for (int y = y0; y < y0 + side; ++y)
        for (int x = x0; x < x0 + side; ++x) img.at(x, y) = v;
}

TEST(WorstRegions, FindsTheHotSpotsInOrderOfSummedError) {
    ImageGrey error(64, 48, 0.0f);
    fillSquare(error, 40, 8, 8, 0.5f);   // sum 32
    fillSquare(error, 4, 30, 8, 1.0f);   // sum 64: the worst
    fillSquare(error, 20, 2, 4, 0.25f);  // sum 4
    const std::vector<Region> r = worstRegions(error, 8, 3);
    ASSERT_EQ(r.size(), 3u);
    EXPECT_EQ(r[0].x, 4);
    EXPECT_EQ(r[0].y, 30);
    EXPECT_DOUBLE_EQ(r[0].meanError, 1.0);  // the window is exactly the square
    EXPECT_EQ(r[1].x, 40);
    EXPECT_EQ(r[1].y, 8);
    EXPECT_DOUBLE_EQ(r[1].meanError, 0.5);
    // The third window holds the whole small square (sum 4), wherever it sits around it.
    EXPECT_DOUBLE_EQ(r[2].meanError * 64, 4.0);
    EXPECT_LE(r[2].x, 20);
    EXPECT_GE(r[2].x + 8, 24);
}

TEST(WorstRegions, WindowsStayInsideAndNeverOverlap) {
    ImageGrey error(50, 37, 0.0f);
    for (int y = 0; y < error.height(); ++y)
        for (int x = 0; x < error.width(); ++x) error.at(x, y) = static_cast<float>((x * 7 + y * 13) % 11) / 10.0f;
    const int size = 9;
    const std::vector<Region> r = worstRegions(error, size, 6);
    ASSERT_FALSE(r.empty());
    for (std::size_t i = 0; i < r.size(); ++i) {
        EXPECT_EQ(r[i].size, size);
        EXPECT_GE(r[i].x, 0);
        EXPECT_GE(r[i].y, 0);
        EXPECT_LE(r[i].x + size, error.width());
        EXPECT_LE(r[i].y + size, error.height());
        if (i > 0) {
            EXPECT_GE(r[i - 1].meanError, r[i].meanError);
        }
        for (std::size_t j = 0; j < i; ++j)
            EXPECT_TRUE(std::abs(r[i].x - r[j].x) >= size || std::abs(r[i].y - r[j].y) >= size) << i << " " << j;
    }
}

TEST(WorstRegions, NothingToShowWithoutError) {
    EXPECT_TRUE(worstRegions(ImageGrey(32, 32, 0.0f), 8, 4).empty());  // a perfect render
    EXPECT_TRUE(worstRegions(ImageGrey(4, 4, 1.0f), 8, 4).empty());    // window larger than the image
    EXPECT_EQ(worstRegions(ImageGrey(16, 16, 1.0f), 8, 9).size(), 4u); // only 4 disjoint windows fit
}

TEST(WorstRegions, DefaultSizeIsAnEighthOfTheShorterSide) {
    EXPECT_EQ(defaultRegionSize(256, 256), 32);
    EXPECT_EQ(defaultRegionSize(512, 384), 48);
    EXPECT_EQ(defaultRegionSize(40, 64), 8);  // floor of 8 pixels
    EXPECT_EQ(defaultRegionSize(5, 64), 5);   // never larger than the image
}

}  // namespace
}  // namespace aamap::metrics
