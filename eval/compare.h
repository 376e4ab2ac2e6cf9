#pragma once
// `aamap compare OUTDIR... -o OUT`: several finished runs (the same scene with other settings, or
// other scenes) side by side. Each run's results.json is read as it is; what differs between the
// runs' configs (every setting but the renders and the thread count) becomes the columns that
// tell the runs apart. Writes OUT/compare.csv (every render of every run, with those columns in
// front of results.csv's), OUT/compare.md and OUT/compare.html (per scene: the renders on the
// time-error Pareto front over all its runs, and their error-against-time plot; then per run: the
// run's own tables, its speedups within the run), atomically.
#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "eval/report.h"

namespace aamap {

struct ComparedRun {
    std::filesystem::path dir;
    nlohmann::ordered_json results;
    std::vector<std::pair<std::string, std::string>> differs;  // key -> this run's value, in full
    // The same values short: a path's last two parts, a list or mapping (inline lights) as #1, #2
    // in order of first appearance.
    std::vector<std::pair<std::string, std::string>> shortDiffers;
    // "snapshot.blur_radius=2": the short values of the keys that differ, the scene left out where
    // other keys differ too (the report groups runs by scene); the folder's name when none does.
    std::string label;
};

// The experiment folders `dir` stands for: a sweep's output folder (it holds sweep.json) stands for
// its variants' folders, in sweep order; any other folder for itself. InputError names sweep.json
// when it is malformed.
std::vector<std::filesystem::path> experimentFolders(const std::filesystem::path& dir);

// Reads each dir/results.json (InputError naming the file when missing or malformed) and works
// out the settings that differ between them; a sweep's folder counts as all its variants (so a
// sweep compares with another sweep or a single run). Needs at least one folder.
std::vector<ComparedRun> loadComparedRuns(const std::vector<std::filesystem::path>& dirs);

// The renders of one scene's runs that no other render beats in both time and error (% pixels above
// the FLIP threshold, else above the MSE threshold), fastest first: the best setting at each error
// level, whatever run, shading mode or strategy it comes from. Time = trace + Snapshot.
Table paretoTable(const std::vector<const ComparedRun*>& sceneRuns, std::size_t sceneIndex = 0);

// The first table of a comparison (a sweep's report): a row per run, a column per key that
// differs (short values), then its headline figures: per series that is not the baseline, its
// speedup over the baseline and its % error pixels at the largest rpp both have, the baseline's
// error there, the map's recall, precision and flagged share, and the time of all its renders.
Table summaryTable(const std::vector<ComparedRun>& runs);

// Which run won, per series that is not the baseline, among one scene's runs: the fastest whose
// error at that rpp is within kEqualErrorPoints of the lowest any of them reaches. One sentence
// per series; none without a baseline or an error figure.
inline constexpr double kEqualErrorPoints = 0.1;
std::vector<std::string> winners(const std::vector<const ComparedRun*>& sceneRuns);

std::string compareCsv(const std::vector<ComparedRun>& runs);
// Per scene with several runs: the Pareto front of time against error over all their renders, and
// scenePlots[scene index] (relative to the output folder; "" or missing: no plot).
std::string compareMarkdown(const std::vector<ComparedRun>& runs, const std::vector<std::string>& scenePlots = {});
std::string compareHtml(const std::vector<ComparedRun>& runs, const std::filesystem::path& outDir,
                        const std::vector<std::string>& scenePlots = {});

// The names of the three files (`aamap compare`'s; a sweep's comparison is its report).
struct ComparisonFiles {
    std::string html = "compare.html", markdown = "compare.md", csv = "compare.csv";
};

// All of the above into outDir (created if needed), with the plots of tools/report_plots.py
// --compare in outDir/plots/ when `plots`.
void writeComparison(const std::vector<std::filesystem::path>& dirs, const std::filesystem::path& outDir,
                     const ComparisonFiles& files = {}, bool plots = true);

}  // namespace aamap
