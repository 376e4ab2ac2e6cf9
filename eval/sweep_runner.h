#pragma once
// Runs a swept experiment (eval/config.h Experiment): every variant into OUTDIR/<its folder>, all
// with one render cache (OUTDIR/cache), so what variants share is traced once; then
// OUTDIR/report.html, report.md and results.csv compare the variants (eval/compare.h), grouped by
// scene, and OUTDIR/sweep.json lists them so that `aamap report OUTDIR` can rebuild everything.
#include <filesystem>
#include <functional>
#include <memory>

#include "eval/config.h"
#include "eval/runner.h"

namespace aamap {

using BackendFactory = std::function<std::unique_ptr<RenderBackend>(const ExperimentConfig&)>;

void runSweepWith(const Experiment& experiment, const std::filesystem::path& outDir, const BackendFactory& backend,
                  const RunnerOptions& options);

// `aamap run CONFIG --plan`: the variants, each one's Snapshot and renders, what the cache holds
// already, the rays each render may trace and its time (measured for a cached render; estimated
// from the cached renders' rate for the others, when there are some). Reads the cache only:
// loads no scene, traces nothing, writes nothing.
std::string planText(const Experiment& experiment, const std::filesystem::path& outDir,
                     const std::filesystem::path& cacheDir);

// `aamap report OUTDIR`: the report of one run (OUTDIR/results.json), or of every variant of a
// sweep and their comparison (OUTDIR/sweep.json). InputError when neither is there.
void rebuildReport(const std::filesystem::path& outDir, bool plots);

}  // namespace aamap
