// The runner with a fake backend: resumability (a deleted record is the only render redone;
// temporaries of a killed run are removed), metrics wiring, automatic reference and 1-ray renders,
// and the report files.
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <stdexcept>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "core/error.h"
#include "core/image_io.h"
#include "eval/config.h"
#include "eval/report.h"
#include "eval/runner.h"
#include "tests/common/read_text.h"
#include "tests/eval/fake_backend.h"

namespace aamap {
namespace {

namespace fs = std::filesystem;

const char* const kConfig = R"(scene: builtin:cornell
image: {width: 48, height: 32}
renders:
  - {strategy: uniform, rpp: [1, 4, 16], series: Standard}
  - {strategy: aamap, rpp: [1, 4, 16], series: Selective}
report: {plots: false}
)";

class Runner : public ::testing::Test {
protected:
    void SetUp() override {
        out_ = fs::path(::testing::TempDir()) / ("runner_" + std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()));
        fs::remove_all(out_);
    }
    Results run(FakeBackend& backend, const std::vector<std::string>& overrides = {}) {
        const ExperimentConfig c = parseConfig(kConfig, "exp.yaml", overrides);
        return runExperimentWith(c, out_, backend, RunnerOptions{"test-rev", false});
    }
    fs::path out_;
};

// The run's stages alone: plan reads and decides without tracing or writing; execute traces
// and records without measuring; evaluate measures without tracing (no oracle here); report
// writes the report. Out of order is an error.
TEST_F(Runner, StagesEachDoTheirOwnPartAlone) {
    const ExperimentConfig c = parseConfig(kConfig, "exp.yaml");
    FakeBackend backend;
    fs::create_directories(out_);
    ExperimentRun run(c, out_, backend, RunnerOptions{"test-rev", false});
    EXPECT_THROW(run.execute(), std::logic_error);
    run.plan();
    EXPECT_EQ(backend.totalTraces(), 0);
    EXPECT_EQ(backend.prepares, 0);
    EXPECT_TRUE(run.results().renders.empty());
    EXPECT_FALSE(fs::exists(out_ / "results.json"));
    EXPECT_THROW(run.evaluate(), std::logic_error);

    run.execute();
    EXPECT_EQ(backend.totalTraces(), 6);
    EXPECT_EQ(backend.snapshots, 1);
    ASSERT_EQ(run.results().renders.size(), 6u);
    for (const RenderRecord& r : run.results().renders) EXPECT_TRUE(r.metrics.is_null()) << r.name;
    EXPECT_TRUE(fs::exists(out_ / "results.json"));
    EXPECT_FALSE(fs::exists(out_ / "report.html"));

    run.evaluate();
    EXPECT_EQ(backend.totalTraces(), 6);
    for (const RenderRecord& r : run.results().renders) EXPECT_TRUE(r.metrics.contains("pct_error_flip")) << r.name;
    EXPECT_FALSE(run.results().mapQuality.is_null());
    EXPECT_FALSE(fs::exists(out_ / "report.html"));

    const Results done = run.report();
    EXPECT_EQ(done.renders.size(), 6u);
    EXPECT_TRUE(fs::exists(out_ / "report.html"));
    EXPECT_TRUE(fs::exists(out_ / "report.md"));
    EXPECT_THROW(run.report(), std::logic_error);
}

// A bad input is found by the plan, before the scene loads or anything is traced.
TEST_F(Runner, PlanRefusesABadReferenceFileBeforeAnyWork) {
    const ExperimentConfig c =
        parseConfig(std::string(kConfig) + "reference: {type: file, path: missing.exr}\n", (out_ / "exp.yaml").string());
    FakeBackend backend;
    fs::create_directories(out_);
    ExperimentRun run(c, out_, backend, RunnerOptions{"test-rev", false});
    EXPECT_THROW(run.plan(), InputError);
    EXPECT_EQ(backend.prepares, 0);
    EXPECT_EQ(backend.totalTraces(), 0);
    EXPECT_FALSE(fs::exists(out_ / "results.json"));
}

TEST_F(Runner, SecondRunReusesEverythingAndDeletedRecordIsTheOnlyRedo) {
    FakeBackend first;
    const Results r1 = run(first);
    // 6 listed renders; the reference (uniform 16) and the 1-ray probe (uniform 1) are listed too,
    // so nothing is traced twice.
    EXPECT_EQ(first.totalTraces(), 6);
    EXPECT_EQ(first.snapshots, 1);
    ASSERT_EQ(r1.renders.size(), 6u);
    for (const RenderRecord& r : r1.renders) EXPECT_FALSE(r.cached);

    FakeBackend second;
    const Results r2 = run(second);
    EXPECT_EQ(second.totalTraces(), 0);
    EXPECT_EQ(second.prepares, 0);  // no scene, no GPU
    EXPECT_EQ(second.snapshots, 0);
    for (const RenderRecord& r : r2.renders) EXPECT_TRUE(r.cached);
    EXPECT_DOUBLE_EQ(r2.renders[4].times.trace, r1.renders[4].times.trace);  // timings survive

    // A run killed while committing aamap4: its record never landed, and temporaries remain.
    const std::string key = r1.renders[4].key;
    fs::remove(out_ / "cache" / key / "record.json");
    fs::create_directories(out_ / "cache" / (key + ".tmp-99999-0"));
    std::ofstream(out_ / "cache" / (key + ".tmp-99999-0") / "image.exr") << "half";
    std::ofstream(out_ / "aamap4.png.tmp-99999") << "half";
    FakeBackend third;
    const Results r3 = run(third);
    EXPECT_EQ(third.totalTraces(), 1);
    EXPECT_EQ(third.traces["aamap4"], 1);
    EXPECT_FALSE(r3.renders[4].cached);
    EXPECT_TRUE(r3.renders[3].cached);
    EXPECT_FALSE(fs::exists(out_ / "cache" / (key + ".tmp-99999-0")));
    EXPECT_FALSE(fs::exists(out_ / "aamap4.png.tmp-99999"));
    for (const auto& e : fs::recursive_directory_iterator(out_))
        EXPECT_EQ(e.path().filename().string().find(".tmp-"), std::string::npos) << e.path();
}

TEST_F(Runner, AFailedFirstRunLeavesNoFolderAndALaterFailureKeepsFinishedRenders) {
    FakeBackend broken;
    broken.failPrepare = true;
    EXPECT_THROW(run(broken), InputError);
    EXPECT_FALSE(fs::exists(out_)) << "a run that failed before finishing anything left " << out_;

    FakeBackend backend;
    run(backend);
    const auto entries = [&] {
        std::size_t n = 0;
        for ([[maybe_unused]] const auto& e : fs::directory_iterator(out_ / "cache")) ++n;
        return n;
    };
    const std::size_t finished = entries();
    ASSERT_GT(finished, 0u);
    // A fully cached rerun never loads the scene; ask for one new render so the failure happens.
    EXPECT_THROW(run(broken, {"renders.0.rpp=[1, 4, 9, 16]"}), InputError);
    EXPECT_EQ(entries(), finished) << "finished renders must survive a later failed run";
}

TEST_F(Runner, DamagedEntryIsTracedAgain) {
    FakeBackend first;
    const Results r1 = run(first);
    std::ofstream(out_ / "cache" / r1.renders[1].key / "image.exr", std::ios::trunc) << "not an exr";
    FakeBackend second;
    const Results r2 = run(second);
    EXPECT_EQ(second.totalTraces(), 1);
    EXPECT_EQ(second.traces["uniform4"], 1);
    EXPECT_FALSE(r2.renders[1].cached);
}

TEST_F(Runner, ChangedSettingsOnlyRedoWhatTheyTouch) {
    FakeBackend first;
    run(first);
    FakeBackend second;  // the snapshot gain changes the aamap renders, not the uniform ones
    run(second, {"snapshot.gain=2"});
    EXPECT_EQ(second.snapshots, 1);
    EXPECT_EQ(second.totalTraces(), 3);
    EXPECT_EQ(second.traces["aamap16"], 1);
}

TEST_F(Runner, MetricsAgainstTheReference) {
    FakeBackend backend;
    const Results r = run(backend);
    const RenderRecord& same = r.renders[2];  // uniform16 is the reference itself
    ASSERT_EQ(same.name, "uniform16");
    EXPECT_EQ(same.metrics["mse"].get<double>(), 0.0);
    EXPECT_EQ(same.metrics["pct_error_mse"].get<double>(), 0.0);
    EXPECT_EQ(same.metrics["flip_mean"].get<double>(), 0.0);
    EXPECT_EQ(same.metrics["pct_error_flip"].get<double>(), 0.0);
    EXPECT_TRUE(same.metrics["psnr"].is_null());  // infinite
    const RenderRecord& coarse = r.renders[0];  // uniform1 differs along the edge column
    EXPECT_GT(coarse.metrics["mse"].get<double>(), 0.0);
    EXPECT_NEAR(coarse.metrics["pct_error_mse"].get<double>(), 100.0 / FakeBackend::kW, 1e-9);
    for (const char* f : {"uniform1.flip.png", "uniform1.overlay.png", "reference.png", "one_ray.png",
                          "aliasing.png", "aamap.png", "aamap.exr", "snapshot.png"})
        EXPECT_TRUE(fs::is_regular_file(out_ / f)) << f;
    ASSERT_FALSE(r.mapQuality.is_null());
    EXPECT_EQ(r.mapQuality["recall"].get<double>(), 1.0);  // the edge band is flagged
    EXPECT_EQ(r.mapQuality["flagged_pixels"].get<int>(), FakeBackend::kH * (2 * FakeBackend::kBand + 1));
    EXPECT_GT(r.mapQuality["true_pixels"].get<int>(), 0);
    EXPECT_GT(r.mapQuality["precision"].get<double>(), 0.0);  // FLIP spreads less wide than the band
    EXPECT_TRUE(r.reference.has_value());
    EXPECT_TRUE(r.oneRay.has_value());
    // The report's crops: none where the render is the reference, the edge column where it errs.
    EXPECT_TRUE(same.metrics["worst_regions"].empty());
    ASSERT_FALSE(coarse.metrics["worst_regions"].empty());
    const nlohmann::ordered_json& worst = coarse.metrics["worst_regions"][0];
    EXPECT_LE(worst["x"].get<int>(), FakeBackend::kW / 2);
    EXPECT_GT(worst["x"].get<int>() + worst["size"].get<int>(), FakeBackend::kW / 2);
    EXPECT_GT(worst["flip_mean"].get<double>(), 0.0);
}

// A path-traced reference of a biased shading mode: the most-sampled uniform render carries the
// bias alone (its error against the truth), and every other render is measured against it too,
// which leaves the antialiasing it lacks (here the edge column only, as without a bias).
TEST_F(Runner, GroundTruthSplitsShadingBiasFromAntialiasing) {
    FakeBackend backend;
    backend.shadingBias = 0.05f;
    const Results r = run(backend, {"reference.mode=path", "reference.rpp=64"});
    ASSERT_EQ(r.referenceInfo.shadingFloor, "uniform16");
    const RenderRecord& floor = r.renders[2];
    ASSERT_EQ(floor.name, "uniform16");
    EXPECT_FALSE(floor.metrics.contains("antialiasing"));
    // The bias shows in every column but the edge's, where the floor's missing rays and the bias
    // nearly cancel.
    EXPECT_GE(floor.metrics["pct_error_mse"].get<double>(), 100.0 * (FakeBackend::kW - 1) / FakeBackend::kW - 1e-9);
    const RenderRecord& coarse = r.renders[0];
    ASSERT_EQ(coarse.name, "uniform1");
    const nlohmann::ordered_json& aa = coarse.metrics["antialiasing"];
    EXPECT_EQ(aa["against"].get<std::string>(), "uniform16");
    EXPECT_NEAR(aa["pct_error_mse"].get<double>(), 100.0 / FakeBackend::kW, 1e-9);
    EXPECT_GT(aa["flip_mean"].get<double>(), 0.0);
    EXPECT_LT(aa["flip_mean"].get<double>(), coarse.metrics["flip_mean"].get<double>());
    const RenderRecord& selective = r.renders[5];  // the map flags the edge: its pixels get 16 rays
    ASSERT_EQ(selective.name, "aamap16");
    EXPECT_EQ(selective.metrics["antialiasing"]["mse"].get<double>(), 0.0);
    const std::string md = test::readText(out_ / "report.md");
    EXPECT_NE(md.find("Error against ground truth: shading bias and antialiasing"), std::string::npos) << md;
    EXPECT_NE(md.find("| uniform16 (shading bias) |"), std::string::npos) << md;

    // A reference in the renders' own mode is no ground truth to split against.
    FakeBackend same;
    same.shadingBias = 0.05f;
    const Results plain = run(same);
    EXPECT_TRUE(plain.referenceInfo.shadingFloor.empty());
    for (const RenderRecord& rec : plain.renders) EXPECT_FALSE(rec.metrics.contains("antialiasing")) << rec.name;
    EXPECT_EQ(test::readText(out_ / "report.md").find("Error against ground truth"), std::string::npos);
}

// Cache mode with B bounces renders paths of B + 2 segments; a path reference of another length is
// named in a warning, since the difference would pass for the cache's bias.
// The oracle map on a scene where the answer is known: a 1-ray pixel is wrong only at the edge
// column (and where FLIP spreads its error), so the oracle flags that column and the aamap renders
// on it match the reference there with no Snapshot cost.
TEST_F(Runner, OracleMapFlagsWhatTheReferenceSaysAndBoundsTheMap) {
    FakeBackend backend;
    const Results r = run(backend, {"metrics.oracle=true"});
    ASSERT_TRUE(r.oracle);
    ASSERT_EQ(r.oracle->runs.size(), 3u);  // aamap1, aamap4, aamap16
    EXPECT_GT(r.oracle->flaggedFraction, 0.0);
    EXPECT_LT(r.oracle->flaggedFraction, 1.0);
    EXPECT_GE(r.oracle->rounds, 2);  // the last round finds nothing new
    const ImageGrey oracle = [&] {
        const ImageRGB8 png = readPng(out_ / "oracle.png");
        ImageGrey g(png.width(), png.height());
        for (int y = 0; y < png.height(); ++y)
            for (int x = 0; x < png.width(); ++x) g.at(x, y) = png.at(x, y).r / 255.0f;
        return g;
    }();
    for (int y = 0; y < FakeBackend::kH; ++y) {
        EXPECT_EQ(oracle.at(FakeBackend::kW / 2, y), 1.0f) << y;  // the only wrong column
        EXPECT_EQ(oracle.at(0, y), 0.0f) << y;                      // flat: one ray is right
    }
    for (std::size_t k = 0; k < r.oracle->runs.size(); ++k) {
        const OracleRun& o = r.oracle->runs[k];
        EXPECT_EQ(o.mapRender, r.renders[3 + k].name);
        EXPECT_EQ(o.record.name, "oracle_" + o.mapRender);
        EXPECT_EQ(o.record.parameters["map"], "oracle");
        EXPECT_EQ(o.record.times.snapshotTotal, 0.0);
        EXPECT_EQ(o.record.key.rfind("oracle-", 0), 0u);
        // The oracle flags fewer pixels than the Snapshot's band, so it traces fewer rays.
        if (o.record.maxRaysPerPixel > 1) {
            EXPECT_LT(o.record.meanPrimaryRpp, r.renders[3 + k].meanPrimaryRpp);
        }
    }
    const OracleRun& best = r.oracle->runs[2];
    ASSERT_EQ(best.mapRender, "aamap16");
    EXPECT_EQ(best.record.metrics["mse"].get<double>(), 0.0);  // the reference is uniform16
    const std::string md = test::readText(out_ / "report.md");
    EXPECT_NE(md.find("The map against the oracle map"), std::string::npos) << md;
    EXPECT_NE(md.find("| aamap16 | 16 |"), std::string::npos) << md;

    FakeBackend again;  // the oracle renders are cached like the others
    const Results r2 = run(again, {"metrics.oracle=true"});
    EXPECT_EQ(again.totalTraces(), 0);
    ASSERT_TRUE(r2.oracle);
    ASSERT_EQ(r2.oracle->runs.size(), 3u);
    EXPECT_TRUE(r2.oracle->runs[2].record.cached);

    FakeBackend plain;
    EXPECT_FALSE(run(plain).oracle);
    EXPECT_EQ(test::readText(out_ / "report.md").find("oracle"), std::string::npos);
}

TEST_F(Runner, CacheAgainstPathReferenceOfAnotherDepthIsWarned) {
    const auto mentions = [](const Results& r, const std::string& text) {
        for (const std::string& w : r.warnings)
            if (w.find(text) != std::string::npos) return true;
        return false;
    };
    FakeBackend mismatched;
    const Results off = run(mismatched, {"shading.mode=cache", "shading.cache.bounces=4", "shading.max_depth=5",
                                          "reference.mode=path", "reference.rpp=64"});
    EXPECT_TRUE(mentions(off, "set shading.max_depth: 6")) << fmt::format("{}", fmt::join(off.warnings, "\n"));
    FakeBackend matched;
    const Results same = run(matched, {"shading.mode=cache", "shading.cache.bounces=4", "shading.max_depth=6",
                                        "reference.mode=path", "reference.rpp=64"});
    EXPECT_FALSE(mentions(same, "shading.max_depth")) << fmt::format("{}", fmt::join(same.warnings, "\n"));
}

TEST_F(Runner, ReferenceAndOneRayRendersAreAddedWhenMissing) {
    FakeBackend backend;
    run(backend, {"renders.0.rpp=4", "renders.1.rpp=4", "reference.rpp=64"});
    EXPECT_EQ(backend.traces["uniform64"], 1);  // the reference
    EXPECT_EQ(backend.traces["uniform1"], 1);   // the 1-ray probe of map quality
    FakeBackend noProbe;
    run(noProbe, {"renders.0.rpp=4", "renders.1.rpp=4", "metrics.map_quality=false", "reference.rpp=4"});
    EXPECT_EQ(noProbe.totalTraces(), 0);  // all cached from the run above
}

TEST_F(Runner, ReportFilesAndTables) {
    FakeBackend backend;
    run(backend);
    for (const char* f : {"report.html", "report.md", "results.csv", "results.json"})
        EXPECT_TRUE(fs::is_regular_file(out_ / f)) << f;
    const std::string csv = test::readText(out_ / "results.csv");
    std::istringstream lines(csv);
    std::string header;
    std::getline(lines, header);
    std::string expected;
    for (const std::string& c : resultsCsvColumns()) expected += (expected.empty() ? "" : ",") + c;
    EXPECT_EQ(header, expected);
    int rows = 0;
    for (std::string line; std::getline(lines, line);) rows += !line.empty();
    EXPECT_EQ(rows, 6);
    EXPECT_NE(csv.find("\naamap16,Selective,aamap,16,"), std::string::npos) << csv;

    const std::string md = test::readText(out_ / "report.md");
    for (const char* s : {"Table 1/2: render time", "Table 1/2: speedup over Standard", "Table 3: % error pixels",
                          "| rpp | Standard | Selective |", "| rpp | Selective |",
                          "| rpp | Standard FLIP | Standard MSE | Selective FLIP | Selective MSE |", "Map quality"})
        EXPECT_NE(md.find(s), std::string::npos) << s << "\n" << md;
    for (const char* row : {"\n| 1 |", "\n| 4 |", "\n| 16 |"}) EXPECT_NE(md.find(row), std::string::npos) << row;

    const std::string html = test::readText(out_ / "report.html");
    for (const char* s : {"<h2 id=\"time\">", "<h2 id=\"speedup\">", "<h2 id=\"error\">", "<h2 id=\"map_quality\">",
                          "src=\"aamap16.overlay.png\"", "src=\"aamap.png\"", "href=\"results.csv\"",
                          "plots turned off"})
        EXPECT_NE(html.find(s), std::string::npos) << s;
    EXPECT_EQ(html.find("file://"), std::string::npos);  // relative links only
}

TEST_F(Runner, ViewerDataNamesEveryRenderAndOnlyFilesThatExist) {
    FakeBackend backend;
    run(backend);
    const std::string html = test::readText(out_ / "report.html");
    const std::string open = "<script type=\"application/json\" id=\"aamap-viewer-data\">";
    const std::size_t begin = html.find(open);
    ASSERT_NE(begin, std::string::npos);
    const std::size_t end = html.find("</script>", begin);
    const nlohmann::json data = nlohmann::json::parse(html.substr(begin + open.size(), end - begin - open.size()));
    EXPECT_EQ(data["renders"].size(), 6u);
    EXPECT_EQ(data["width"].get<int>(), FakeBackend::kW);
    for (const nlohmann::json& r : data["renders"])
        for (const auto& [layer, file] : r["layers"].items())
            if (!file.is_null()) {
                EXPECT_TRUE(fs::is_regular_file(out_ / file.get<std::string>())) << file;
            }
    EXPECT_EQ(data["reference"], "reference.png");
    EXPECT_NE(html.find("<script>"), std::string::npos);  // the viewer's script is on the page itself
    EXPECT_EQ(html.find("http://"), std::string::npos);   // nothing to fetch from a network
    EXPECT_EQ(html.find("https://"), std::string::npos);
}

TEST_F(Runner, AFailedPlotScriptLinksNoStalePlots) {
    FakeBackend backend;
    run(backend);
    fs::create_directories(out_ / "plots");
    std::ofstream(out_ / "plots/time_vs_rpp.png") << "an earlier run's plot";
    ::setenv("AAMAP_PYTHON", "/bin/false", 1);  // runs, and fails
    std::ifstream in(out_ / "results.json");
    writeReport(out_, nlohmann::ordered_json::parse(in), true);
    ::unsetenv("AAMAP_PYTHON");
    const std::string html = test::readText(out_ / "report.html");
    EXPECT_NE(html.find("What went wrong"), std::string::npos);
    EXPECT_NE(html.find("failed (exit status 1)"), std::string::npos);
    EXPECT_EQ(html.find("plots/time_vs_rpp.png"), std::string::npos);
    EXPECT_FALSE(fs::exists(out_ / "plots/time_vs_rpp.png"));
}

TEST(ReadableNumber, ShortestFormForFloatsThreeDigitsOtherwise) {
    EXPECT_EQ(readableNumber(static_cast<double>(0.1f)), "0.1");  // not 0.10000000149011612
    EXPECT_EQ(readableNumber(0.1), "0.1");
    EXPECT_EQ(readableNumber(static_cast<double>(5.151367f)), "5.15");  // a measured float: 3 digits
    EXPECT_EQ(readableNumber(static_cast<double>(0.025f)), "0.025");
    EXPECT_EQ(readableNumber(36.0), "36");
    EXPECT_EQ(readableNumber(0.123456789), "0.123");
    EXPECT_EQ(readableNumber(12.3456789), "12.3");
    EXPECT_EQ(readableNumber(1234.56789), "1230");
    EXPECT_EQ(readableNumber(0.000123456), "0.000123");
    EXPECT_EQ(readableNumber(NAN), "—");
}

TEST_F(Runner, MissingPythonDegradesWithAWarning) {
    FakeBackend backend;
    run(backend);
    ::setenv("AAMAP_PYTHON", "/nonexistent/python", 1);
    std::ifstream in(out_ / "results.json");
    const nlohmann::ordered_json results = nlohmann::ordered_json::parse(in);
    writeReport(out_, results, true);
    ::unsetenv("AAMAP_PYTHON");
    const std::string html = test::readText(out_ / "report.html");
    EXPECT_NE(html.find("Python venv not found"), std::string::npos);
    EXPECT_NE(html.find("Table 3"), std::string::npos);  // the tables are there regardless
}

}  // namespace
}  // namespace aamap
