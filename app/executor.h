#pragma once
// How `aamap run` hands its renders to an executor that spreads them over machines: the work list
// it prints with --list-work, and --executor ray, which runs tools/ray_executor.py.
#include <filesystem>
#include <string>
#include <vector>

#include "eval/config.h"
#include "eval/experiment.h"

namespace aamap::app {

// What a worker passes to its own `aamap` to compute one item: the same config and overrides.
struct WorkerCommand {
    std::filesystem::path config;  // made absolute
    std::vector<std::string> overrides;
    int threads = -1;  // --threads, when given
    bool validation = false;
};

// --list-work's JSON: {"format", "cache": the cache folder, "items": [{kind, key, name, threads,
// needs_snapshot, group, args}]}; args is the command line after the binary, without --cache.
std::string workListJson(const Experiment& experiment, const std::filesystem::path& outDir, const RunOptions& options,
                         const WorkerCommand& worker);

// Replaces this process with tools/ray_executor.py under the venv's Python (AAMAP_PYTHON
// overrides), passing it this binary and the command line less --executor and --ray-address.
// Returns only by throwing EnvironmentError (no venv, no script, exec failed).
[[noreturn]] void execRayExecutor(int argc, char** argv, const std::string& rayAddress);

}  // namespace aamap::app
