#pragma once
// The report of an experiment, built from its results document (results.json) alone, so that
// `aamap report OUTDIR` can rebuild it: results.csv, report.md (the paper's tables in Markdown),
// report.html (tables, a comparison viewer, plots; relative links, opens from disk, offline), and the
// plots of tools/report_plots.py (run from the Python venv; skipped with a warning without one).
#include <cmath>
#include <filesystem>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

namespace aamap {

struct Table {
    std::string id;     // html anchor / file-safe
    std::string title;  // "Table 1: ..."
    std::string note;   // one line under the table
    std::vector<std::string> header;
    std::vector<std::vector<std::string>> rows;
};

// Tables 1-2 (time, speedup per rpp and series), Table 3 (% error pixels by FLIP and MSE), the
// per-render summary and map quality. A render's time is trace + snapshot_total: what its image
// cost, without the scene load and BVH build that every render shares.
std::vector<Table> reportTables(const nlohmann::ordered_json& results);

// Cost of a render's image (a results.json render record): the trace plus, for aamap-driven
// strategies, the Snapshot's per-frame time; 0 for a record without times.
double renderSeconds(const nlohmann::ordered_json& render);

// results.json's number at `key` of `j`; `fallback` when absent or not a number (a field a run
// left out).
double numberOr(const nlohmann::ordered_json& j, const char* key, double fallback = NAN);

// A number as people write it: the shortest text that reads back as the same float when the value
// is one (0.1, not 0.10000000149011612), else 3 significant digits ("1.23e+04" only past 1e6);
// "—" when not finite.
std::string readableNumber(double v);

// A CSV field, quoted (RFC 4180) when it holds a comma, a quote or a newline.
std::string csvField(const std::string& s);

// One row per render; the header is resultsCsvColumns().
std::string resultsCsv(const nlohmann::ordered_json& results);
const std::vector<std::string>& resultsCsvColumns();

// What the Snapshot cost (per frame, readback, setup, GPU per pass, device); none without a Snapshot.
std::optional<Table> snapshotCostTable(const nlohmann::ordered_json& results);

std::string markdownReport(const nlohmann::ordered_json& results, const std::vector<Table>& tables);
// One table as Markdown: a heading of that level, the table, the note.
std::string markdownTable(const Table& t, const std::string& heading = "##");

struct PlotRun {
    bool ran = false;
    std::string warning;             // why there are no plots ("" when they ran)
    std::vector<std::string> files;  // relative to OUTDIR, the plots that exist
};
// Runs tools/report_plots.py OUTDIR with the venv's Python (AAMAP_PYTHON overrides the
// interpreter, AAMAP_REPORT_PLOTS the script).
PlotRun runPlots(const std::filesystem::path& outDir);
// The same script's error-against-time plot of several runs (label, folder) into outDir/file.
PlotRun runComparisonPlot(const std::filesystem::path& outDir, const std::string& file, const std::string& title,
                          const std::vector<std::pair<std::string, std::filesystem::path>>& runs);

std::string htmlReport(const nlohmann::ordered_json& results, const std::vector<Table>& tables, const PlotRun& plots,
                       const std::filesystem::path& outDir);

// One table as HTML (heading, table, note), and text escaped for HTML: for other pages built from
// the same tables (eval/compare.h).
std::string htmlTable(const Table& t);
std::string htmlEscape(const std::string& s);

// Writes results.csv, report.md and report.html (atomically), running the plots first if asked.
void writeReport(const std::filesystem::path& outDir, const nlohmann::ordered_json& results, bool plots);

}  // namespace aamap
