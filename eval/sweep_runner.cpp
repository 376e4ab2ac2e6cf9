#include "eval/sweep_runner.h"

#include <fstream>
#include <set>

#include <fmt/format.h>
#include <nlohmann/json.hpp>
#include <spdlog/spdlog.h>

#include "core/atomic_file.h"
#include "core/error.h"
#include "eval/compare.h"
#include "eval/report.h"

namespace aamap {
namespace fs = std::filesystem;
using Json = nlohmann::ordered_json;

namespace {

const ComparisonFiles kSweepFiles{"report.html", "report.md", "results.csv"};

Json readJsonFile(const fs::path& file) {
    std::ifstream in(file);
    if (!in) throw InputError(file, "cannot read (run the experiment first)");
    try {
        return Json::parse(in);
    } catch (const nlohmann::json::exception& e) {
        throw InputError(file, e.what());
    }
}

}  // namespace

void runSweepWith(const Experiment& experiment, const fs::path& outDir, const BackendFactory& backend,
                  const RunnerOptions& options) {
    RunnerOptions ro = options;
    if (ro.cacheDir.empty()) ro.cacheDir = outDir / "cache";
    Json sweep = {{"format", "aamap-sweep-1"}, {"swept_keys", experiment.sweptKeys}, {"variants", Json::array()}};
    // One time-left estimate over the whole sweep: every variant's missing traces planned first.
    WorkEstimate estimate;
    std::set<std::string> planned;
    for (const ExperimentConfig& variant : experiment.variants) planWork(variant, ro.cacheDir, estimate, planned);
    if (experiment.variants.size() > 1) ro.estimate = &estimate;
    std::vector<fs::path> dirs;
    for (std::size_t i = 0; i < experiment.variants.size(); ++i) {
        std::vector<std::string> parts;
        for (std::size_t k = 0; k < experiment.sweptKeys.size(); ++k)
            parts.push_back(experiment.sweptKeys[k] + "=" + experiment.sweptValues[i][k]);
        spdlog::info("variant {}/{}: {} -> {}", i + 1, experiment.variants.size(), fmt::join(parts, ", "),
                     (outDir / experiment.folders[i]).string());
        const std::unique_ptr<RenderBackend> b = backend(experiment.variants[i]);
        runExperimentWith(experiment.variants[i], outDir / experiment.folders[i], *b, ro);
        dirs.push_back(outDir / experiment.folders[i]);
        sweep["variants"].push_back({{"folder", experiment.folders[i]}, {"values", experiment.sweptValues[i]}});
        writeTextAtomically(outDir / "sweep.json", sweep.dump(2) + "\n");  // the finished ones so far
    }
    writeComparison(dirs, outDir, kSweepFiles, ro.plots && experiment.variants.front().report.plots);
}

void rebuildReport(const fs::path& outDir, bool plots) {
    if (!fs::is_regular_file(outDir / "sweep.json")) {
        writeReport(outDir, readJsonFile(outDir / "results.json"), plots);
        return;
    }
    const std::vector<fs::path> dirs = experimentFolders(outDir);
    for (const fs::path& dir : dirs) writeReport(dir, readJsonFile(dir / "results.json"), plots);
    writeComparison(dirs, outDir, kSweepFiles, plots);
}

}  // namespace aamap
