#include <cmath>

#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>
#include <gtest/gtest.h>

#include "core/error.h"
#include "scene/view_file.h"
#include "tests/common/temp_dir.h"

namespace aamap {
namespace {

const std::filesystem::path kFile = "views/test.vf";

void expectSameVec(glm::vec3 actual, glm::vec3 expected) {
    EXPECT_NEAR(actual.x, expected.x, 1e-6f);
    EXPECT_NEAR(actual.y, expected.y, 1e-6f);
    EXPECT_NEAR(actual.z, expected.z, 1e-6f);
}

// Expects parseViewOptions(text) to fail at kFile:7:column with `what` in the message.
void expectViewError(std::string_view text, int column, const std::string& what) {
    try {
        parseViewOptions(text, kFile, 7);
        FAIL() << "no error for: " << text;
    } catch (const InputError& e) {
        EXPECT_EQ(e.file(), kFile);
        EXPECT_EQ(e.line(), 7);
        EXPECT_EQ(e.column(), column) << e.what();
        EXPECT_NE(std::string(e.what()).find(what), std::string::npos) << e.what();
        EXPECT_EQ(std::string(e.what()).rfind("views/test.vf:7:" + std::to_string(column) + ": ", 0), 0u) << e.what();
    }
}

TEST(ViewOptions, RadianceDefaults) {
    const View v = parseViewOptions("-vtv", kFile, 1);
    expectSameVec(v.position, {0, 0, 0});
    expectSameVec(v.direction, {0, 1, 0});
    expectSameVec(v.up, {0, 0, 1});
    EXPECT_FLOAT_EQ(v.horizontalFovDeg, 45.0f);
    EXPECT_FLOAT_EQ(v.verticalFovDeg, 45.0f);
    EXPECT_FLOAT_EQ(v.shiftX, 0.0f);
    EXPECT_FLOAT_EQ(v.shiftY, 0.0f);
    EXPECT_EQ(v.name, "");
}

TEST(ViewOptions, EveryOption) {
    const View v = parseViewOptions("-vtv -vp 1 2.5 -3 -vd 0 0 -2 -vu 0 1 0 -vh 60 -vv 40.5 -vs 0.25 -vl -0.125 -vo 1 -va 0",
                                    kFile, 1);
    expectSameVec(v.position, {1, 2.5f, -3});
    expectSameVec(v.direction, {0, 0, -1});  // normalised
    expectSameVec(v.up, {0, 1, 0});
    EXPECT_FLOAT_EQ(v.horizontalFovDeg, 60.0f);
    EXPECT_FLOAT_EQ(v.verticalFovDeg, 40.5f);
    EXPECT_FLOAT_EQ(v.shiftX, 0.25f);
    EXPECT_FLOAT_EQ(v.shiftY, -0.125f);
}

TEST(ViewOptions, LaterOptionsOverride) {
    const View v = parseViewOptions("-vh 10 -vh +20 -vp 1 1 1 -vp 2 2 2", kFile, 1);
    EXPECT_FLOAT_EQ(v.horizontalFovDeg, 20.0f);
    expectSameVec(v.position, {2, 2, 2});
}

TEST(ViewOptions, ProgramLinesAndHeaderForm) {
    const View a = parseViewOptions("rview -vtv -vp 0 1 3.9 -vd 0 0 -1 -vu 0 1 0 -vh 39.3 -vv 39.3", kFile, 1);
    expectSameVec(a.position, {0, 1, 3.9f});
    EXPECT_FLOAT_EQ(a.verticalFovDeg, 39.3f);
    const View b = parseViewOptions("rpict -x 512 -y 512 -ab 2 -vp 1 2 3 -vu 0 1 0 -vd 0 0 1 -i scene.oct", kFile, 1);
    expectSameVec(b.position, {1, 2, 3});
    expectSameVec(b.direction, {0, 0, 1});
    const View c = parseViewOptions("VIEW= -vtv -vp 4 5 6 -vd 1 0 0", kFile, 1);
    expectSameVec(c.position, {4, 5, 6});
    const View d = parseViewOptions("VIEW=-vtv -vh 30", kFile, 1);
    EXPECT_FLOAT_EQ(d.horizontalFovDeg, 30.0f);
}

TEST(ViewOptions, NamesFromVnOrTrailingComment) {
    EXPECT_EQ(parseViewOptions("-vtv -vn front # ignored", kFile, 1).name, "front");
    EXPECT_EQ(parseViewOptions("rview -vtv -vp 0 0 0  # overview shot ", kFile, 1).name, "overview shot");
}

TEST(ViewOptions, ErrorsNameFileLineAndColumn) {
    expectViewError("-vtl -vp 0 0 0", 1, "view type -vtl is not supported (only -vtv)");
    expectViewError("rview -vp 0 0 0 -vth", 17, "view type -vth is not supported (only -vtv)");
    expectViewError("-vt", 1, "-vt needs a view type");
    expectViewError("-vp 1 2", 1, "-vp needs 3 numbers");
    expectViewError("-vp 1 x 3", 7, "'x' is not a number");
    expectViewError("-vh nan", 5, "not a finite number");
    expectViewError("-vh", 1, "-vh needs a number");
    expectViewError("-vd 0 0 0", 1, "view direction (-vd) is zero");
    expectViewError("-vd 0 0 1 -vu 0 0 2", 11, "parallel");
    expectViewError("-vu 0 0 0", 1, "(-vu) is zero");
    expectViewError("-vd 0 0 1", 1, "parallel");  // Radiance's default up is +z
    expectViewError("-vh 180", 1, "-vh 180 is outside (0, 180)");
    expectViewError("-vv 0", 1, "-vv 0 is outside");
    expectViewError("-vx 1", 1, "unknown view option '-vx'");
    expectViewError("-vp 0 0 0 -ab 2", 11, "'-ab' is not a view option");
    expectViewError("hello -vp 0 0 0", 1, "expected a view option");
    expectViewError("VIEW= -vtc", 7, "view type -vtc is not supported");
}

TEST(ViewFile, SeveralViewsNamedByStemAndIndex) {
    const std::string text =
        "# a comment line\r\n"
        "rview -vtv -vp 0 0 0 -vd 1 0 0 -vh 50 -vv 40\r\n"
        "\r\n"
        "   VIEW= -vtv -vp 1 1 1 -vd 0 1 0 # named\r\n"
        "-vp 2 2 2 -vd 0 -1 0\r\n"
        "FORMAT=32-bit_rle_rgbe\r\n";
    const auto views = parseViewText(text, "dir/room.vf");
    ASSERT_EQ(views.size(), 3u);
    EXPECT_EQ(views[0].name, "room:0");
    EXPECT_FLOAT_EQ(views[0].horizontalFovDeg, 50.0f);
    EXPECT_EQ(views[1].name, "named");
    EXPECT_EQ(views[2].name, "room:2");
    expectSameVec(views[2].position, {2, 2, 2});
}

TEST(ViewFile, ErrorLineNumbersCountCommentsAndBlankLines) {
    try {
        parseViewText("# c\n\n-vp 0 0 0\n-vp 0 0 q\n", "a.vf");
        FAIL();
    } catch (const InputError& e) {
        EXPECT_EQ(std::string(e.what()), "a.vf:4:9: -vp: 'q' is not a number");
    }
}

TEST(ViewFile, LoadFromDiskAndViewFileReference) {
    test::TempDir dir;
    dir.write("base.vf", "rview -vtv -vp 1 2 3 -vd 0 0 1 -vu 0 1 0 -vh 30 -vv 20\n");
    const auto path = dir.write("cam.vf", "rview -vf base.vf -vh 60\n");
    const auto views = loadViewFile(path);
    ASSERT_EQ(views.size(), 1u);
    expectSameVec(views[0].position, {1, 2, 3});
    EXPECT_FLOAT_EQ(views[0].horizontalFovDeg, 60.0f);
    EXPECT_FLOAT_EQ(views[0].verticalFovDeg, 20.0f);
    EXPECT_EQ(views[0].name, "cam:0");

    EXPECT_THROW(loadViewFile(dir.path() / "missing.vf"), InputError);
    EXPECT_THROW(loadViewFile(dir.write("empty.vf", "# nothing\n")), InputError);
    const auto loop = dir.write("loop.vf", "-vf loop.vf\n");
    EXPECT_THROW(loadViewFile(loop), InputError);
}

TEST(FitResolution, ShrinksOneDimensionForSquarePixels) {
    View v;
    v.horizontalFovDeg = v.verticalFovDeg = 40.0f;
    EXPECT_EQ(fitResolution(v, 512, 384), (std::pair{384, 384}));
    EXPECT_EQ(fitResolution(v, 300, 600), (std::pair{300, 300}));
    v.horizontalFovDeg = 2.0f * glm::degrees(std::atan(2.0f));  // tan ratio 2 : 1
    v.verticalFovDeg = 2.0f * glm::degrees(std::atan(1.0f));
    EXPECT_EQ(fitResolution(v, 1000, 1000), (std::pair{1000, 500}));
    EXPECT_EQ(fitResolution(v, 100, 20), (std::pair{40, 20}));
    EXPECT_THROW(fitResolution(v, 0, 10), std::invalid_argument);
}

}  // namespace
}  // namespace aamap
