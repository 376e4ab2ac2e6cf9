// The runner's checks before and around the work: a file reference is read and sized before
// anything is traced (a bad one leaves no output folder), and what makes figures meaningless is a
// warning at the top of the results (a reference with fewer rays, a black reference, a scene that
// the backend found lacking).
#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include <gtest/gtest.h>

#include "core/error.h"
#include "core/image_io.h"
#include "eval/config.h"
#include "eval/runner.h"
#include "tests/eval/fake_backend.h"

namespace aamap {
namespace {

namespace fs = std::filesystem;

std::string readText(const fs::path& file) {
    std::ifstream in(file);
    return std::string(std::istreambuf_iterator<char>(in), {});
}

class RunnerChecks : public ::testing::Test {
protected:
    void SetUp() override {
        dir_ = fs::path(::testing::TempDir()) /
               ("runner_checks_" + std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()));
        fs::remove_all(dir_);
        fs::create_directories(dir_);
        out_ = dir_ / "out";
    }
    Results run(FakeBackend& backend, const std::string& extra) {
        const std::string yaml = "scene: builtin:cornell\nimage: {width: 48, height: 32}\n"
                                 "renders:\n  - {strategy: uniform, rpp: [1, 16]}\n  - {strategy: aamap, rpp: 16}\n"
                                 "report: {plots: false}\n" + extra;
        const ExperimentConfig c = parseConfig(yaml, (dir_ / "exp.yaml").string(), {});
        return runExperimentWith(c, out_, backend, RunnerOptions{"test-rev", false});
    }
    static bool hasWarning(const Results& r, const std::string& part) {
        return std::any_of(r.warnings.begin(), r.warnings.end(),
                           [&](const std::string& w) { return w.find(part) != std::string::npos; });
    }
    fs::path dir_, out_;
};

TEST_F(RunnerChecks, MissingReferenceFileFailsBeforeAnyWorkAndLeavesNoFolder) {
    FakeBackend backend;
    try {
        run(backend, "reference: {type: file, path: missing.exr}\n");
        FAIL() << "expected an InputError";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("missing.exr"), std::string::npos) << e.what();
        EXPECT_GT(e.line(), 0);  // points at the config's reference.path
    }
    EXPECT_EQ(backend.snapshots, 0);
    EXPECT_EQ(backend.totalTraces(), 0);
    EXPECT_FALSE(fs::exists(out_));
}

TEST_F(RunnerChecks, ReferenceOfTheWrongSizeFailsBeforeAnyWork) {
    writeExr(dir_ / "small.exr", ImageRGB(16, 16, glm::vec3(0.5f)));
    FakeBackend backend;
    try {
        run(backend, "reference: {type: file, path: small.exr}\n");
        FAIL() << "expected an InputError";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("16x16"), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("48x32"), std::string::npos) << e.what();
    }
    EXPECT_EQ(backend.snapshots, 0);
    EXPECT_EQ(backend.totalTraces(), 0);
    EXPECT_FALSE(fs::exists(out_));
    // When the size is known without the scene, the scene is not even loaded first.
    FakeBackend known;
    known.sizeKnown = true;
    EXPECT_THROW(run(known, "reference: {type: file, path: small.exr}\n"), InputError);
    EXPECT_EQ(known.prepares, 0);
}

TEST_F(RunnerChecks, BlackReferenceIsAWarning) {
    writeExr(dir_ / "black.exr", ImageRGB(FakeBackend::kW, FakeBackend::kH, glm::vec3(0.0f)));
    FakeBackend backend;
    const Results r = run(backend, "reference: {type: file, path: black.exr}\n");
    EXPECT_TRUE(hasWarning(r, "black everywhere"));
}

TEST_F(RunnerChecks, ReferenceWithFewerRaysThanARenderIsAWarning) {
    FakeBackend backend;
    const Results fewer = run(backend, "reference: {rpp: 4}\n");
    EXPECT_TRUE(hasWarning(fewer, "fewer than render"));
    fs::remove_all(out_);
    const Results enough = run(backend, "");  // the default: the largest rpp of the renders
    EXPECT_FALSE(hasWarning(enough, "fewer than render"));
}

TEST_F(RunnerChecks, SceneWarningsReachTheResults) {
    FakeBackend backend;
    backend.sceneWarnings = {"scene 'fake' has no lights: ..."};
    const Results r = run(backend, "");
    ASSERT_FALSE(r.warnings.empty());
    EXPECT_EQ(r.warnings.front(), backend.sceneWarnings.front());  // first: it explains the rest
}

// timing.repeats: every distinct render is timed `repeats` times, round by round when
// interleaved; the record keeps every run and its median; a rerun asking for more runs traces
// only the runs the cache lacks.
TEST_F(RunnerChecks, RepeatedTimingsInterleaveAndResume) {
    FakeBackend backend;
    const Results r = run(backend, "timing: {repeats: 3}\nmetrics: {map_quality: false}\n");
    // Distinct keys: uniform1, uniform16 (also the reference), aamap16.
    const std::vector<std::string> round = {"uniform1", "uniform16", "aamap16"};
    std::vector<std::string> expected;
    for (int i = 0; i < 3; ++i) expected.insert(expected.end(), round.begin(), round.end());
    EXPECT_EQ(backend.order, expected);
    for (const RenderRecord& rec : r.renders) {
        ASSERT_EQ(rec.times.traceRuns.size(), 3u) << rec.name;
        std::vector<double> runs = rec.times.traceRuns;
        std::sort(runs.begin(), runs.end());
        EXPECT_EQ(rec.times.trace, runs[1]) << rec.name;
    }
    ASSERT_TRUE(r.reference.has_value());
    EXPECT_EQ(r.reference->times.traceRuns.size(), 3u);

    FakeBackend more;
    const Results again = run(more, "timing: {repeats: 4}\nmetrics: {map_quality: false}\n");
    EXPECT_EQ(more.order, round);  // one more run each, nothing traced from scratch
    for (const RenderRecord& rec : again.renders) EXPECT_EQ(rec.times.traceRuns.size(), 4u) << rec.name;
}

TEST_F(RunnerChecks, RepeatedTimingsWithoutInterleaving) {
    FakeBackend backend;
    run(backend, "timing: {repeats: 2, interleave: false}\nmetrics: {map_quality: false}\n");
    const std::vector<std::string> expected = {"uniform1", "uniform16", "aamap16",  // the first pass
                                               "uniform1", "uniform16", "aamap16"};
    EXPECT_EQ(backend.order, expected);  // with 2 runs each, one more per render in turn
    FakeBackend three;
    fs::remove_all(out_);
    run(three, "timing: {repeats: 3, interleave: false}\nmetrics: {map_quality: false}\n");
    const std::vector<std::string> blocked = {"uniform1", "uniform16", "aamap16", "uniform1", "uniform1",
                                              "uniform16", "uniform16", "aamap16", "aamap16"};
    EXPECT_EQ(three.order, blocked);
}

// A traced reference carries its own convergence (two half images of its samples): a noisy one
// is a warning at the top, and the report leaves its error pixels out; a converged one is not.
TEST_F(RunnerChecks, NoisyReferenceIsAWarningAndItsErrorPixelsAreLeftOut) {
    FakeBackend backend;
    backend.halfNoise = 2.0f;  // the reference's halves differ by 0.5: far above FLIP's threshold
    const Results r = run(backend, "metrics: {map_quality: false}\n");
    EXPECT_TRUE(hasWarning(r, "is noisy")) << (r.warnings.empty() ? "" : r.warnings.front());
    ASSERT_TRUE(r.referenceInfo.noise.has_value());
    const auto& n = *r.referenceInfo.noise;
    EXPECT_TRUE(n["noisy"].get<bool>());
    EXPECT_FALSE(n["converged"].get<bool>());
    EXPECT_GT(n["floor_pct"].get<double>(), 50.0);  // every other pixel at least
    ASSERT_TRUE(n["suggested_rpp"].is_number());
    EXPECT_GT(n["suggested_rpp"].get<int>(), 16);
    const std::string md = readText(out_ / "report.md");
    EXPECT_NE(md.find("not reported: the reference is noisy"), std::string::npos);
    EXPECT_NE(md.find("## The reference"), std::string::npos);
    EXPECT_NE(readText(out_ / "report.html").find("is noisy"), std::string::npos);  // the problems box

    FakeBackend clean;
    clean.halfNoise = 0.0f;
    fs::remove_all(out_);
    const Results ok = run(clean, "metrics: {map_quality: false}\n");
    EXPECT_FALSE(hasWarning(ok, "noisy"));
    ASSERT_TRUE(ok.referenceInfo.noise.has_value());
    EXPECT_TRUE((*ok.referenceInfo.noise)["converged"].get<bool>());
    EXPECT_EQ((*ok.referenceInfo.noise)["suggested_rpp"].get<int>(), 16);
    EXPECT_EQ(readText(out_ / "report.md").find("not reported"), std::string::npos);
}

// report.md carries what the HTML's Snapshot card says: its cost per frame, on which device.
TEST_F(RunnerChecks, MarkdownReportHasTheSnapshotCost) {
    FakeBackend backend;
    run(backend, "metrics: {map_quality: false}\n");
    const std::string md = readText(out_ / "report.md");
    EXPECT_NE(md.find("## Snapshot cost"), std::string::npos) << md;
    EXPECT_NE(md.find("| per frame (ms) | 5 |"), std::string::npos) << md;  // the fake's 5 ms
    EXPECT_NE(md.find("on fake GPU"), std::string::npos) << md;
}

// The oracle's renders are timed in the same rounds as the renders they are compared with: the
// repeated runs wait until the oracle's first runs are done.
TEST_F(RunnerChecks, OracleRendersAreTimedInTheSameRounds) {
    FakeBackend backend;
    const Results r = run(backend, "timing: {repeats: 2}\nmetrics: {oracle: true}\n");
    ASSERT_TRUE(r.oracle.has_value());
    ASSERT_EQ(r.oracle->runs.size(), 1u);
    const std::vector<std::string> expected = {"uniform1", "uniform16", "aamap16",  // first runs
                                               "aamap16",                           // the oracle's first run
                                               "uniform1", "uniform16", "aamap16", "aamap16"};  // one round of all
    EXPECT_EQ(backend.order, expected);
    EXPECT_EQ(r.oracle->runs[0].record.times.traceRuns.size(), 2u);
    for (const RenderRecord& rec : r.renders) EXPECT_EQ(rec.times.traceRuns.size(), 2u) << rec.name;
}

}  // namespace
}  // namespace aamap
