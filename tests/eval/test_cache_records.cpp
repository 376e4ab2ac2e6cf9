// The typed records of the render cache: each kind round-trips through its record.json, records
// written before a field existed still read, and the runner reuses entries of earlier runs.
#include <filesystem>
#include <fstream>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "eval/cache_records.h"
#include "eval/config.h"
#include "eval/runner.h"
#include "tests/eval/fake_backend.h"

namespace aamap {
namespace {

namespace fs = std::filesystem;
using Json = nlohmann::ordered_json;

fs::path scratch(const std::string& name) {
    const fs::path dir = fs::path(::testing::TempDir()) / ("cache_records_" + name);
    fs::remove_all(dir);
    fs::create_directories(dir);
    return dir;
}

SnapshotRecord sampleSnapshot() {
    SnapshotRecord s;
    s.key = "00112233aabbccdd";
    s.width = 96;
    s.height = 64;
    s.totalSeconds = 0.015625;
    s.readbackSeconds = 0.0009765625;
    s.setupSeconds = 0.25;
    s.passesGpuMs = {{"geometry_buffer", 1.5}, {"laplacian", 0.125}};
    s.vulkanDevice = "llvmpipe";
    s.machine = {"host", "cpu", 2};
    s.gitRevision = "rev";
    return s;
}

TEST(CacheRecords, SnapshotRecordRoundTripsEveryField) {
    const fs::path dir = scratch("snapshot");
    const SnapshotRecord s = sampleSnapshot();
    writeRecord(dir / "record.json", toJson(s));
    const SnapshotRecord back = readSnapshotRecord(dir / "record.json");
    EXPECT_EQ(back.key, s.key);
    EXPECT_EQ(back.width, s.width);
    EXPECT_EQ(back.height, s.height);
    EXPECT_EQ(back.totalSeconds, s.totalSeconds);
    EXPECT_EQ(back.readbackSeconds, s.readbackSeconds);
    EXPECT_EQ(back.setupSeconds, s.setupSeconds);
    EXPECT_EQ(back.passesGpuMs, s.passesGpuMs);  // in the graph's order
    EXPECT_EQ(back.vulkanDevice, s.vulkanDevice);
    EXPECT_EQ(back.machine.hostname, "host");
    EXPECT_EQ(back.machine.cpuModel, "cpu");
    EXPECT_EQ(back.machine.threads, 2);
    EXPECT_EQ(back.gitRevision, s.gitRevision);
    EXPECT_FALSE(back.cached);
    EXPECT_EQ(toJson(back), toJson(s));
}

TEST(CacheRecords, SnapshotRecordOfAnEarlierFormatReads) {
    Json j = toJson(sampleSnapshot());
    j.erase("setup_s");
    j.erase("cached");
    j["machine"].erase("threads");
    const SnapshotRecord back = snapshotRecordFromJson(j);
    EXPECT_EQ(back.setupSeconds, 0.0);
    EXPECT_EQ(back.machine.threads, 0);
    EXPECT_EQ(back.totalSeconds, 0.015625);
    j.erase("total_s");  // a required field missing is an error, not a zero
    EXPECT_THROW(snapshotRecordFromJson(j), nlohmann::json::exception);
}

TEST(CacheRecords, CachedRenderKeepsTheRecordAndWhatItsKeyHashes) {
    const fs::path dir = scratch("render");
    const ExperimentConfig c = parseConfig("scene: builtin:cornell\nrenders: [{strategy: aamap, rpp: 16}]\n", "exp.yaml");
    CachedRender entry;
    entry.record.name = "aamap16";
    entry.record.scene = "builtin:cornell";
    entry.record.strategy = "aamap";
    entry.record.maxRaysPerPixel = 16;
    entry.record.times.traceRuns = {0.5, 0.25, 0.75};
    entry.record.times.trace = 0.5;
    entry.record.rays = {100, 200, 3};
    entry.record.machine = {"host", "cpu", 2};
    entry.renderConfig = renderKeyObject(c, c.renders[0]);
    writeRecord(dir / "record.json", toJson(entry));
    const CachedRender back = readCachedRender(dir / "record.json");
    EXPECT_EQ(back.record.name, "aamap16");
    EXPECT_EQ(back.record.times.traceRuns, entry.record.times.traceRuns);
    EXPECT_EQ(back.record.rays.total(), 303u);
    EXPECT_EQ(back.renderConfig, entry.renderConfig);
    EXPECT_EQ(fnv1a64Hex(back.renderConfig.dump()), renderKey(c, c.renders[0]));
}

TEST(CacheRecords, PixelFactsRecordRoundTrips) {
    const fs::path dir = scratch("facts");
    writeRecord(dir / "record.json", toJson(PixelFactsRecord{"facts-0123", 1.25}));
    const PixelFactsRecord back = readPixelFactsRecord(dir / "record.json");
    EXPECT_EQ(back.key, "facts-0123");
    EXPECT_EQ(back.seconds, 1.25);
}

TEST(CacheRecords, DamagedOrMissingFilesThrow) {
    const fs::path dir = scratch("damaged");
    EXPECT_ANY_THROW(readCachedRender(dir / "absent.json"));
    std::ofstream(dir / "truncated.json") << R"({"name": "uniform1", "scene": )";
    EXPECT_ANY_THROW(readCachedRender(dir / "truncated.json"));
    std::ofstream(dir / "wrong.json") << R"({"name": 3})";
    EXPECT_ANY_THROW(readSnapshotRecord(dir / "wrong.json"));
}

TEST(RenderKeyObject, IsWhatTheKeyHashes) {
    const ExperimentConfig c = parseConfig(R"(scene: builtin:cornell
snapshot: {blur_radius: 3}
renders:
  - {strategy: uniform, rpp: 4}
  - {strategy: aamap-subsample, rpp: 16, spacing: 8}
)",
                                           "exp.yaml");
    for (const RenderConfig& r : c.renders) {
        const Json key = renderKeyObject(c, r);
        EXPECT_EQ(key.dump(), renderKeyJson(c, r)) << r.name;
        EXPECT_EQ(fnv1a64Hex(key.dump()), renderKey(c, r)) << r.name;
        EXPECT_EQ(key["strategy"], r.strategy);
        EXPECT_EQ(key["rpp"], r.rpp);
    }
    // Only a render driven by the aamap depends on the Snapshot's settings.
    EXPECT_FALSE(renderKeyObject(c, c.renders[0]).contains("snapshot"));
    // The key holds the Snapshot's settings that are not at their default; the records all of them.
    EXPECT_EQ(renderKeyObject(c, c.renders[1])["snapshot"], Json({{"blur_radius", 3}}));
    EXPECT_EQ(snapshotSettingsJson(c)["blur_radius"], 3);
    EXPECT_EQ(renderKeyObject(c, c.renders[1])["params"]["spacing"], 8.0);
}

TEST(RenderKeyObject, SnapshotSettingsAreTheCanonicalSection) {
    const ExperimentConfig c = parseConfig("scene: builtin:cornell\nsnapshot: {noise_floor: 0.125}\n"
                                           "renders: [{strategy: aamap, rpp: 4}]\n",
                                           "exp.yaml");
    EXPECT_EQ(snapshotSettingsJson(c), Json::parse(c.canonicalJson())["snapshot"]);
    EXPECT_EQ(snapshotSettingsJson(c)["noise_floor"], 0.125);
}

// The runner's records in results.json are the cache's records: the Snapshot's costs reach every
// aamap-driven render, and a second run reads them back from the typed files.
class CacheEntriesOfEarlierRuns : public ::testing::Test {
protected:
    void SetUp() override {
        out_ = fs::path(::testing::TempDir()) /
               ("cache_entries_" + std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()));
        fs::remove_all(out_);
    }
    Results run(FakeBackend& backend, const std::vector<std::string>& overrides = {}) {
        const ExperimentConfig c = parseConfig(R"(scene: builtin:cornell
image: {width: 32, height: 24}
renders:
  - {strategy: uniform, rpp: [1, 4]}
  - {strategy: aamap, rpp: 4}
report: {plots: false}
)",
                                               "exp.yaml", overrides);
        return runExperimentWith(c, out_, backend, RunnerOptions{"test-rev", false});
    }
    fs::path out_;
};

TEST_F(CacheEntriesOfEarlierRuns, SnapshotCostsReachTheAamapRendersOnlyAndSurviveTheCache) {
    FakeBackend first;
    const Results r1 = run(first);
    ASSERT_TRUE(r1.snapshot);
    EXPECT_FALSE(r1.snapshot->cached);
    const RenderRecord& selective = r1.renders[2];
    EXPECT_EQ(selective.times.snapshotTotal, r1.snapshot->totalSeconds);
    EXPECT_EQ(selective.times.snapshotSetup, r1.snapshot->setupSeconds);
    EXPECT_EQ(selective.times.snapshotPassesGpuMs, r1.snapshot->passesGpuMs);
    EXPECT_EQ(selective.parameters["snapshot_key"], r1.snapshot->key);
    EXPECT_EQ(r1.renders[0].times.snapshotTotal, 0.0);
    EXPECT_EQ(r1.renders[0].vulkanDevice, "");

    // The cache entry holds what its key hashes.
    const CachedRender entry = readCachedRender(out_ / "cache" / selective.key / "record.json");
    EXPECT_EQ(fnv1a64Hex(entry.renderConfig.dump()), selective.key);

    FakeBackend second;
    const Results r2 = run(second);
    EXPECT_EQ(second.snapshots, 0);
    ASSERT_TRUE(r2.snapshot);
    EXPECT_TRUE(r2.snapshot->cached);
    EXPECT_EQ(r2.snapshot->totalSeconds, r1.snapshot->totalSeconds);
    EXPECT_EQ(r2.renders[2].times.snapshotTotal, r1.renders[2].times.snapshotTotal);
}

TEST_F(CacheEntriesOfEarlierRuns, RecordsWithoutNewerFieldsAreReusedAndRepeatsAddOnlyMissingRuns) {
    FakeBackend first;
    const Results r1 = run(first);
    // Rewrite the entries as an earlier version wrote them: no setup_s, no threads, no trace_runs.
    const fs::path snap = out_ / "cache" / r1.snapshot->key / "record.json";
    Json s = toJson(*r1.snapshot);
    s.erase("setup_s");
    s.erase("cached");
    s["machine"].erase("threads");
    writeRecord(snap, s);
    const fs::path render = out_ / "cache" / r1.renders[1].key / "record.json";
    Json rj = toJson(readCachedRender(render));
    rj["times_s"].erase("trace_runs");
    writeRecord(render, rj);

    FakeBackend second;
    const Results r2 = run(second, {"timing.repeats=2"});
    EXPECT_EQ(second.snapshots, 0);
    EXPECT_EQ(r2.snapshot->setupSeconds, 0.0);
    // Every entry had one run; each traces once more, and the cache keeps both runs.
    EXPECT_EQ(second.totalTraces(), first.totalTraces());
    for (const RenderRecord& r : r2.renders) EXPECT_EQ(r.times.traceRuns.size(), 2u) << r.name;
    EXPECT_EQ(readCachedRender(render).record.times.traceRuns.size(), 2u);
    EXPECT_EQ(fnv1a64Hex(readCachedRender(render).renderConfig.dump()), r1.renders[1].key);

    FakeBackend third;
    run(third, {"timing.repeats=2"});
    EXPECT_EQ(third.totalTraces(), 0);
}

TEST_F(CacheEntriesOfEarlierRuns, ADamagedSnapshotEntryIsRenderedAgain) {
    FakeBackend first;
    const Results r1 = run(first);
    std::ofstream(out_ / "cache" / r1.snapshot->key / "record.json", std::ios::trunc) << R"({"key": )";
    FakeBackend second;
    const Results r2 = run(second);
    EXPECT_EQ(second.snapshots, 1);
    EXPECT_FALSE(r2.snapshot->cached);
    EXPECT_EQ(second.totalTraces(), 0);  // the renders' entries are intact
    EXPECT_EQ(readSnapshotRecord(out_ / "cache" / r1.snapshot->key / "record.json").key, r1.snapshot->key);
}

}  // namespace
}  // namespace aamap
