// aamap compare: two runs that differ in one setting get one column for it, every render of both
// runs is a row, each run's tables appear under its label; a folder without results is an error.
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include <gtest/gtest.h>

#include "core/error.h"
#include "eval/compare.h"
#include "eval/config.h"
#include "eval/runner.h"
#include "tests/common/read_text.h"
#include "tests/eval/fake_backend.h"

namespace aamap {
namespace {

namespace fs = std::filesystem;

TEST(Compare, RunsDifferingInOneSettingSideBySide) {
    const fs::path dir = fs::path(::testing::TempDir()) / "compare_two_runs";
    fs::remove_all(dir);
    const std::string yaml = "scene: builtin:cornell\nimage: {width: 48, height: 32}\n"
                             "renders:\n  - {strategy: uniform, rpp: [1, 4], series: Standard}\n"
                             "  - {strategy: aamap, rpp: 4, series: Selective}\nreport: {plots: false}\n";
    for (const char* gain : {"1", "2"}) {
        FakeBackend backend;
        const ExperimentConfig c = parseConfig(yaml, "exp.yaml", {std::string("snapshot.gain=") + gain});
        runExperimentWith(c, dir / (std::string("gain") + gain), backend, RunnerOptions{"test-rev", false});
    }
    writeComparison({dir / "gain1", dir / "gain2"}, dir / "cmp", {}, false);
    const std::string csv = test::readText(dir / "cmp" / "compare.csv");
    std::istringstream lines(csv);
    std::string header;
    std::getline(lines, header);
    EXPECT_EQ(header.rfind("run,snapshot.gain,name,series,", 0), 0u) << header;  // only the gain differs
    int rows = 0, gain2 = 0;
    for (std::string line; std::getline(lines, line);) {
        ++rows;
        const std::size_t a = line.find(','), b = line.find(',', a + 1);
        const std::string run = line.substr(0, a), gain = line.substr(a + 1, b - a - 1);
        EXPECT_EQ(gain, run.find("gain2") != std::string::npos ? "2.0" : "1.0") << line;
        if (gain == "2.0") ++gain2;
    }
    EXPECT_EQ(rows, 6);  // 3 renders per run
    EXPECT_EQ(gain2, 3);
    const std::string md = test::readText(dir / "cmp" / "compare.md");
    EXPECT_NE(md.find("### snapshot.gain=1.0"), std::string::npos) << md;
    EXPECT_NE(md.find("### snapshot.gain=2.0"), std::string::npos) << md;
    EXPECT_NE(md.find("#### Table 3"), std::string::npos) << md;
    const std::string html = test::readText(dir / "cmp" / "compare.html");
    EXPECT_NE(html.find("../gain2/report.html"), std::string::npos);  // relative links to each run's report

    EXPECT_THROW(writeComparison({dir / "gain1", dir / "missing"}, dir / "cmp2", {}, false), InputError);
    EXPECT_FALSE(fs::exists(dir / "cmp2"));  // nothing written for bad input
}

// Two shading modes against one path-traced reference: the table across the runs holds exactly the
// renders that no other render of either run matches in both time and error.
TEST(Compare, ParetoFrontAcrossRunsHoldsExactlyTheUndominatedRenders) {
    const fs::path dir = fs::path(::testing::TempDir()) / "compare_pareto";
    fs::remove_all(dir);
    const std::string yaml = "scene: builtin:cornell\nimage: {width: 48, height: 32}\n"
                             "renders:\n  - {strategy: uniform, rpp: [1, 4, 16, 64], series: Standard}\n"
                             "  - {strategy: aamap, rpp: [4, 16, 64], series: Selective}\n"
                             "reference: {mode: path, rpp: 256}\nmetrics: {map_quality: false}\nreport: {plots: false}\n";
    std::vector<fs::path> dirs;
    for (const char* mode : {"direct", "path"}) {
        FakeBackend backend;
        if (std::string(mode) == "direct") backend.shadingBias = 0.02f;  // biased: off everywhere by a little
        const ExperimentConfig c = parseConfig(yaml, "exp.yaml", {std::string("shading.mode=") + mode});
        dirs.push_back(dir / mode);
        runExperimentWith(c, dirs.back(), backend, RunnerOptions{"test-rev", false});
    }
    const std::vector<ComparedRun> runs = loadComparedRuns(dirs);
    const Table t = paretoTable({&runs[0], &runs[1]});
    ASSERT_FALSE(t.rows.empty());
    struct Point {
        std::string run, name;
        double seconds, error;
    };
    std::vector<Point> all;
    for (const ComparedRun& run : runs)
        for (const auto& r : run.results["renders"])
            all.push_back({run.label, r["name"].get<std::string>(),
                           r["times_s"]["trace"].get<double>() + r["times_s"]["snapshot_total"].get<double>(),
                           r["metrics"]["pct_error_flip"].get<double>()});
    ASSERT_EQ(all.size(), 14u);
    const auto inTable = [&](const Point& p) {
        for (const auto& row : t.rows)
            if (row[0] == p.run && row[2] == p.name) return true;
        return false;
    };
    for (const Point& p : all) {
        bool dominated = false;
        for (const Point& q : all)
            if (&q != &p && q.seconds <= p.seconds && q.error <= p.error && (q.seconds < p.seconds || q.error < p.error))
                dominated = true;
        EXPECT_EQ(inTable(p), !dominated) << p.run << " " << p.name << " " << p.seconds << " s " << p.error << " %";
    }
    for (std::size_t i = 1; i < t.rows.size(); ++i) {  // fastest first, each more accurate than the last
        EXPECT_LT(std::stod(t.rows[i - 1][3]), std::stod(t.rows[i][3]));
        EXPECT_GT(std::stod(t.rows[i - 1][4]), std::stod(t.rows[i][4]));
    }
    EXPECT_EQ(t.rows.back()[0], "shading.mode=path");  // the unbiased mode reaches the lowest error
    EXPECT_EQ(t.note.find("different references"), std::string::npos) << t.note;  // one path reference for both
    // Runs whose references differ (another seed traces another reference) are said not to compare.
    {
        FakeBackend backend;
        const ExperimentConfig c = parseConfig(yaml, "exp.yaml", {"shading.mode=path", "seed=2"});
        runExperimentWith(c, dir / "seed2", backend, RunnerOptions{"test-rev", false});
    }
    const std::vector<ComparedRun> mixed = loadComparedRuns({dirs[1], dir / "seed2"});
    EXPECT_NE(paretoTable({&mixed[0], &mixed[1]}).note.find("different references"), std::string::npos);
    writeComparison(dirs, dir / "cmp", {}, false);
    EXPECT_NE(test::readText(dir / "cmp" / "compare.md").find("### Speed against accuracy across the runs"), std::string::npos);
}

}  // namespace
}  // namespace aamap
