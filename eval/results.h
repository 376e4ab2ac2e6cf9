#pragma once
// results.json: one record per render with everything needed to reproduce and compare it
// (config hash, git revision, machine, device, stage times, ray counts).
#include <cstdint>
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

namespace aamap {

struct MachineInfo {
    std::string hostname;
    std::string cpuModel;
    int threads = 0;  // hardware threads
};
MachineInfo currentMachine();

// Seconds unless named otherwise. A record carries the stages its image needed: a strategy that
// does not use the aamap has no snapshot cost. `total` is the sum of the stages that apply.
struct StageTimes {
    double load = 0;
    double bvhBuild = 0;
    double snapshotTotal = 0;
    std::vector<std::pair<std::string, double>> snapshotPassesGpuMs;  // pass -> GPU milliseconds
    double readback = 0;
    double trace = 0;
    double total = 0;
};

struct RayTotals {
    std::uint64_t primary = 0, shadow = 0, other = 0;
    std::uint64_t total() const { return primary + shadow + other; }
};

struct RenderRecord {
    std::string name;
    std::string scene;  // the spec loaded ("builtin:cornell" or a resolved path)
    std::string view;   // view name, or "<file>#<index>"
    int width = 0, height = 0;
    std::string strategy;
    nlohmann::ordered_json parameters;  // strategy parameters (strata, snapshot settings, ...)
    int maxRaysPerPixel = 0;            // n*n
    StageTimes times;
    RayTotals rays;
    double meanPrimaryRpp = 0;
    std::uint64_t nonFiniteSamples = 0;
    std::string gitRevision;
    std::string configHash;
    std::string vulkanDevice;  // "" when the strategy did not use the GPU
    MachineInfo machine;
    std::vector<std::string> outputs;  // file names written for this render, relative to OUTDIR
};

struct Results {
    std::string gitRevision;
    std::string configHash;
    std::string configJson;  // ExperimentConfig::canonicalJson()
    std::vector<RenderRecord> renders;
};

nlohmann::ordered_json toJson(const RenderRecord& record);
nlohmann::ordered_json toJson(const Results& results);
// Pretty-printed, written atomically.
void writeResults(const std::filesystem::path& path, const Results& results);

}  // namespace aamap
