// Texture decoding (scene/texture_loader.h): every channel layout stb_image returns becomes the
// same RGBA (grey replicated, a missing alpha opaque), the coverage texture reads alpha or, where
// there is none, the first channel, and PNM that stb_image decodes wrongly is refused.
#include <string>

#include <gtest/gtest.h>

#include "scene/texture_loader.h"
#include "tests/common/temp_dir.h"

namespace aamap {
namespace {

// Binary PNM: `magic` P5 (grey) or P6 (RGB), big-endian samples when maxval > 255.
std::string pnm(char magic, int w, int h, int maxval, const std::string& samples) {
    return std::string("P") + magic + "\n" + std::to_string(w) + " " + std::to_string(h) + "\n" +
           std::to_string(maxval) + "\n" + samples;
}

// Debian 12's stb_image reads 16-bit PNM byte-swapped (and past its buffer when converting
// channels), and ignores maxval: such files are refused with a reason, which a scene turns into
// a warning and the plain colour.
TEST(TextureLoader, PnmOtherThanEightBitMaxval255IsRefusedWithTheReason) {
    test::TempDir dir;
    const auto rgb16 = dir.write("rgb16.ppm", pnm('6', 1, 1, 65535, std::string("\xff\x00\x00\x00\x80\x00", 6)));
    const auto grey7 = dir.write("grey7.pgm", "P5\n# made by hand\n2 1 127\n" + std::string("\x40\x7f", 2));
    for (const auto& file : {rgb16, grey7}) {
        std::string error;
        EXPECT_FALSE(loadTexture(file, &error)) << file;
        EXPECT_NE(error.find("PNM with maxval"), std::string::npos) << error;
        error.clear();
        EXPECT_FALSE(loadCoverageTexture(file, &error)) << file;
        EXPECT_NE(error.find("is not supported"), std::string::npos) << error;
    }
}

TEST(TextureLoader, EightBitGreyAndRgbPnm) {
    test::TempDir dir;
    const auto grey = dir.write("grey.pgm", pnm('5', 1, 1, 255, std::string("\xff", 1)));
    const auto rgb = dir.write("rgb.ppm", pnm('6', 1, 1, 255, std::string("\x00\xff\x00", 3)));
    std::string error;
    const auto g = loadTexture(grey, &error);
    ASSERT_TRUE(g) << error;
    EXPECT_EQ(g->rgba, (std::vector<float>{1.0f, 1.0f, 1.0f, 1.0f}));
    const auto c = loadTexture(rgb, &error);
    ASSERT_TRUE(c) << error;
    EXPECT_EQ(c->rgba, (std::vector<float>{0.0f, 1.0f, 0.0f, 1.0f}));
    const auto cov = loadCoverageTexture(rgb, &error);  // no alpha: the first channel
    ASSERT_TRUE(cov) << error;
    EXPECT_EQ(cov->rgba, (std::vector<float>(4, 0.0f)));
}

}  // namespace
}  // namespace aamap
