// Sweeps outside the renders list: the cartesian product of the listed settings, the first key
// varying slowest, each variant an ordinary experiment; errors name the list's file:line; the
// variants run into sub-folders that share one cache, so what they share is traced once.
#include <algorithm>
#include <filesystem>
#include <fstream>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "core/error.h"
#include "eval/config.h"
#include "eval/compare.h"
#include "eval/sweep_runner.h"
#include "tests/eval/fake_backend.h"
#include "tests/common/read_text.h"

namespace aamap {
namespace {

namespace fs = std::filesystem;

const char* const kSwept = R"(scene: [builtin:cornell, builtin:spheres-plane]
image: {width: 48, height: 32}
snapshot: {blur_radius: [1, 2]}
timing: {repeats: 3}
renders:
  - {strategy: uniform, rpp: [1, 4], series: Standard}
  - {strategy: aamap, rpp: 4, series: Selective}
report: {plots: false}
)";

// The line of the error a swept config gives; -1 when it parses.
int lineOf(const std::string& yaml) {
    try {
        parseExperiment(yaml, "exp.yaml");
    } catch (const InputError& e) {
        return e.line();
    }
    return -1;
}

TEST(ConfigSweeps, CartesianProductWithTheFirstKeySlowest) {
    const Experiment e = parseExperiment(kSwept, "exp.yaml");
    ASSERT_EQ(e.sweptKeys, (std::vector<std::string>{"scene", "snapshot.blur_radius"}));
    ASSERT_EQ(e.variants.size(), 4u);
    const std::vector<std::pair<std::string, int>> expected = {
        {"builtin:cornell", 1}, {"builtin:cornell", 2}, {"builtin:spheres-plane", 1}, {"builtin:spheres-plane", 2}};
    for (std::size_t i = 0; i < 4; ++i) {
        EXPECT_EQ(e.variants[i].scene, expected[i].first);
        EXPECT_EQ(e.variants[i].snapshot.filter.blurRadius, expected[i].second);
        EXPECT_EQ(e.variants[i].timing.repeats, 3);  // what is not swept is the same everywhere
        EXPECT_EQ(e.sweptValues[i][0], expected[i].first);
    }
    EXPECT_EQ(e.folders, (std::vector<std::string>{"scene-cornell_blur_radius-1", "scene-cornell_blur_radius-2",
                                                   "scene-spheres-plane_blur_radius-1",
                                                   "scene-spheres-plane_blur_radius-2"}));
    // A swept Snapshot setting changes the aamap renders' keys, not the uniform ones'.
    EXPECT_EQ(renderKey(e.variants[0], e.variants[0].renders[0]), renderKey(e.variants[1], e.variants[1].renders[0]));
    EXPECT_NE(renderKey(e.variants[0], e.variants[0].renders[2]), renderKey(e.variants[1], e.variants[1].renders[2]));
}

TEST(ConfigSweeps, OverridesSweepAndSingleConfigCommandsRefuse) {
    const char* plain = "scene: builtin:cornell\nrenders: [{strategy: uniform, rpp: 1}]\n";
    const Experiment e = parseExperiment(plain, "exp.yaml", {"snapshot.blur_radius=[1,2]", "shading.mode=[direct, path]"});
    EXPECT_EQ(e.variants.size(), 4u);
    EXPECT_EQ(e.folders[3], "blur_radius-2_mode-path");
    EXPECT_EQ(parseExperiment(plain, "exp.yaml").variants.size(), 1u);
    EXPECT_TRUE(parseExperiment(plain, "exp.yaml").sweptKeys.empty());
    EXPECT_THROW(parseConfig(plain, "exp.yaml", {"snapshot.blur_radius=[1,2]"}), InputError);
    // Two swept keys with the same last name are told apart by their section.
    const Experiment both = parseExperiment(plain, "exp.yaml", {"snapshot.area_light_samples=[1,2]",
                                                                "shading.area_light_samples=[4,9]"});
    EXPECT_EQ(both.folders[0], "snapshot_area_light_samples-1_shading_area_light_samples-4");
}

TEST(ConfigSweeps, BadListsNameTheirLine) {
    EXPECT_EQ(lineOf("scene: builtin:cornell\nsnapshot: {blur_radius: []}\nrenders: [{strategy: uniform, rpp: 1}]\n"), 2);
    EXPECT_EQ(lineOf("scene: builtin:cornell\nsnapshot:\n  blur_radius: [1, 1]\nrenders: [{strategy: uniform, rpp: 1}]\n"), 3);
    // A swept value is checked like a single one, and the error points at the list item.
    EXPECT_EQ(lineOf("scene: builtin:cornell\nsnapshot:\n  blur_radius:\n    - 1\n    - 99\n"
                     "renders: [{strategy: uniform, rpp: 1}]\n"),
              5);
    // The cap on the expansion.
    std::string many = "scene: builtin:cornell\nseed: [";
    for (int i = 0; i < 17; ++i) many += std::to_string(i) + (i < 16 ? ", " : "]\n");
    many += "image: {width: [";
    for (int i = 1; i <= 17; ++i) many += std::to_string(i) + (i < 17 ? ", " : "]}\n");
    many += "renders: [{strategy: uniform, rpp: 1}]\n";
    EXPECT_GT(lineOf(many), 0);
}

// zip: lists of equal length that vary together, in a product with the other sweeps.
TEST(ConfigSweeps, ZippedListsVaryTogether) {
    const char* yaml = "scene: [builtin:cornell, builtin:spheres-plane]\n"
                       "snapshot: {blur_radius: [0, 1, 2], gain: [1, 2, 4]}\n"
                       "zip: [[snapshot.blur_radius, snapshot.gain]]\n"
                       "renders: [{strategy: uniform, rpp: 1}]\n";
    const Experiment e = parseExperiment(yaml, "exp.yaml");
    ASSERT_EQ(e.variants.size(), 6u);  // 2 scenes x 3 pairs, not 2 x 3 x 3
    const int radius[] = {0, 1, 2}, gain[] = {1, 2, 4};
    for (std::size_t i = 0; i < 6; ++i) {
        EXPECT_EQ(e.variants[i].scene, i < 3 ? "builtin:cornell" : "builtin:spheres-plane");
        EXPECT_EQ(e.variants[i].snapshot.filter.blurRadius, radius[i % 3]);
        EXPECT_DOUBLE_EQ(e.variants[i].snapshot.filter.gain, gain[i % 3]);
    }
    const std::string body = "scene: builtin:cornell\nsnapshot: {blur_radius: [0, 1], gain: [1, 2, 4]}\n";
    EXPECT_EQ(lineOf(body + "zip: [[snapshot.blur_radius, snapshot.gain]]\nrenders: [{strategy: uniform, rpp: 1}]\n"), 3);
    EXPECT_EQ(lineOf(body + "zip: [[snapshot.blur_radius, seed]]\nrenders: [{strategy: uniform, rpp: 1}]\n"), 3);
    EXPECT_EQ(lineOf(body + "zip: [[snapshot.gain]]\nrenders: [{strategy: uniform, rpp: 1}]\n"), 3);
}

// A sweep's report opens with one table: a row per variant, a column per swept key, then the
// headline figures; the variants' own tables follow, folded.
TEST(ConfigSweeps, SweepSummaryHasARowPerVariantAndAColumnPerKey) {
    const fs::path out = fs::path(::testing::TempDir()) / "config_sweeps_summary";
    fs::remove_all(out);
    const char* yaml = "scene: [builtin:cornell, builtin:spheres-plane]\nimage: {width: 48, height: 32}\n"
                       "snapshot: {blur_radius: [0, 1, 2]}\n"
                       "renders:\n  - {strategy: uniform, rpp: [1, 4], series: Standard}\n"
                       "  - {strategy: aamap, rpp: 4, series: Selective}\nreport: {plots: false}\n";
    const Experiment e = parseExperiment(yaml, "exp.yaml");
    runSweepWith(e, out,
                 [](const ExperimentConfig&) { return std::unique_ptr<RenderBackend>(std::make_unique<FakeBackend>()); },
                 RunnerOptions{"test-rev", false});
    const std::vector<ComparedRun> runs = loadComparedRuns({out});
    const Table t = summaryTable(runs);
    ASSERT_EQ(t.rows.size(), 6u);
    ASSERT_GE(t.header.size(), 2u);
    EXPECT_EQ(t.header[0], "scene");
    EXPECT_EQ(t.header[1], "snapshot.blur_radius");
    EXPECT_NE(t.header[2].find("Selective speedup @4"), std::string::npos) << t.header[2];
    EXPECT_EQ(t.rows[4][0], "builtin:spheres-plane");
    EXPECT_EQ(t.rows[4][1], "1");
    EXPECT_EQ(runs[4].label, "snapshot.blur_radius=1");  // the scene is the section's, not the label's
    for (const auto& row : t.rows) EXPECT_EQ(row.size(), t.header.size());
    const std::string md = test::readText(out / "report.md");
    const std::size_t summary = md.find("## Summary"), detail = md.find("<details>");
    ASSERT_NE(summary, std::string::npos);
    ASSERT_NE(detail, std::string::npos);
    EXPECT_LT(summary, detail);  // the summary first, each variant's own tables folded below
    EXPECT_NE(md.find("is the fastest within"), std::string::npos) << md.substr(0, 2000);
}

// Map kinds side by side: with the oracle on, each map-driven series gets its efficiency against
// the oracle map in the summary, the speedup over the oracle twin's speedup at the same rpp.
TEST(ConfigSweeps, SummaryGivesEachMapItsOracleEfficiency) {
    const fs::path out = fs::path(::testing::TempDir()) / "config_sweeps_oracle";
    fs::remove_all(out);
    const char* yaml = "scene: builtin:cornell\nimage: {width: 48, height: 32}\n"
                       "snapshot: {map: [luminance, geometric]}\n"
                       "renders:\n  - {strategy: uniform, rpp: [1, 4], series: Standard}\n"
                       "  - {strategy: aamap, rpp: 4, series: Selective}\n"
                       "metrics: {oracle: true}\nreport: {plots: false}\n";
    runSweepWith(parseExperiment(yaml, "exp.yaml"), out,
                 [](const ExperimentConfig&) { return std::unique_ptr<RenderBackend>(std::make_unique<FakeBackend>()); },
                 RunnerOptions{"test-rev", false});
    const std::vector<ComparedRun> runs = loadComparedRuns({out});
    const Table t = summaryTable(runs);
    ASSERT_EQ(t.rows.size(), 2u);
    const auto column = std::find(t.header.begin(), t.header.end(), "Selective oracle efficiency");
    ASSERT_NE(column, t.header.end());
    const auto c = static_cast<std::size_t>(column - t.header.begin());
    for (std::size_t i = 0; i < runs.size(); ++i) {
        const nlohmann::ordered_json& r = runs[i].results;
        const auto seconds = [](const nlohmann::ordered_json& x) {
            return x["times_s"]["trace"].get<double>() + x["times_s"]["snapshot_total"].get<double>();
        };
        const nlohmann::ordered_json* map = nullptr;
        const nlohmann::ordered_json* base = nullptr;
        for (const auto& x : r["renders"]) {
            if (x["series"] == "Selective") map = &x;
            if (x["series"] == "Standard" && x["max_rays_per_pixel"] == 4) base = &x;
        }
        ASSERT_TRUE(map && base);
        const nlohmann::ordered_json* oracle = nullptr;
        for (const auto& o : r["oracle"]["runs"])
            if (o["map_render"] == (*map)["name"]) oracle = &o["render"];
        ASSERT_TRUE(oracle);
        const double expected = (seconds(*base) / seconds(*map)) / (seconds(*base) / seconds(*oracle));
        std::string cell = t.rows[i][c];
        cell.erase(std::remove(cell.begin(), cell.end(), '*'), cell.end());
        EXPECT_NEAR(std::stod(cell), expected, 0.01 * expected + 0.005) << cell;
    }
}

TEST(ConfigSweeps, VariantsShareOneCacheAndOneReport) {
    const fs::path out = fs::path(::testing::TempDir()) / "config_sweeps_run";
    fs::remove_all(out);
    const Experiment e = parseExperiment(kSwept, "exp.yaml");
    runSweepWith(e, out,
                 [](const ExperimentConfig&) { return std::unique_ptr<RenderBackend>(std::make_unique<FakeBackend>()); },
                 RunnerOptions{"test-rev", false});
    for (const std::string& folder : e.folders) {
        ASSERT_TRUE(fs::is_regular_file(out / folder / "results.json")) << folder;
        std::ifstream in(out / folder / "results.json");
        const nlohmann::json results = nlohmann::json::parse(in);
        for (const nlohmann::json& r : results["renders"]) EXPECT_EQ(r["times_s"]["trace_runs"].size(), 3u);
        EXPECT_FALSE(fs::exists(out / folder / "cache"));  // the shared one holds them
    }
    // The uniform renders of the second blur radius came from the first one's cache entries.
    std::ifstream in(out / e.folders[1] / "results.json");
    const nlohmann::json second = nlohmann::json::parse(in);
    EXPECT_TRUE(second["renders"][0]["cached"].get<bool>());
    EXPECT_FALSE(second["renders"][2]["cached"].get<bool>());  // the aamap render depends on the radius
    for (const char* f : {"report.html", "report.md", "results.csv", "sweep.json"})
        EXPECT_TRUE(fs::is_regular_file(out / f)) << f;
    // `aamap report OUTDIR` rebuilds it from the files alone.
    fs::remove(out / "report.md");
    rebuildReport(out, false);
    EXPECT_TRUE(fs::is_regular_file(out / "report.md"));
    // `aamap compare` takes the sweep's folder as all its variants, in sweep order.
    const std::vector<ComparedRun> runs = loadComparedRuns({out});
    ASSERT_EQ(runs.size(), e.folders.size());
    for (std::size_t i = 0; i < runs.size(); ++i) EXPECT_EQ(runs[i].dir, out / e.folders[i]);
    EXPECT_FALSE(runs[0].differs.empty()) << "the swept key tells the variants apart";
    writeComparison({out}, out / "cmp", {}, false);
    EXPECT_TRUE(fs::is_regular_file(out / "cmp" / "compare.csv"));
    // A malformed index is an error naming it, and nothing is written.
    std::ofstream(out / "sweep.json") << "{\"variants\": 3}";
    try {
        writeComparison({out}, out / "cmp2", {}, false);
        ADD_FAILURE() << "a malformed sweep.json must be an error";
    } catch (const InputError& err) {
        EXPECT_NE(std::string(err.what()).find("sweep.json"), std::string::npos) << err.what();
    }
    EXPECT_FALSE(fs::exists(out / "cmp2"));
}

}  // namespace
}  // namespace aamap
