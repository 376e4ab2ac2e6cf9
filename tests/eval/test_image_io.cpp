// Image files: EXR/PNG round trips, tone mapping, the false-colour legend, atomic writes.
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>
#include <fstream>
#include <stdexcept>

#include <gtest/gtest.h>

#include "core/atomic_file.h"
#include "core/error.h"
#include "core/image_io.h"
#include "tests/common/temp_dir.h"

namespace aamap {
namespace {

namespace fs = std::filesystem;

class ImageIo : public ::testing::Test {
protected:
    std::vector<std::string> entries() const { return scratch_.entries(); }

    test::TempDir scratch_;
    const fs::path dir_ = scratch_.path();
};

TEST_F(ImageIo, ExrRgbRoundTripIsExact) {
    ImageRGB img(5, 3);
    for (int y = 0; y < 3; ++y)
        for (int x = 0; x < 5; ++x) img.at(x, y) = {x * 0.25f, y * 1e-3f, 1e4f + x * y};
    writeExr(dir_ / "a.exr", img);
    EXPECT_EQ(readExr(dir_ / "a.exr"), img);
    EXPECT_THROW(readExrGrey(dir_ / "a.exr"), InputError);  // colour is not a map
}

TEST_F(ImageIo, ExrGreyRoundTripIsExact) {
    ImageGrey map(4, 2);
    for (std::size_t i = 0; i < map.size(); ++i) map.pixels()[i] = static_cast<float>(i) / 7.0f;
    writeExr(dir_ / "m.exr", map);
    EXPECT_EQ(readExrGrey(dir_ / "m.exr"), map);
    const ImageRGB asRgb = readExr(dir_ / "m.exr");  // Y replicated
    EXPECT_EQ(asRgb.at(3, 1), glm::vec3(map.at(3, 1)));
}

TEST_F(ImageIo, PngRoundTripAndToneMapping) {
    ImageRGB img(3, 2);
    img.at(0, 0) = {0.0f, 0.5f, 1.0f};
    img.at(1, 0) = {2.0f, -1.0f, 0.0031308f};
    img.at(2, 0) = {std::numeric_limits<float>::quiet_NaN(), std::numeric_limits<float>::infinity(), 0.25f};
    const ImageRGB8 ldr = toneMap(img, 1.0f);
    EXPECT_EQ(ldr.at(0, 0), glm::u8vec3(0, 188, 255));  // sRGB(0.5) = 0.7354
    EXPECT_EQ(ldr.at(1, 0), glm::u8vec3(255, 0, 10));   // clamped; the OETF's linear toe
    EXPECT_EQ(ldr.at(2, 0), glm::u8vec3(0, 0, 137));    // non-finite -> black
    EXPECT_EQ(toneMap(img, 2.0f).at(0, 0), glm::u8vec3(0, 255, 255));
    writePng(dir_ / "a.png", ldr);
    EXPECT_EQ(readPng(dir_ / "a.png"), ldr);

    ImageGrey map(2, 1);
    map.at(0, 0) = 0.5f;
    map.at(1, 0) = 3.0f;
    const ImageGrey8 q = quantise(map);
    EXPECT_EQ(q.at(0, 0), 128);  // linear, no OETF
    EXPECT_EQ(q.at(1, 0), 255);
    writePng(dir_ / "m.png", q);
    EXPECT_EQ(readPng(dir_ / "m.png").at(0, 0), glm::u8vec3(128));
}

TEST_F(ImageIo, ReadingMissingOrBadFilesIsAnInputError) {
    EXPECT_THROW(readPng(dir_ / "none.png"), InputError);
    EXPECT_THROW(readExr(dir_ / "none.exr"), InputError);
    std::ofstream(dir_ / "junk.exr") << "not an exr";
    EXPECT_THROW(readExr(dir_ / "junk.exr"), InputError);
}

TEST_F(ImageIo, FalseColourHasARampAndALegend) {
    Image<std::uint16_t> rpp(200, 10, 1);
    for (int y = 0; y < 10; ++y) {
        rpp.at(199, y) = 36;
        rpp.at(100, y) = 0;
    }
    const ImageRGB8 fc = falseColour(rpp, 36);
    ASSERT_EQ(fc.width(), 200);
    ASSERT_EQ(fc.height(), 10 + falseColourLegendHeight(200));
    EXPECT_EQ(fc.at(0, 0), colourRamp(0.0f));
    EXPECT_EQ(fc.at(199, 0), colourRamp(1.0f));
    EXPECT_EQ(fc.at(100, 0), glm::u8vec3(0));
    EXPECT_NE(colourRamp(0.0f), colourRamp(1.0f));
    // The legend below the image: white text (title and tick labels) and the full ramp.
    int white = 0;
    bool low = false, high = false;
    for (int y = 10; y < fc.height(); ++y)
        for (int x = 0; x < fc.width(); ++x) {
            white += fc.at(x, y) == glm::u8vec3(255);
            low = low || fc.at(x, y) == colourRamp(0.0f);
            high = high || fc.at(x, y) == colourRamp(1.0f);
        }
    EXPECT_GT(white, 100);
    EXPECT_TRUE(low);
    EXPECT_TRUE(high);
}

TEST_F(ImageIo, FalseColourWidensNarrowImages) {
    const ImageRGB8 fc = falseColour(Image<std::uint16_t>(16, 16, 4), 4);
    EXPECT_GE(fc.width(), 160);  // the legend must stay legible
    EXPECT_EQ(fc.at(0, 0), colourRamp(1.0f));
    EXPECT_EQ(falseColour(Image<std::uint16_t>(8, 8, 1), 1).at(0, 0), colourRamp(1.0f));
}

TEST_F(ImageIo, AtomicWritesLeaveOnlyTheFinalFile) {
    writePng(dir_ / "a.png", ImageRGB8(4, 4));
    writeExr(dir_ / "a.exr", ImageRGB(4, 4));
    writeTextAtomically(dir_ / "a.json", "{}");
    EXPECT_EQ(entries(), (std::vector<std::string>{"a.exr", "a.json", "a.png"}));
}

TEST_F(ImageIo, AFailingWriterLeavesNothing) {
    EXPECT_THROW(writeFileAtomically(dir_ / "b.bin",
                                     [](const fs::path& tmp) {
                                         std::ofstream(tmp) << "half a file";
                                         throw std::runtime_error("disk full");
                                     }),
                 std::runtime_error);
    EXPECT_TRUE(entries().empty());
    // A failure inside a real writer: the previous complete file survives untouched.
    writePng(dir_ / "c.png", ImageRGB8(2, 2, glm::u8vec3(7)));
    EXPECT_THROW(writePng(dir_ / "c.png", ImageRGB8()), EnvironmentError);  // empty image
    EXPECT_THROW(writeExr(dir_ / "missing" / "d.exr", ImageRGB(2, 2)), EnvironmentError);
    EXPECT_EQ(entries(), std::vector<std::string>{"c.png"});
    EXPECT_EQ(readPng(dir_ / "c.png").at(1, 1), glm::u8vec3(7));
}

}  // namespace
}  // namespace aamap
