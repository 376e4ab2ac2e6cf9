#include "eval/results.h"

#include <fstream>
#include <thread>
#include <unistd.h>

#include "core/atomic_file.h"

namespace aamap {

MachineInfo currentMachine() {
    MachineInfo m;
    char host[256] = {};
    if (::gethostname(host, sizeof(host) - 1) == 0) m.hostname = host;
    std::ifstream cpuinfo("/proc/cpuinfo");
    for (std::string line; std::getline(cpuinfo, line);) {
        if (line.starts_with("model name")) {
            const std::size_t colon = line.find(':');
            if (colon != std::string::npos) m.cpuModel = line.substr(line.find_first_not_of(" \t", colon + 1));
            break;
        }
    }
    if (m.cpuModel.empty()) m.cpuModel = "unknown";
    m.threads = static_cast<int>(std::thread::hardware_concurrency());
    return m;
}

namespace {
using Json = nlohmann::ordered_json;

Json passesJson(const std::vector<std::pair<std::string, double>>& passes) {
    Json j = Json::object();
    for (const auto& [pass, ms] : passes) j[pass] = ms;
    return j;
}

std::vector<std::pair<std::string, double>> passesFromJson(const Json& j) {
    std::vector<std::pair<std::string, double>> passes;
    for (const auto& [pass, ms] : j.items()) passes.emplace_back(pass, ms.get<double>());
    return passes;
}

}  // namespace

Json toJson(const MachineInfo& m) {
    return {{"hostname", m.hostname}, {"cpu_model", m.cpuModel}, {"threads", m.threads}};
}

// Snapshot records written before `threads` was kept lack it.
MachineInfo machineFromJson(const Json& j) {
    return {j.at("hostname").get<std::string>(), j.at("cpu_model").get<std::string>(), j.value("threads", 0)};
}

Json toJson(const RenderRecord& r) {
    Json j;
    j["name"] = r.name;
    j["series"] = r.series;
    j["key"] = r.key;
    j["cached"] = r.cached;
    j["scene"] = r.scene;
    j["view"] = r.view;
    j["width"] = r.width;
    j["height"] = r.height;
    j["strategy"] = r.strategy;
    j["parameters"] = r.parameters.is_null() ? Json::object() : r.parameters;
    j["max_rays_per_pixel"] = r.maxRaysPerPixel;
    j["times_s"] = {{"load", r.times.load},
                    {"bvh_build", r.times.bvhBuild},
                    {"snapshot_setup", r.times.snapshotSetup},
                    {"snapshot_total", r.times.snapshotTotal},
                    {"snapshot_passes_gpu_ms", passesJson(r.times.snapshotPassesGpuMs)},
                    {"readback", r.times.readback},
                    {"trace", r.times.trace},
                    {"trace_runs", r.times.traceRuns},
                    {"total", r.times.total}};
    j["rays"] = {{"primary", r.rays.primary}, {"shadow", r.rays.shadow}, {"other", r.rays.other},
                 {"total", r.rays.total()}};
    j["mean_primary_rpp"] = r.meanPrimaryRpp;
    j["non_finite_samples"] = r.nonFiniteSamples;
    j["git_revision"] = r.gitRevision;
    j["config_hash"] = r.configHash;
    j["vulkan_device"] = r.vulkanDevice;
    j["machine"] = toJson(r.machine);
    j["outputs"] = r.outputs;
    if (!r.metrics.is_null()) j["metrics"] = r.metrics;
    return j;
}

Json toJson(const SnapshotRecord& s) {
    return {{"key", s.key},
            {"width", s.width},
            {"height", s.height},
            {"total_s", s.totalSeconds},
            {"readback_s", s.readbackSeconds},
            {"setup_s", s.setupSeconds},
            {"passes_gpu_ms", passesJson(s.passesGpuMs)},
            {"vulkan_device", s.vulkanDevice},
            {"machine", toJson(s.machine)},
            {"git_revision", s.gitRevision},
            {"cached", s.cached}};
}

SnapshotRecord snapshotRecordFromJson(const Json& j) {
    SnapshotRecord s;
    s.key = j.at("key").get<std::string>();
    s.cached = j.value("cached", false);
    s.width = j.at("width").get<int>();
    s.height = j.at("height").get<int>();
    s.totalSeconds = j.at("total_s").get<double>();
    s.readbackSeconds = j.at("readback_s").get<double>();
    s.setupSeconds = j.value("setup_s", 0.0);  // absent in records written before it existed
    s.passesGpuMs = passesFromJson(j.at("passes_gpu_ms"));
    s.vulkanDevice = j.at("vulkan_device").get<std::string>();
    s.machine = machineFromJson(j.at("machine"));
    s.gitRevision = j.at("git_revision").get<std::string>();
    return s;
}

Json toJson(const ReferenceInfo& r) {
    Json j = {{"type", r.type}};
    if (r.rpp) j["rpp"] = *r.rpp;
    if (!r.mode.empty()) j["mode"] = r.mode;
    if (!r.path.empty()) j["path"] = r.path;
    if (!r.shadingFloor.empty()) j["shading_floor"] = r.shadingFloor;
    if (r.noise) j["noise"] = *r.noise;
    return j;
}

Json toJson(const Results& results) {
    Json j;
    j["format"] = "aamap-results-1";
    j["git_revision"] = results.gitRevision;
    j["config_hash"] = results.configHash;
    j["config"] = results.configJson.empty() ? Json::object() : Json::parse(results.configJson);
    j["renders"] = Json::array();
    for (const RenderRecord& r : results.renders) j["renders"].push_back(toJson(r));
    j["reference"] = results.referenceInfo.type.empty() ? Json::object() : toJson(results.referenceInfo);
    if (results.reference) j["reference"]["render"] = toJson(*results.reference);
    if (results.oneRay) j["one_ray"] = toJson(*results.oneRay);
    if (!results.mapQuality.is_null()) j["map_quality"] = results.mapQuality;
    if (results.snapshot) j["snapshot"] = toJson(*results.snapshot);
    if (results.oracle) {
        Json runs = Json::array();
        for (const OracleRun& o : results.oracle->runs) runs.push_back({{"map_render", o.mapRender}, {"render", toJson(o.record)}});
        j["oracle"] = {{"flagged_fraction", results.oracle->flaggedFraction},
                       {"rounds", results.oracle->rounds},
                       {"residual_pct_error_flip", results.oracle->residualErrorPercent},
                       {"runs", runs}};
    }
    j["warnings"] = results.warnings;
    return j;
}

RenderRecord recordFromJson(const Json& j) {
    RenderRecord r;
    r.name = j.at("name").get<std::string>();
    r.series = j.value("series", std::string());
    r.key = j.value("key", std::string());
    r.scene = j.at("scene").get<std::string>();
    r.view = j.at("view").get<std::string>();
    r.width = j.at("width").get<int>();
    r.height = j.at("height").get<int>();
    r.strategy = j.at("strategy").get<std::string>();
    r.parameters = j.at("parameters");
    r.maxRaysPerPixel = j.at("max_rays_per_pixel").get<int>();
    const auto& t = j.at("times_s");
    r.times.load = t.at("load").get<double>();
    r.times.bvhBuild = t.at("bvh_build").get<double>();
    r.times.snapshotSetup = t.value("snapshot_setup", 0.0);  // absent in records written before it existed
    r.times.snapshotTotal = t.at("snapshot_total").get<double>();
    r.times.snapshotPassesGpuMs = passesFromJson(t.at("snapshot_passes_gpu_ms"));
    r.times.readback = t.at("readback").get<double>();
    r.times.trace = t.at("trace").get<double>();
    // Records written before repeats existed hold one run: the trace itself.
    r.times.traceRuns = t.contains("trace_runs") ? t.at("trace_runs").get<std::vector<double>>()
                                                 : std::vector<double>{r.times.trace};
    r.times.total = t.at("total").get<double>();
    const auto& rays = j.at("rays");
    r.rays = {rays.at("primary").get<std::uint64_t>(), rays.at("shadow").get<std::uint64_t>(),
              rays.at("other").get<std::uint64_t>()};
    r.meanPrimaryRpp = j.at("mean_primary_rpp").get<double>();
    r.nonFiniteSamples = j.at("non_finite_samples").get<std::uint64_t>();
    r.gitRevision = j.at("git_revision").get<std::string>();
    r.configHash = j.at("config_hash").get<std::string>();
    r.vulkanDevice = j.at("vulkan_device").get<std::string>();
    r.machine = machineFromJson(j.at("machine"));
    r.outputs = j.at("outputs").get<std::vector<std::string>>();
    return r;
}

void writeResults(const std::filesystem::path& path, const Results& results) {
    writeTextAtomically(path, toJson(results).dump(2) + "\n");
}

}  // namespace aamap
