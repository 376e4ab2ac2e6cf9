#include "eval/sweep_runner.h"

#include <cstdint>
#include <fstream>
#include <set>

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <nlohmann/json.hpp>
#include <spdlog/spdlog.h>

#include "core/atomic_file.h"
#include "core/error.h"
#include "core/log.h"
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

std::string planText(const Experiment& experiment, const fs::path& outDir, const fs::path& cacheDir) {
    const fs::path cache = cacheDir.empty() ? outDir / "cache" : cacheDir;
    const auto duration = [](const std::optional<double>& s) { return s ? formatDuration(*s) : std::string("unknown"); };
    std::string text = fmt::format("plan: {} variant(s) into {}, cache {} (nothing is traced or written)\n",
                                   experiment.variants.size(), outDir.string(), cache.string());
    std::set<std::string> counted;  // renders that variants share are traced once
    int toTrace = 0, unknown = 0;
    double seconds = 0, rays = 0;
    for (std::size_t i = 0; i < experiment.variants.size(); ++i) {
        const ExperimentConfig& c = experiment.variants[i];
        const RunPlan plan = planRun(c, cache);
        std::vector<std::string> parts;
        for (std::size_t k = 0; k < experiment.sweptKeys.size(); ++k)
            parts.push_back(experiment.sweptKeys[k] + "=" + experiment.sweptValues[i][k]);
        text += fmt::format("\nvariant {}/{}{}: scene {}, {}x{}, {} shading{}\n", i + 1, experiment.variants.size(),
                            parts.empty() ? "" : fmt::format(" ({})", fmt::join(parts, ", ")), c.scene, c.image.width,
                            c.image.height, toString(c.shading.mode),
                            plan.repeats > 1 ? fmt::format(", {} timed runs each", plan.repeats) : "");
        if (plan.usesSnapshot)
            text += fmt::format("  {:<24} {:<16} {:>5}  {:>14}  {:<6}  {}\n", "snapshot", "", "", "",
                                plan.snapshotCached ? "cached" : "to run", plan.snapshotKey);
        text += fmt::format("  {:<24} {:<16} {:>5}  {:>14}  {:<6}  {}\n", "render", "strategy", "rpp", "rays (at most)",
                            "cache", "time");
        for (const PlannedRender& r : plan.renders) {
            const double budget = static_cast<double>(r.rpp) * plan.pixels;
            text += fmt::format("  {:<24} {:<16} {:>5}  {:>14}  {:<6}  {}{}\n", r.name, r.strategy, r.rpp,
                                static_cast<std::uint64_t>(budget), r.cached ? "cached" : "trace",
                                r.cached || !r.seconds ? "" : "about ", duration(r.seconds));
            if (r.cached || !counted.insert(r.key).second) continue;
            ++toTrace;
            rays += budget * plan.repeats;
            if (r.seconds) seconds += *r.seconds * plan.repeats;
            else ++unknown;
        }
        if (!plan.secondsPerRayUnit)
            text += "  (no render of this variant is cached yet: its times are unknown until one is)\n";
    }
    text += fmt::format("\n{} trace(s) to do, {} primary rays at most", toTrace, static_cast<std::uint64_t>(rays));
    if (toTrace > 0)
        text += unknown == 0 ? fmt::format(", about {}", formatDuration(seconds))
                             : fmt::format(", {} of them of unknown time{}", unknown,
                                           seconds > 0 ? fmt::format(" (the others about {})", formatDuration(seconds)) : "");
    return text + "\n";
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
