// What the runner records for the sampling strategies, with a fake backend: the traced mask of
// subsampling strategies (the paper's Figure 5), where the block sums came from, the hybrid
// strategy's parameters, and the snapshot.map key.
#include <filesystem>
#include <fstream>
#include <iterator>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "core/error.h"
#include "core/image_io.h"
#include "eval/config.h"
#include "eval/runner.h"

namespace aamap {
namespace {

namespace fs = std::filesystem;

// Interpolated pixels (every odd column) carry no primary ray, as aamap-subsample's do.
class SubsamplingBackend : public RenderBackend {
public:
    static constexpr int kW = 16, kH = 8;
    SceneInfo prepare() override { return {kW, kH, "fake:scene", "fake view", 0.0, 0.0}; }
    SnapshotOutput snapshot() override {
        SnapshotOutput s;
        s.aamap = ImageGrey(kW, kH, 0.5f);
        s.device = "fake GPU";
        return s;
    }
    TraceOutput trace(const RenderConfig& r, const ImageGrey*, const std::function<void(int, int)>&) override {
        TraceOutput t;
        t.image = ImageRGB(kW, kH, glm::vec3(0.25f));
        t.primaryRays = Image<std::uint16_t>(kW, kH, 1);
        const bool subsampled = r.strategy == "aamap-subsample";
        std::uint64_t rays = 0;
        for (int y = 0; y < kH; ++y)
            for (int x = 0; x < kW; ++x) {
                t.primaryRays.at(x, y) = subsampled && x % 2 == 1 ? 0 : 1;
                rays += t.primaryRays.at(x, y);
            }
        t.rays = {rays, 0, 0};
        if (subsampled) t.blockSums = "gpu";
        return t;
    }
};

const char* const kCombinedMapConfig = R"(scene: builtin:cornell
image: {width: 16, height: 8}
snapshot: {map: combined}
renders:
  - {strategy: aamap-subsample, rpp: 4, spacing: 4}
  - {name: hybrid, strategy: hybrid, rpp: 4, noise_threshold: 0.02, sample_step: 3}
reference: {type: none}
metrics: {map_quality: false}
report: {plots: false}
)";

TEST(StrategyOutputs, TracedMaskBlockSumSourceAndHybridParameters) {
    const fs::path out = fs::path(::testing::TempDir()) / "strategy_outputs";
    fs::remove_all(out);
    const ExperimentConfig c = parseConfig(kCombinedMapConfig, "exp.yaml", {});
    EXPECT_EQ(c.snapshot.map, passes::AamapSource::Combined);
    SubsamplingBackend backend;
    runExperimentWith(c, out, backend, RunnerOptions{"test-rev", false});

    std::ifstream in(out / "results.json");
    const nlohmann::json results = nlohmann::json::parse(in);
    const nlohmann::json& subsample = results["renders"][0];
    const nlohmann::json& hybrid = results["renders"][1];
    EXPECT_EQ(subsample["parameters"]["block_sums"], "gpu");
    EXPECT_FALSE(hybrid["parameters"].contains("block_sums"));
    EXPECT_EQ(hybrid["strategy"], "hybrid");
    EXPECT_DOUBLE_EQ(hybrid["parameters"]["noise_threshold"].get<double>(), 0.02);
    EXPECT_TRUE(hybrid["parameters"]["sample_step"].is_number_integer());  // an integer stays one in the record
    EXPECT_EQ(hybrid["parameters"]["sample_step"].get<int>(), 3);
    std::ifstream csvIn(out / "results.csv");
    const std::string csv((std::istreambuf_iterator<char>(csvIn)), std::istreambuf_iterator<char>());
    EXPECT_NE(csv.find("sample_step=3"), std::string::npos) << csv;
    EXPECT_EQ(csv.find("sample_step=3.0"), std::string::npos) << csv;
    EXPECT_EQ(hybrid["parameters"]["mapping"], "paper");
    EXPECT_EQ(subsample["rays"]["primary"].get<std::uint64_t>(), 64u);  // what the backend traced
    EXPECT_EQ(subsample["parameters"]["snapshot"]["map"], "combined");

    // The mask: white where traced, black where interpolated; only for subsampling strategies.
    const std::string name = subsample["name"].get<std::string>();
    ASSERT_TRUE(fs::exists(out / (name + ".traced.png")));
    const ImageRGB8 mask = readPng(out / (name + ".traced.png"));
    for (int x = 0; x < SubsamplingBackend::kW; ++x) EXPECT_EQ(mask.at(x, 3).r, x % 2 == 1 ? 0 : 255) << x;
    const auto& outputs = subsample["outputs"];
    EXPECT_NE(std::find(outputs.begin(), outputs.end(), name + ".traced.png"), outputs.end());
    EXPECT_FALSE(fs::exists(out / (hybrid["name"].get<std::string>() + ".traced.png")));
}

TEST(StrategyOutputs, SnapshotMapIsCheckedAndKeysOfLuminanceRunsAreUnchanged) {
    const ExperimentConfig plain = parseConfig("scene: builtin:cornell\nrenders: [{strategy: aamap, rpp: 4}]\n",
                                               "a.yaml", {});
    const ExperimentConfig luminance = parseConfig(
        "scene: builtin:cornell\nsnapshot: {map: luminance}\nrenders: [{strategy: aamap, rpp: 4}]\n", "a.yaml", {});
    const ExperimentConfig geometric = parseConfig(
        "scene: builtin:cornell\nsnapshot: {map: geometric}\nrenders: [{strategy: aamap, rpp: 4}]\n", "a.yaml", {});
    EXPECT_EQ(snapshotKey(plain), snapshotKey(luminance));
    EXPECT_NE(snapshotKey(plain), snapshotKey(geometric));
    try {
        parseConfig("scene: builtin:cornell\nsnapshot: {map: depth}\nrenders: [{strategy: aamap, rpp: 4}]\n", "b.yaml",
                    {});
        FAIL() << "snapshot.map: depth was accepted";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("b.yaml:2"), std::string::npos) << e.what();
    }
}

}  // namespace
}  // namespace aamap
