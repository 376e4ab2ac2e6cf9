// results.json: every required field, written atomically and readable back.
#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "eval/results.h"

namespace aamap {
namespace {

TEST(Results, RecordHasEveryField) {
    RenderRecord r;
    r.name = "selective";
    r.strategy = "aamap";
    r.parameters = {{"strata", 6}};
    r.maxRaysPerPixel = 36;
    r.times.snapshotPassesGpuMs = {{"gbuffer", 0.5}, {"laplacian", 0.25}};
    r.rays = {10, 20, 3};
    const nlohmann::ordered_json j = toJson(r);
    for (const char* key : {"name", "scene", "view", "width", "height", "strategy", "parameters", "max_rays_per_pixel",
                            "times_s", "rays", "mean_primary_rpp", "non_finite_samples", "git_revision",
                            "config_hash", "vulkan_device", "machine"})
        EXPECT_TRUE(j.contains(key)) << key;
    for (const char* key : {"load", "bvh_build", "snapshot_setup", "snapshot_total", "snapshot_passes_gpu_ms",
                            "readback", "trace", "total"})
        EXPECT_TRUE(j["times_s"].contains(key)) << key;
    EXPECT_EQ(j["times_s"]["snapshot_passes_gpu_ms"]["laplacian"], 0.25);
    EXPECT_EQ(j["rays"]["total"], 33);
    for (const char* key : {"hostname", "cpu_model", "threads"}) EXPECT_TRUE(j["machine"].contains(key)) << key;
}

TEST(Results, SnapshotSetupRoundTripsAndOlderRecordsReadAsZero) {
    RenderRecord r;
    r.times.snapshotSetup = 0.125;
    r.times.snapshotTotal = 0.03125;
    nlohmann::ordered_json j = toJson(r);
    EXPECT_EQ(recordFromJson(j).times.snapshotSetup, 0.125);
    EXPECT_EQ(recordFromJson(j).times.snapshotTotal, 0.03125);
    j["times_s"].erase("snapshot_setup");  // a cached record from before the field existed
    EXPECT_EQ(recordFromJson(j).times.snapshotSetup, 0.0);
}

TEST(Results, WrittenPrettyAndAtomically) {
    const std::filesystem::path dir = std::filesystem::path(::testing::TempDir()) / "aamap_results";
    std::filesystem::remove_all(dir);
    std::filesystem::create_directories(dir);
    Results results;
    results.configHash = "0123456789abcdef";
    results.configJson = R"({"scene":"builtin:cornell"})";
    results.renders.resize(2);
    writeResults(dir / "results.json", results);
    std::ifstream in(dir / "results.json");
    const nlohmann::json j = nlohmann::json::parse(in);
    EXPECT_EQ(j["renders"].size(), 2u);
    EXPECT_EQ(j["config"]["scene"], "builtin:cornell");
    EXPECT_EQ(std::distance(std::filesystem::directory_iterator(dir), {}), 1);
    std::filesystem::remove_all(dir);
}

TEST(Results, MachineIsDescribed) {
    const MachineInfo m = currentMachine();
    EXPECT_FALSE(m.hostname.empty());
    EXPECT_FALSE(m.cpuModel.empty());
    EXPECT_GT(m.threads, 0);
}

}  // namespace
}  // namespace aamap
