// The report's tables and CSV with repeated timings: the median, its spread, speedups as a range.
#include <algorithm>
#include <stdexcept>
#include <string>
#include <vector>
#include <fstream>
#include <iterator>

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "eval/report.h"
#include "scene/light_file.h"

namespace aamap {
namespace {

using Json = nlohmann::ordered_json;

Json render(const std::string& name, const std::string& strategy, const std::string& series,
            const std::vector<double>& traceRuns, double snapshot) {
    std::vector<double> sorted = traceRuns;
    std::sort(sorted.begin(), sorted.end());
    return {{"name", name}, {"strategy", strategy}, {"series", series}, {"max_rays_per_pixel", 16},
            {"parameters", Json::object()}, {"width", 8}, {"height", 8}, {"mean_primary_rpp", 1.0},
            {"rays", {{"primary", 64}, {"total", 64}}}, {"git_revision", "x"},
            {"times_s", {{"trace", sorted[sorted.size() / 2]}, {"trace_runs", traceRuns}, {"snapshot_total", snapshot},
                         {"total", 1.0}}}};
}

Json results(Json renders) {
    return {{"renders", std::move(renders)}, {"config", {{"metrics", {{"flip_threshold", 0.1}}}}}};
}

const Table& table(const std::vector<Table>& tables, const std::string& id) {
    for (const Table& t : tables)
        if (t.id == id) return t;
    throw std::runtime_error("no table " + id);
}

TEST(ReportTables, RepeatedRunsShowMedianAndRange) {
    const Json r = results({render("u", "uniform", "Uniform", {4.0, 2.0, 3.0}, 0.0),
                            render("a", "aamap", "Selective", {1.0, 0.5, 0.75}, 0.25)});
    const auto tables = reportTables(r);
    const Table& time = table(tables, "time");
    ASSERT_EQ(time.rows.size(), 1u);
    EXPECT_EQ(time.rows[0][1], "3.000 (2.000–4.000)");  // uniform: median 3, runs 2..4
    EXPECT_EQ(time.rows[0][2], "1.000 (0.750–1.250)");  // trace median 0.75 + Snapshot 0.25
    // Speedup: 3/1 = 3; range: fastest baseline over slowest selective (2/1.25) to the reverse (4/0.75).
    const Table& speed = table(tables, "speedup");
    EXPECT_EQ(speed.rows[0][1], "3.00 (1.60–5.33)");
}

TEST(ReportTables, OneRunShowsNoRange) {
    const Json r = results({render("u", "uniform", "Uniform", {2.0}, 0.0), render("a", "aamap", "Selective", {1.0}, 0.0)});
    const auto tables = reportTables(r);
    EXPECT_EQ(table(tables, "time").rows[0][1], "2.000");
    EXPECT_EQ(table(tables, "speedup").rows[0][1], "2.00");
}

TEST(ReportTables, CsvCarriesTheSpread) {
    const Json r = results({render("u", "uniform", "Uniform", {4.0, 2.0, 3.0}, 0.0),
                            render("a", "aamap", "Selective", {1.0, 0.5, 0.75}, 0.25)});
    const std::string csv = resultsCsv(r);
    const auto columns = resultsCsvColumns();
    const auto column = [&](const std::string& name) {
        return static_cast<std::size_t>(std::find(columns.begin(), columns.end(), name) - columns.begin());
    };
    // The selective render's row (the third line).
    std::vector<std::string> lines;
    for (std::size_t start = 0, end; (end = csv.find('\n', start)) != std::string::npos; start = end + 1)
        lines.push_back(csv.substr(start, end - start));
    ASSERT_EQ(lines.size(), 3u);
    std::vector<std::string> fields;
    for (std::size_t start = 0, end = 0; end != std::string::npos; start = end + 1) {
        end = lines[2].find(',', start);
        fields.push_back(lines[2].substr(start, end == std::string::npos ? std::string::npos : end - start));
    }
    ASSERT_EQ(fields.size(), columns.size());
    EXPECT_EQ(fields[column("time_min_s")], "0.75");
    EXPECT_EQ(fields[column("time_max_s")], "1.25");
    EXPECT_EQ(fields[column("trace_runs")], "3");
    EXPECT_EQ(fields[column("speedup")], "3");
    EXPECT_EQ(fields[column("speedup_min")], "1.6");
    EXPECT_EQ(fields[column("speedup_max")], "5.33333333");
}

// The docs name every results.csv column and every light type a config may use.
TEST(ReportDocs, ListEveryCsvColumnAndLightType) {
    const auto read = [](const char* file) {
        std::ifstream in(std::string(AAMAP_SOURCE_DIR) + "/" + file);
        return std::string(std::istreambuf_iterator<char>(in), {});
    };
    const std::string experiments = read("docs/experiments.md");
    const std::size_t at = experiments.find("`results.csv` columns:");
    ASSERT_NE(at, std::string::npos);
    const std::string list = experiments.substr(at, experiments.find("\n\n", at) - at);
    for (const std::string& column : resultsCsvColumns()) EXPECT_NE(list.find(column), std::string::npos) << column;
    const std::string config = read("docs/config.md"), lights = read("docs/lights.md");
    const std::size_t lightFile = config.find("| `light_file` |");
    ASSERT_NE(lightFile, std::string::npos);
    const std::string row = config.substr(lightFile, config.find('\n', lightFile) - lightFile);
    const std::size_t typeRow = lights.find("| `type` |");
    ASSERT_NE(typeRow, std::string::npos);
    const std::string types = lights.substr(typeRow, lights.find('\n', typeRow) - typeRow);
    for (LightType t : {LightType::Point, LightType::Spot, LightType::Quad, LightType::Disk, LightType::Directional,
                        LightType::Environment}) {
        EXPECT_NE(types.find(fmt::format("`{}`", toString(t))), std::string::npos) << toString(t);
        EXPECT_NE(row.find(toString(t)), std::string::npos) << toString(t) << " not in " << row;
    }
}

}  // namespace
}  // namespace aamap
