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

nlohmann::ordered_json toJson(const RenderRecord& r) {
    using Json = nlohmann::ordered_json;
    Json passes = Json::object();
    for (const auto& [pass, ms] : r.times.snapshotPassesGpuMs) passes[pass] = ms;
    Json j;
    j["name"] = r.name;
    j["scene"] = r.scene;
    j["view"] = r.view;
    j["width"] = r.width;
    j["height"] = r.height;
    j["strategy"] = r.strategy;
    j["parameters"] = r.parameters.is_null() ? Json::object() : r.parameters;
    j["max_rays_per_pixel"] = r.maxRaysPerPixel;
    j["times_s"] = {{"load", r.times.load},
                    {"bvh_build", r.times.bvhBuild},
                    {"snapshot_total", r.times.snapshotTotal},
                    {"snapshot_passes_gpu_ms", passes},
                    {"readback", r.times.readback},
                    {"trace", r.times.trace},
                    {"total", r.times.total}};
    j["rays"] = {{"primary", r.rays.primary}, {"shadow", r.rays.shadow}, {"other", r.rays.other},
                 {"total", r.rays.total()}};
    j["mean_primary_rpp"] = r.meanPrimaryRpp;
    j["non_finite_samples"] = r.nonFiniteSamples;
    j["git_revision"] = r.gitRevision;
    j["config_hash"] = r.configHash;
    j["vulkan_device"] = r.vulkanDevice;
    j["machine"] = {{"hostname", r.machine.hostname}, {"cpu_model", r.machine.cpuModel}, {"threads", r.machine.threads}};
    j["outputs"] = r.outputs;
    return j;
}

nlohmann::ordered_json toJson(const Results& results) {
    using Json = nlohmann::ordered_json;
    Json j;
    j["format"] = "aamap-results-1";
    j["git_revision"] = results.gitRevision;
    j["config_hash"] = results.configHash;
    j["config"] = results.configJson.empty() ? Json::object() : Json::parse(results.configJson);
    j["renders"] = Json::array();
    for (const RenderRecord& r : results.renders) j["renders"].push_back(toJson(r));
    return j;
}

void writeResults(const std::filesystem::path& path, const Results& results) {
    writeTextAtomically(path, toJson(results).dump(2) + "\n");
}

}  // namespace aamap
