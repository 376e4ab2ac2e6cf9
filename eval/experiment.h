#pragma once
// One experiment run: load the scene, render the Snapshot and its aamap on the GPU, trace every
// render in the config, and write images plus results.json into the output folder.
#include <filesystem>
#include <optional>
#include <utility>
#include <stdexcept>
#include <string>

#include "eval/config.h"
#include "eval/results.h"
#include "eval/runner.h"
#include "passes/snapshot.h"
#include "scene/scene.h"
#include "tracer/tracer_types.h"

namespace aamap {

struct RunOptions {
    bool validation = false;  // Khronos validation layer; any warning or error fails the run
    std::string device;       // ContextOptions::device ("" picks the best GPU)
    int threads = -1;         // >= 0 overrides the config's `threads`
    std::string gitRevision = "unknown";
    bool plots = true;  // false: --no-plots
    std::filesystem::path cacheDir;  // the render cache; empty: OUTDIR/cache
};

// The run worked, but the Vulkan validation layer reported problems (the messages were already
// logged as they arrived). The app exits with code 3.
class ValidationFailure : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

// Runs eval/runner.h with the real backend (scene, Vulkan Snapshot, Embree tracer).
// Throws InputError (bad scene, view, ...), EnvironmentError (no device, cannot write) or
// ValidationFailure. Every render is committed to OUTDIR/cache as it finishes, so a killed run
// resumes where it stopped.
Results runExperiment(const ExperimentConfig& config, const std::filesystem::path& outDir, const RunOptions& options);

// Every variant of a swept experiment with the real backend (eval/sweep_runner.h); one variant
// without sweeps runs as runExperiment.
// Every variant's inputs are checked (checkInputs) before the first one runs.
void runSweptExperiment(const Experiment& experiment, const std::filesystem::path& outDir, const RunOptions& options);

// What can be checked of a config's inputs without loading its scene, so that a bad one fails
// before any work: the scene file exists or the built-in name is known (did-you-mean), the view
// file loads and view_index is within it, a camera is valid. Throws InputError naming the
// config's line.
void checkInputs(const ExperimentConfig& config);

// The render size when the scene is not needed for it (a camera or view file in the config, and
// an image box that no Mitsuba film replaces); nullopt otherwise.
std::optional<std::pair<int, int>> renderSizeWithoutScene(const ExperimentConfig& config);

// The render cache every variant of the experiment shares: options.cacheDir, else OUTDIR/cache.
std::filesystem::path experimentCacheDir(const std::filesystem::path& outDir, const RunOptions& options);

// `aamap run --list-work`: every Snapshot and render of every variant that the cache lacks, each
// key once (work an executor spreads over machines, eval/runner.h WorkItem).
std::vector<WorkItem> listMissingWork(const Experiment& experiment, const std::filesystem::path& outDir,
                                      const RunOptions& options);

// `aamap run --only KEY`: computes the one item KEY, of whichever variant has it, into the cache
// (experimentCacheDir) with the real backend. InputError when no variant has it.
void computeExperimentItem(const Experiment& experiment, const std::string& key, const std::filesystem::path& outDir,
                           const RunOptions& options);

// The setup `aamap run` and `aamap view` share, so both render exactly the same thing: the scene
// with the config's lights, the chosen view, and the render size that view fits into image.*.
struct PreparedScene {
    Scene scene;
    View view;
    std::string viewLabel;
    int width = 0, height = 0;
    double loadSeconds = 0;
};
PreparedScene prepareScene(const ExperimentConfig& config);  // throws InputError naming the config line
// The config with what the scene file decides where the config is silent (a Mitsuba integrator's
// max_depth, rr_depth and hide_emitters), and in `notes` one sentence per render setting of the
// file: applied, or not applied and why (its sample count, pixel filter).
ExperimentConfig withSceneRenderSettings(const ExperimentConfig& config, const Scene& scene,
                                         std::vector<std::string>& notes);
// snapshot.* (and image.exposure for the greyscale) as the Snapshot's settings.
SnapshotSettings snapshotSettingsFor(const ExperimentConfig& config);
// One render's tracer settings at width x height; threads >= 0 overrides the config's.
TraceSettings traceSettingsFor(const ExperimentConfig& config, const RenderConfig& render, int width, int height,
                               int threads);

}  // namespace aamap
