// The work an executor spreads over machines (eval/runner.h WorkItem): what --list-work lists,
// what --only computes, and that a run after every item was computed elsewhere traces nothing and
// gives the same images. Plus the warning for speedups whose times come from different machines.
#include <algorithm>
#include <filesystem>
#include <fstream>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "core/error.h"
#include "eval/config.h"
#include "eval/runner.h"
#include "eval/timing_machines.h"
#include "tests/eval/fake_backend.h"

namespace aamap {
namespace {

namespace fs = std::filesystem;

const char* const kWorkItemsConfig = R"(scene: builtin:cornell
image: {width: 48, height: 32}
threads: 2
renders:
  - {strategy: uniform, rpp: [1, 4, 16], series: Standard}
  - {strategy: aamap, rpp: [4, 16], series: Selective}
report: {plots: false}
)";

class WorkItems : public ::testing::Test {
protected:
    void SetUp() override {
        dir_ = fs::path(::testing::TempDir()) /
               ("work_items_" + std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()));
        fs::remove_all(dir_);
    }
    fs::path dir_;
};

TEST_F(WorkItems, ListsTheSnapshotFirstThenEachMissingKeyOnce) {
    const ExperimentConfig c = parseConfig(kWorkItemsConfig, "exp.yaml");
    const std::vector<WorkItem> items = missingWork(c, dir_ / "cache", -1);
    // 5 listed renders; the reference (uniform 16) and the 1-ray probe (uniform 1) share their keys.
    ASSERT_EQ(items.size(), 6u);
    EXPECT_EQ(items[0].kind, "snapshot");
    EXPECT_EQ(items[0].key, snapshotKey(c));
    for (std::size_t i = 1; i < items.size(); ++i) {
        EXPECT_EQ(items[i].kind, "render");
        EXPECT_EQ(items[i].threads, 2);
        EXPECT_EQ(items[i].needsSnapshot, items[i].name.starts_with("aamap") ? snapshotKey(c) : "") << items[i].name;
        EXPECT_TRUE(items[i].group.empty());  // timing.same_machine is off
        for (std::size_t j = 0; j < i; ++j) EXPECT_NE(items[i].key, items[j].key);
    }
    EXPECT_EQ(missingWork(c, dir_ / "cache", 0)[1].threads, 0);  // --threads overrides the config
}

TEST_F(WorkItems, ItemsComputedOneByOneLeaveNothingToTraceAndTheSameImages) {
    const ExperimentConfig c = parseConfig(kWorkItemsConfig, "exp.yaml");
    const fs::path shared = dir_ / "distributed" / "cache";
    FakeBackend workers;
    for (const WorkItem& w : missingWork(c, shared, -1)) {
        FakeBackend worker;  // each item in a process of its own
        computeWorkItem(c, w.key, worker, RunnerOptions{"test-rev", false, shared});
        EXPECT_EQ(worker.totalTraces() + worker.snapshots, 1) << w.name;
    }
    EXPECT_TRUE(missingWork(c, shared, -1).empty());
    for (const auto& e : fs::directory_iterator(shared))  // no folder besides the entries
        EXPECT_EQ(e.path().filename().string().find(".tmp-"), std::string::npos) << e.path();

    FakeBackend driver;
    const Results distributed = runExperimentWith(c, dir_ / "distributed", driver, RunnerOptions{"test-rev", false});
    EXPECT_EQ(driver.totalTraces(), 0);
    EXPECT_EQ(driver.snapshots, 0);
    FakeBackend local;
    const Results plain = runExperimentWith(c, dir_ / "local", local, RunnerOptions{"test-rev", false});
    ASSERT_EQ(distributed.renders.size(), plain.renders.size());
    for (std::size_t i = 0; i < plain.renders.size(); ++i) {
        EXPECT_EQ(distributed.renders[i].key, plain.renders[i].key);
        EXPECT_EQ(distributed.renders[i].metrics.dump(), plain.renders[i].metrics.dump()) << plain.renders[i].name;
    }
}

TEST_F(WorkItems, OnlyRefusesAnUnknownKeyAndAMapRenderWithoutItsSnapshot) {
    const ExperimentConfig c = parseConfig(kWorkItemsConfig, "exp.yaml");
    const RunnerOptions options{"test-rev", false, dir_ / "cache"};
    FakeBackend backend;
    EXPECT_THROW(computeWorkItem(c, "0123456789abcdef", backend, options), InputError);
    const std::vector<WorkItem> items = missingWork(c, dir_ / "cache", -1);
    const auto mapped = std::find_if(items.begin(), items.end(), [](const WorkItem& w) { return !w.needsSnapshot.empty(); });
    ASSERT_NE(mapped, items.end());
    EXPECT_THROW(computeWorkItem(c, mapped->key, backend, options), EnvironmentError);
    EXPECT_EQ(backend.totalTraces(), 0);
    EXPECT_FALSE(fs::exists(dir_ / "cache" / mapped->key));
}

TEST_F(WorkItems, SameMachineGroupsTheRendersOfOneRpp) {
    const ExperimentConfig c = parseConfig(kWorkItemsConfig, "exp.yaml", {"timing.same_machine=true"});
    EXPECT_NE(c.hash(), parseConfig(kWorkItemsConfig, "exp.yaml").hash());
    EXPECT_EQ(parseConfig(kWorkItemsConfig, "exp.yaml", {"timing.same_machine=false"}).hash(),
              parseConfig(kWorkItemsConfig, "exp.yaml").hash());  // the default keeps old configs' hashes
    std::map<std::string, std::vector<std::string>> groups;
    for (const WorkItem& w : missingWork(c, dir_ / "cache", -1))
        if (w.kind == "render") groups[w.group].push_back(w.name);
    ASSERT_EQ(groups.size(), 3u);  // rpp 1, 4, 16
    for (const auto& [group, names] : groups) {
        EXPECT_FALSE(group.empty());
        EXPECT_EQ(names.size(), names.front() == "uniform1" ? 1u : 2u) << group;
    }
}

// The records of a distributed run keep each worker's machine; the run's warnings say when a
// speedup mixes two of them.
TEST_F(WorkItems, ARunWhoseRendersCameFromTwoMachinesWarns) {
    const ExperimentConfig c = parseConfig(kWorkItemsConfig, "exp.yaml");
    FakeBackend first;
    const Results one = runExperimentWith(c, dir_, first, RunnerOptions{"test-rev", false});
    for (const std::string& w : one.warnings) EXPECT_EQ(w.find("different machines"), std::string::npos) << w;
    const auto aamap4 = std::find_if(one.renders.begin(), one.renders.end(), [](const RenderRecord& r) { return r.name == "aamap4"; });
    ASSERT_NE(aamap4, one.renders.end());
    const fs::path record = dir_ / "cache" / aamap4->key / "record.json";
    nlohmann::ordered_json j = nlohmann::ordered_json::parse(std::ifstream(record));
    j["machine"]["hostname"] = "another-worker";  // as a worker elsewhere would have written it
    std::ofstream(record) << j.dump(2);
    FakeBackend second;
    const Results two = runExperimentWith(c, dir_, second, RunnerOptions{"test-rev", false});
    EXPECT_EQ(second.totalTraces(), 0);
    const auto warned = std::find_if(two.warnings.begin(), two.warnings.end(), [](const std::string& w) {
        return w.find("rpp 4 divide times traced on different machines") != std::string::npos &&
               w.find("another-worker") != std::string::npos;
    });
    EXPECT_NE(warned, two.warnings.end());
}

RenderRecord record(const std::string& name, const std::string& series, const std::string& strategy, int rpp,
                    const std::string& host) {
    RenderRecord r;
    r.name = name;
    r.series = series;
    r.strategy = strategy;
    r.maxRaysPerPixel = rpp;
    r.machine = {host, "Some CPU", 8};
    return r;
}

TEST(TimingMachines, WarnsOnlyWhenASpeedupDividesTimesFromTwoMachines) {
    Results results;
    results.renders = {record("u4", "Standard", "uniform", 4, "a"), record("s4", "Selective", "aamap", 4, "a"),
                       record("u16", "Standard", "uniform", 16, "a"), record("s16", "Selective", "aamap", 16, "a")};
    EXPECT_TRUE(mixedMachineWarnings(results).empty());
    results.renders[3].machine.hostname = "b";
    const std::vector<std::string> w = mixedMachineWarnings(results);
    ASSERT_EQ(w.size(), 1u);
    EXPECT_NE(w[0].find("rpp 16"), std::string::npos) << w[0];
    EXPECT_EQ(w[0].find("rpp 4,"), std::string::npos) << w[0];
    EXPECT_NE(w[0].find("b (Some CPU)"), std::string::npos) << w[0];
    results.renders[3].machine.hostname = "a";
    results.renders[3].machine.cpuModel = "Another CPU";  // one host name, another machine
    EXPECT_EQ(mixedMachineWarnings(results).size(), 1u);
}

// --plan's view of a run: nothing cached before it (and the cache folder not created by asking),
// everything cached after it, with the rate of the cached renders estimating a new render's time.
TEST_F(WorkItems, PlanReadsTheCacheOnly) {
    const ExperimentConfig c = parseConfig(kWorkItemsConfig, "exp.yaml");
    const RunPlan before = planRun(c, dir_ / "out" / "cache");
    EXPECT_FALSE(fs::exists(dir_ / "out"));
    ASSERT_EQ(before.renders.size(), 7u);  // 5 listed, the reference, the 1-ray probe
    EXPECT_TRUE(before.usesSnapshot);
    EXPECT_FALSE(before.snapshotCached);
    for (const PlannedRender& r : before.renders) {
        EXPECT_FALSE(r.cached) << r.name;
        EXPECT_FALSE(r.seconds.has_value()) << r.name;  // no rate to go by yet
    }
    EXPECT_FALSE(before.secondsPerRayUnit.has_value());

    FakeBackend backend;
    runExperimentWith(c, dir_ / "out", backend, RunnerOptions{"test-rev", false});
    const RunPlan after = planRun(c, dir_ / "out" / "cache");
    EXPECT_TRUE(after.snapshotCached);
    for (const PlannedRender& r : after.renders) {
        EXPECT_TRUE(r.cached) << r.name;
        ASSERT_TRUE(r.seconds.has_value()) << r.name;
    }
    ASSERT_TRUE(after.secondsPerRayUnit.has_value());
    // The fake backend takes 1 ms per rpp: the rate is that over the pixels.
    EXPECT_NEAR(*after.secondsPerRayUnit * FakeBackend::kW * FakeBackend::kH, 0.001, 1e-9);
    const RunPlan bigger = planRun(parseConfig(kWorkItemsConfig, "exp.yaml", {"renders.0.rpp=[1, 4, 36]"}), dir_ / "out" / "cache");
    ASSERT_EQ(bigger.renders[2].name, "uniform36");
    EXPECT_FALSE(bigger.renders[2].cached);
    ASSERT_TRUE(bigger.renders[2].seconds.has_value());
    EXPECT_NEAR(*bigger.renders[2].seconds, *after.secondsPerRayUnit * 36 * 48 * 32, 1e-9);
}

}  // namespace
}  // namespace aamap
