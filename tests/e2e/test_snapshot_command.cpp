// `aamap snapshot` end to end on the built-in Cornell box plus a light file: its images, the
// --explain text (kept and culled passes, and the scene's light decisions), the --dot file, and a
// bad light file's file:line:col error with exit code 2.
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include <fmt/format.h>
#include <gtest/gtest.h>

namespace {

namespace fs = std::filesystem;

struct CommandResult {
    int code = -1;
    std::string out, err;
};

std::string slurp(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
}

// Runs `aamap snapshot ARGS` with stdout and stderr captured in files under dir.
CommandResult snapshot(const fs::path& dir, const std::string& args) {
    const char* exe = std::getenv("AAMAP_EXE");
    if (exe == nullptr) throw std::runtime_error("AAMAP_EXE is not set");
    const std::string cmd = fmt::format("\"{}\" snapshot {} > \"{}\" 2> \"{}\"", exe, args, (dir / "stdout").string(),
                                        (dir / "stderr").string());
    const int status = std::system(cmd.c_str());
    CommandResult r;
    r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    r.out = slurp(dir / "stdout");
    r.err = slurp(dir / "stderr");
    return r;
}

class SnapshotCommand : public ::testing::Test {
protected:
    void SetUp() override {
        const char* tmp = std::getenv("AAMAP_E2E_TMP");
        dir_ = fs::path(tmp ? tmp : fs::temp_directory_path().string()) /
               ::testing::UnitTest::GetInstance()->current_test_info()->name();
        fs::remove_all(dir_);
        fs::create_directories(dir_);
    }
    fs::path dir_;
};

TEST_F(SnapshotCommand, WritesImagesExplainAndDot) {
    std::ofstream(dir_ / "lights.yaml") << "- {type: spot, name: stage, position: [0.28, 0.5, 0.28], direction: [0, -1, 0],\n"
                                           "   inner_angle: 20, outer_angle: 35, intensity: [0.2, 0.2, 0.2]}\n"
                                           "- {type: disk, name: lamp, position: [0.1, 0.54, 0.1], normal: [0, -1, 0],\n"
                                           "   radius: 0.03, power: [1, 1, 1]}\n";
    const CommandResult r = snapshot(dir_, fmt::format("builtin:cornell --lights \"{}\" --explain --dot \"{}\" -o \"{}\" "
                                             "--width 64 --height 64 --area-light-samples 2",
                                             (dir_ / "lights.yaml").string(), (dir_ / "graph.dot").string(),
                                             (dir_ / "out").string()));
    ASSERT_EQ(r.code, 0) << r.err;
    for (const char* f : {"snapshot.png", "laplacian.png", "aamap.png", "aamap.exr"})
        EXPECT_TRUE(fs::exists(dir_ / "out" / f)) << f;
    // The scene's own quad light plus the file's disk, each small over the box: one sample each
    // (snapshot.area_light_solid_angle), at most 2; and the spot.
    EXPECT_NE(r.out.find("1 spot, 2 area (2 point samples in all, by solid angle over the view, at most 2 each) -> 3 "
                         "light samples"),
              std::string::npos)
        << r.out;
    EXPECT_NE(r.out.find("shadow pass: 3 cube map(s)"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("at most 2): 'light' 1, 'lamp' 1"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("kept   'shadow': writes 'shadow.cubes' -> read by 'gbuffer'"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("kept   'gbuffer'"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("culled '"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("'stage'"), std::string::npos) << r.out;  // the spot's cube map is named

    const std::string dot = slurp(dir_ / "graph.dot");
    EXPECT_EQ(dot.rfind("digraph render_graph {", 0), 0u) << dot;
    EXPECT_EQ(dot.substr(dot.size() - 2), "}\n");
    EXPECT_NE(dot.find("\"0: shadow\""), std::string::npos) << dot;
    EXPECT_NE(dot.find("(culled)"), std::string::npos) << dot;
    EXPECT_NE(dot.find("style=dashed"), std::string::npos) << dot;
}

TEST_F(SnapshotCommand, BadLightFileNamesFileLineAndColumn) {
    std::ofstream(dir_ / "bad.yaml") << "- {position: [0, 1, 0], intensity: [1, 1, 1]}\n"
                                        "- {type: spot, position: [0, 1, 0], intensity: [1, 1, 1], direction: [0, 0, 0]}\n";
    const CommandResult r = snapshot(dir_, fmt::format("builtin:cornell --lights \"{}\" -o \"{}\"", (dir_ / "bad.yaml").string(),
                                             (dir_ / "out").string()));
    EXPECT_EQ(r.code, 2) << r.err;
    EXPECT_NE(r.err.find(fmt::format("{}:2:70: lights.1.direction: must not be the zero vector", (dir_ / "bad.yaml").string())),
              std::string::npos)
        << r.err;
    EXPECT_FALSE(fs::exists(dir_ / "out"));
}

// Every snapshot key is settable as the config's --set sets it, and through the option generated
// from its declaration; a bad value is refused before any work, naming the option and the key.
TEST_F(SnapshotCommand, SetsEverySnapshotKeyAndRefusesBadValues) {
    const CommandResult ok = snapshot(dir_, fmt::format("builtin:cornell --width 32 --height 32 -o \"{}\" "
                                                        "--set snapshot.blur_radius=2 --set snapshot.map=geometric "
                                                        "--noise-floor 0.05",
                                                        (dir_ / "out").string()));
    EXPECT_EQ(ok.code, 0) << ok.err;
    EXPECT_TRUE(fs::exists(dir_ / "out" / "aamap.png")) << ok.err;

    const CommandResult range = snapshot(dir_, fmt::format("builtin:cornell -o \"{}\" --blur-radius 17", (dir_ / "bad").string()));
    EXPECT_EQ(range.code, 2) << range.err;
    EXPECT_NE(range.err.find("snapshot.blur_radius"), std::string::npos) << range.err;
    const CommandResult unknown = snapshot(dir_, fmt::format("builtin:cornell -o \"{}\" --set snapshot.blur_radios=2", (dir_ / "bad").string()));
    EXPECT_EQ(unknown.code, 2) << unknown.err;
    EXPECT_NE(unknown.err.find("did you mean 'snapshot.blur_radius'"), std::string::npos) << unknown.err;
    EXPECT_FALSE(fs::exists(dir_ / "bad"));
}

}  // namespace
