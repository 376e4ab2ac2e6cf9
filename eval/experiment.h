#pragma once
// One experiment run: load the scene, render the Snapshot and its aamap on the GPU, trace every
// render in the config, and write images plus results.json into the output folder.
#include <filesystem>
#include <stdexcept>
#include <string>

#include "eval/config.h"
#include "eval/results.h"

namespace aamap {

struct RunOptions {
    bool validation = false;  // Khronos validation layer; any warning or error fails the run
    std::string device;       // ContextOptions::device ("" picks the best GPU)
    int threads = -1;         // >= 0 overrides the config's `threads`
    std::string gitRevision = "unknown";
    bool plots = true;  // false: --no-plots
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

}  // namespace aamap
