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
    writeComparison({dir / "gain1", dir / "gain2"}, dir / "cmp");
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

    EXPECT_THROW(writeComparison({dir / "gain1", dir / "missing"}, dir / "cmp2"), InputError);
    EXPECT_FALSE(fs::exists(dir / "cmp2"));  // nothing written for bad input
}

}  // namespace
}  // namespace aamap
