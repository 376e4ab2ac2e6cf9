#pragma once
// `aamap compare OUTDIR... -o OUT`: several finished runs (the same scene with other settings, or
// other scenes) side by side. Each run's results.json is read as it is; what differs between the
// runs' configs (every setting but the renders and the thread count) becomes the columns that
// tell the runs apart. Writes OUT/compare.csv (every render of every run, with those columns in
// front of results.csv's), OUT/compare.md and OUT/compare.html (per scene, then per run: the
// run's own tables, its speedups within the run), atomically.
#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace aamap {

struct ComparedRun {
    std::filesystem::path dir;
    nlohmann::ordered_json results;
    std::vector<std::pair<std::string, std::string>> differs;  // key -> this run's value
    std::string label;  // "snapshot.blur_radius=2", or the folder's name when nothing differs
};

// Reads each dir/results.json (InputError naming the file when missing or malformed) and works
// out the settings that differ between them. Needs at least one folder.
std::vector<ComparedRun> loadComparedRuns(const std::vector<std::filesystem::path>& dirs);

std::string compareCsv(const std::vector<ComparedRun>& runs);
std::string compareMarkdown(const std::vector<ComparedRun>& runs);
std::string compareHtml(const std::vector<ComparedRun>& runs, const std::filesystem::path& outDir);

// The names of the three files (`aamap compare`'s; a sweep's comparison is its report).
struct ComparisonFiles {
    std::string html = "compare.html", markdown = "compare.md", csv = "compare.csv";
};

// All of the above into outDir (created if needed).
void writeComparison(const std::vector<std::filesystem::path>& dirs, const std::filesystem::path& outDir,
                     const ComparisonFiles& files = {});

}  // namespace aamap
