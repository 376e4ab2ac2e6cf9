#pragma once
// results.json: one record per render with everything needed to reproduce and compare it
// (config hash, git revision, machine, device, stage times, ray counts).
#include <cstdint>
#include <filesystem>
#include <optional>
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
    double snapshotSetup = 0;  // once per Snapshot: pipelines, uploads, first use, debug read-back
    double snapshotTotal = 0;  // one execution of the Snapshot for what the strategy consumes
    std::vector<std::pair<std::string, double>> snapshotPassesGpuMs;  // pass -> GPU milliseconds
    double readback = 0;
    double trace = 0;                // the median of traceRuns
    std::vector<double> traceRuns;   // every timed run of the trace (timing.repeats), in order
    double total = 0;
};

struct RayTotals {
    std::uint64_t primary = 0, shadow = 0, other = 0;
    std::uint64_t total() const { return primary + shadow + other; }
};

struct RenderRecord {
    std::string name;
    std::string series;  // table column / plot curve
    std::string key;     // render cache key (eval/config.h renderKey)
    bool cached = false; // reused from an earlier run of this OUTDIR (results.json only)
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
    nlohmann::ordered_json metrics;    // against the reference (eval/evaluate.h); null when there is none
};

// The Snapshot's record (its cache entry's record.json, and results.json's "snapshot"): what one
// execution of the graph cost, on which device. Per frame is what every aamap-driven render adds.
struct SnapshotRecord {
    std::string key;      // render cache key (eval/config.h snapshotKey)
    bool cached = false;  // reused from an earlier run (results.json only)
    int width = 0, height = 0;
    double totalSeconds = 0, readbackSeconds = 0, setupSeconds = 0;  // as SnapshotOutput (eval/runner.h)
    std::vector<std::pair<std::string, double>> passesGpuMs;      // pass -> GPU milliseconds
    std::string vulkanDevice;
    MachineInfo machine;
    std::string gitRevision;
};

// What the errors are measured against.
struct ReferenceInfo {
    std::string type;          // reference.type: uniform, file or none
    std::optional<int> rpp;    // uniform: its rays per pixel
    std::string mode;          // uniform: its shading mode
    std::string path;          // file: the resolved path
    std::string shadingFloor;  // the render whose error is the shading bias alone ("" when none)
    // A traced reference's own convergence, from two independent half images of its samples
    // (eval/evaluate.h estimateReferenceNoise); absent for a file, or a reference of 1 ray.
    std::optional<nlohmann::ordered_json> noise;
};

// An aamap-driven render traced again on the oracle map: the rays the reference says a pixel
// needs, so its speedup and error bound what any map can reach with that strategy.
struct OracleRun {
    std::string mapRender;  // the listed render it repeats, on the Snapshot's map
    RenderRecord record;    // named "oracle_<mapRender>"; no Snapshot cost
};

struct OracleResults {
    double flaggedFraction = 0;       // of the oracle map's pixels
    int rounds = 0;                   // eval/evaluate.h OracleMap
    double residualErrorPercent = 0;  // % FLIP error pixels of its last composite
    std::vector<OracleRun> runs;
};

struct Results {
    std::string gitRevision;
    std::string configHash;
    std::string configJson;  // ExperimentConfig::canonicalJson()
    std::vector<RenderRecord> renders;
    std::optional<RenderRecord> reference;  // the traced reference, when there is one
    std::optional<RenderRecord> oneRay;     // the 1-ray uniform render behind map quality
    ReferenceInfo referenceInfo;
    nlohmann::ordered_json mapQuality;      // eval/evaluate.h evaluateMap; null unless requested and possible
    std::optional<SnapshotRecord> snapshot; // none without the aamap
    std::optional<OracleResults> oracle;    // metrics.oracle
    std::vector<std::string> warnings;      // shown at the top of the report
};

nlohmann::ordered_json toJson(const MachineInfo& machine);
nlohmann::ordered_json toJson(const RenderRecord& record);
nlohmann::ordered_json toJson(const SnapshotRecord& record);
nlohmann::ordered_json toJson(const ReferenceInfo& reference);
nlohmann::ordered_json toJson(const Results& results);
// Inverses of toJson (for cached records). Throw nlohmann::json::exception.
MachineInfo machineFromJson(const nlohmann::ordered_json& j);
RenderRecord recordFromJson(const nlohmann::ordered_json& j);
SnapshotRecord snapshotRecordFromJson(const nlohmann::ordered_json& j);
// Pretty-printed, written atomically.
void writeResults(const std::filesystem::path& path, const Results& results);

}  // namespace aamap
