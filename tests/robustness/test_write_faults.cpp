// A disk that fills up or fails while an output is written: one error naming the file,
// no temporary left, and an existing file under the final name untouched. The failure comes
// from the test hook AAMAP_TEST_WRITE_FAULT (core/atomic_file.h), set by CMakeLists.txt to
// ENOSPC after 4096 bytes; ctest runs each test in its own process, so each starts with 4096.
#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <optional>
#include <random>
#include <sstream>
#include <string>

#include <gtest/gtest.h>
#include <unistd.h>

#include "core/atomic_file.h"
#include "core/error.h"
#include "core/image.h"
#include "core/image_io.h"
#include "tests/common/temp_dir.h"

namespace fs = std::filesystem;
using namespace aamap;

namespace {

constexpr std::size_t kBudget = 4096;

class WriteFaults : public ::testing::Test {
protected:
    void SetUp() override {
        const char* env = std::getenv("AAMAP_TEST_WRITE_FAULT");
        if (!env || std::string(env) != "ENOSPC@4096") GTEST_SKIP() << "run through ctest (sets AAMAP_TEST_WRITE_FAULT)";
        scratch_.emplace();
        dir_ = scratch_->path();
    }
    void TearDown() override { scratch_.reset(); }
    std::vector<std::string> entries() const { return scratch_->entries(); }
    static std::string read(const fs::path& p) {
        std::ifstream in(p, std::ios::binary);
        std::ostringstream s;
        s << in.rdbuf();
        return s.str();
    }
    // Expects `write` to fail with one line naming `file` and ENOSPC.
    template <class F>
    void expectDiskFull(const fs::path& file, F&& write) {
        try {
            write();
            FAIL() << "no error for " << file;
        } catch (const EnvironmentError& e) {
            const std::string what = e.what();
            EXPECT_NE(what.find(file.string() + ": cannot write"), std::string::npos) << what;
            EXPECT_NE(what.find("No space left on device"), std::string::npos) << what;
            EXPECT_EQ(what.find('\n'), std::string::npos) << what;
        }
    }
    std::optional<test::TempDir> scratch_;  // made only when the test runs (SetUp may skip)
    fs::path dir_;
};

// Noise does not compress, so the encoded image is far larger than the budget.
ImageRGB noise(int w, int h) {
    ImageRGB image(w, h);
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    for (glm::vec3& p : image.pixels()) p = {u(rng), u(rng), u(rng)};
    return image;
}

}  // namespace

TEST_F(WriteFaults, WritesWithinTheSpaceLeftSucceed) {
    writeTextAtomically(dir_ / "a.json", std::string(kBudget, 'x'));
    EXPECT_EQ(read(dir_ / "a.json").size(), kBudget);
    expectDiskFull(dir_ / "b.json", [&] { writeTextAtomically(dir_ / "b.json", "y"); });
    EXPECT_EQ(entries(), std::vector<std::string>{"a.json"});
}

TEST_F(WriteFaults, AFullDiskLeavesNoTemporaryAndKeepsTheOldFile) {
    writeTextAtomically(dir_ / "results.json", "{\"old\": true}\n");
    expectDiskFull(dir_ / "results.json", [&] { writeTextAtomically(dir_ / "results.json", std::string(8192, ' ')); });
    EXPECT_EQ(entries(), std::vector<std::string>{"results.json"});
    EXPECT_EQ(read(dir_ / "results.json"), "{\"old\": true}\n");
}

TEST_F(WriteFaults, ExrFailsCleanly) {
    expectDiskFull(dir_ / "image.exr", [&] { writeExr(dir_ / "image.exr", noise(64, 64)); });
    EXPECT_TRUE(entries().empty());
}

TEST_F(WriteFaults, PngFailsCleanly) {
    ImageRGB8 image(64, 64);
    std::mt19937 rng(3);
    for (auto& p : image.pixels()) p = {std::uint8_t(rng()), std::uint8_t(rng()), std::uint8_t(rng())};
    expectDiskFull(dir_ / "image.png", [&] { writePng(dir_ / "image.png", image); });
    EXPECT_TRUE(entries().empty());
}
