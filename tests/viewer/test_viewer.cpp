// `aamap view` end to end (label viewer): the window's screenshot against the files `aamap run`
// wrote for the same config (folder in AAMAP_VIEWER_OFFLINE, made by the viewer.offline test),
// the --help text, and the no-display error. The window needs an X server: xvfb-run provides a
// virtual one; without it the window tests are skipped (not failed) with the reason.
#include <sys/wait.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "core/image_io.h"

namespace aamap {
namespace {

namespace fs = std::filesystem;

std::string env(const char* name) {
    const char* v = std::getenv(name);
    return v ? v : "";
}

struct Outcome {
    int exitCode = -1;
    std::string output;  // stdout and stderr together
};

Outcome runCommand(const std::string& command) {
    Outcome o;
    FILE* pipe = ::popen((command + " 2>&1").c_str(), "r");
    if (!pipe) return o;
    char buffer[4096];
    for (std::size_t n; (n = std::fread(buffer, 1, sizeof buffer, pipe)) > 0;) o.output.append(buffer, n);
    const int status = ::pclose(pipe);
    o.exitCode = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    return o;
}

bool haveXvfb() { return runCommand("command -v xvfb-run && command -v Xvfb && command -v xauth").exitCode == 0; }

// Largest per-channel difference between two same-sized images, and how many pixels differ at all.
struct Difference {
    int maxChannel = 0;
    std::size_t pixels = 0;
};

Difference compare(const ImageRGB8& a, const ImageRGB8& b) {
    Difference d;
    for (std::size_t i = 0; i < a.size(); ++i) {
        const glm::u8vec3 p = a.pixels()[i], q = b.pixels()[i];
        int m = 0;
        for (int c = 0; c < 3; ++c) m = std::max(m, std::abs(int(p[c]) - int(q[c])));
        d.maxChannel = std::max(d.maxChannel, m);
        d.pixels += m > 0;
    }
    return d;
}

class ViewerWindow : public ::testing::Test {
protected:
    void SetUp() override {
        if (!haveXvfb()) GTEST_SKIP() << "xvfb-run, Xvfb or xauth is not installed (tools/install-deps.sh adds xvfb and xauth)";
        ASSERT_FALSE(env("AAMAP_EXE").empty()) << "set AAMAP_EXE";
        offline_ = env("AAMAP_VIEWER_OFFLINE");
        ASSERT_TRUE(fs::is_regular_file(fs::path(offline_) / "aamap.png")) << "run the viewer.offline test first";
        tmp_ = fs::path(env("AAMAP_VIEWER_TMP"));
        fs::create_directories(tmp_);
    }

    // Runs the viewer under a fresh virtual X server; returns the screenshot.
    ImageRGB8 screenshot(const std::string& mode, const std::string& extra) {
        const fs::path shot = tmp_ / fmt::format("{}.png", mode);
        fs::remove(shot);
        const std::string command =
            fmt::format("xvfb-run -a -s '-screen 0 640x480x24' '{}' view '{}' --frames 3 --mode {} --screenshot '{}' {}",
                        env("AAMAP_EXE"), AAMAP_VIEWER_CONFIG, mode, shot.string(), extra);
        const Outcome o = runCommand(command);
        EXPECT_EQ(o.exitCode, 0) << command << "\n" << o.output;
        if (!fs::is_regular_file(shot)) {
            ADD_FAILURE() << "no screenshot " << shot << "\n" << o.output;
            return {};
        }
        return readPng(shot);
    }

    fs::path offline_, tmp_;
};

// The aamap the window shows is the one `aamap run` wrote: same prepareScene, same Snapshot
// graph on the same device, same quantise(). Tolerance 0: the only steps in between are the
// composition (nearest neighbour, integer zoom 2) and a UNORM swapchain, which copy bytes, so any
// difference is a bug (an sRGB swapchain would re-encode them, a filter would blur them).
TEST_F(ViewerWindow, AamapScreenshotMatchesTheOfflineAamap) {
    const ImageRGB8 offline = readPng(fs::path(offline_) / "aamap.png");
    const ImageRGB8 shot = screenshot("aamap", "--zoom 2");
    ASSERT_EQ(shot.width(), offline.width());
    ASSERT_EQ(shot.height(), offline.height());
    const Difference d = compare(shot, offline);
    EXPECT_EQ(d.maxChannel, 0) << d.pixels << " pixels differ";
    // Not a blank image that matches by accident: the box's edges are flagged, its walls are not.
    const auto lit = std::count_if(offline.pixels().begin(), offline.pixels().end(), [](glm::u8vec3 p) { return p.r > 0; });
    EXPECT_GT(lit, 0);
    EXPECT_LT(static_cast<std::size_t>(lit), offline.size());
}

// The selective render traced from the window is the offline render: one code path (the same
// prepareScene, traceSettingsFor and tracer, deterministic per pixel and seed), and the tile
// callback that feeds the live view only reads. Tolerance 0 for the same reason as above.
TEST_F(ViewerWindow, TracedRenderMatchesTheOfflineRender) {
    const ImageRGB8 offline = readPng(fs::path(offline_) / "selective.png");
    const ImageRGB8 shot = screenshot("render", "--trace --render selective --threads 2");
    ASSERT_EQ(shot.width(), offline.width());
    ASSERT_EQ(shot.height(), offline.height());
    const Difference d = compare(shot, offline);
    EXPECT_EQ(d.maxChannel, 0) << d.pixels << " pixels differ";
}

TEST(ViewerCli, HelpListsTheControls) {
    const Outcome o = runCommand(fmt::format("'{}' view --help", env("AAMAP_EXE")));
    EXPECT_EQ(o.exitCode, 0) << o.output;
    for (const char* text : {"--screenshot", "--frames", "--mode", "orbit", "trace the current view", "blur radius",
                             "threshold", "spacing", "rays per pixel", "error map"})
        EXPECT_NE(o.output.find(text), std::string::npos) << "missing '" << text << "' in\n" << o.output;
}

TEST(ViewerCli, NoDisplayIsAClearEnvironmentError) {
    const Outcome o = runCommand(fmt::format("env -u DISPLAY -u WAYLAND_DISPLAY '{}' view '{}' --frames 1",
                                             env("AAMAP_EXE"), AAMAP_VIEWER_CONFIG));
    EXPECT_EQ(o.exitCode, 1) << o.output;
    EXPECT_NE(o.output.find("aamap: error: aamap view needs a display"), std::string::npos) << o.output;
}

}  // namespace
}  // namespace aamap
