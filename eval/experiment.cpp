#include "eval/experiment.h"

#include <algorithm>
#include <chrono>
#include <memory>
#include <numeric>
#include <optional>

#include <fmt/format.h>
#include <glm/geometric.hpp>
#include <spdlog/spdlog.h>

#include "core/error.h"
#include "core/image_io.h"
#include "core/log.h"
#include "engine/vk/context.h"
#include "passes/snapshot.h"
#include "scene/camera.h"
#include "scene/load_scene.h"
#include "scene/view_file.h"
#include "tracer/tracer.h"

namespace aamap {
namespace {

using Clock = std::chrono::steady_clock;

double secondsSince(Clock::time_point start) {
    return std::chrono::duration<double>(Clock::now() - start).count();
}

// Loader errors without a line are about the spec itself ("no such file"): point at the config
// line that named it. Errors inside the scene file keep their own file:line.
Scene loadSceneFor(const ExperimentConfig& config) {
    try {
        return loadScene(config.resolvedScene());
    } catch (const InputError& e) {
        if (e.line() > 0) throw;
        const SourceLocation& at = config.sceneLocation;
        throw InputError(at.file, at.line, at.column, fmt::format("scene '{}': {}", config.scene, e.what()));
    }
}

View pickView(const ExperimentConfig& config, const Scene& scene, std::string& label) {
    std::vector<View> views;
    std::string source;
    if (const auto file = config.resolvedView()) {
        try {
            views = loadViewFile(*file);
        } catch (const InputError& e) {
            if (e.line() > 0) throw;
            const SourceLocation& at = config.viewLocation;
            throw InputError(at.file, at.line, at.column, fmt::format("view '{}': {}", *config.view, e.what()));
        }
        source = file->filename().string();
    } else {
        views = scene.views;
        source = scene.name.empty() ? config.scene : scene.name;
    }
    const SourceLocation& at = config.viewIndexLocation;
    if (views.empty())
        throw InputError(config.viewLocation.file, config.viewLocation.line, config.viewLocation.column,
                         fmt::format("{} has no view; set 'view' to a Radiance .vf file", source));
    if (config.viewIndex >= static_cast<int>(views.size()))
        throw InputError(at.file, at.line, at.column,
                         fmt::format("view_index {} is out of range: {} has {} view(s)", config.viewIndex, source,
                                     views.size()));
    const View& view = views[static_cast<std::size_t>(config.viewIndex)];
    label = view.name.empty() ? fmt::format("{}#{}", source, config.viewIndex) : view.name;
    return view;
}

glm::vec3 toVec3(const std::array<double, 3>& a) {
    return {static_cast<float>(a[0]), static_cast<float>(a[1]), static_cast<float>(a[2])};
}

void addConfigLights(const ExperimentConfig& config, Scene& scene) {
    for (const LightConfig& l : config.lights) {
        PointLight light;
        light.name = l.name;
        light.position = toVec3(l.position);
        light.intensity = toVec3(l.intensity);
        const glm::vec3 n = toVec3(l.normal);
        light.normal = glm::length(n) > 0.0f ? glm::normalize(n) : glm::vec3(0.0f);
        scene.pointLights.push_back(light);
    }
}

SnapshotSettings snapshotSettings(const ExperimentConfig& c) {
    SnapshotSettings s;
    s.scale = static_cast<float>(c.snapshot.scale);
    s.areaLightSamples = c.snapshot.areaLightSamples;
    s.filter.exposure = static_cast<float>(c.image.exposure);  // edges as the viewer will see them
    s.filter.blurRadius = c.snapshot.blurRadius;
    s.filter.noiseFloor = static_cast<float>(c.snapshot.noiseFloor);
    s.filter.gain = static_cast<float>(c.snapshot.gain);
    s.keepDebugImages = true;
    return s;
}

struct SnapshotOutcome {
    SnapshotResult result;
    std::string device;
};

SnapshotOutcome renderSnapshot(const ExperimentConfig& config, const Scene& scene, const View& view, int width,
                               int height, const RunOptions& options, const std::filesystem::path& outDir) {
    SnapshotOutcome out;
    auto context = std::make_unique<VulkanContext>(ContextOptions{options.validation, options.device});
    if (options.validation && !context->validationEnabled())
        throw EnvironmentError("validation was requested but VK_LAYER_KHRONOS_validation is not available");
    out.device = context->deviceName();
    spdlog::info("snapshot on '{}' at {}x{} (scale {})", out.device, width, height, config.snapshot.scale);
    {
        SnapshotRenderer renderer(*context, scene);
        out.result = renderer.render(view, width, height, snapshotSettings(config));
    }  // GPU objects freed here, so their destruction is validated too
    const float exposure = static_cast<float>(config.image.exposure);
    if (!out.result.snapshot.empty()) writePng(outDir / "snapshot.png", toneMap(out.result.snapshot, exposure));
    if (!out.result.laplacian.empty()) writePng(outDir / "laplacian.png", quantise(out.result.laplacian));
    writeExr(outDir / "aamap.exr", out.result.aamap);
    writePng(outDir / "aamap.png", quantise(out.result.aamap));
    if (context->validationEnabled() && context->validationMessageCount() > 0)
        throw ValidationFailure(fmt::format("{} Vulkan validation message(s), logged above",
                                            context->validationMessageCount()));
    const std::size_t flagged = static_cast<std::size_t>(
        std::count_if(out.result.aamap.pixels().begin(), out.result.aamap.pixels().end(), [](float v) { return v > 0; }));
    spdlog::info("snapshot: {:.1f} ms, aamap flags {:.1f}% of pixels", out.result.totalSeconds * 1e3,
                 100.0 * static_cast<double>(flagged) / static_cast<double>(std::max<std::size_t>(1, out.result.aamap.size())));
    return out;
}

StrategyKind strategyKind(const std::string& name) {
    if (name == "uniform") return StrategyKind::Uniform;
    if (name == "aamap") return StrategyKind::Aamap;
    throw InputError("config", fmt::format("unknown strategy '{}'", name));  // parseConfig rejects these first
}

}  // namespace

Results runExperiment(const ExperimentConfig& config, const std::filesystem::path& outDir, const RunOptions& options) {
    const auto runStart = Clock::now();
    Results results;
    results.gitRevision = options.gitRevision;
    results.configHash = config.hash();
    results.configJson = config.canonicalJson();

    std::error_code ec;
    std::filesystem::create_directories(outDir, ec);
    if (ec) throw EnvironmentError(fmt::format("{}: cannot create output folder: {}", outDir.string(), ec.message()));

    spdlog::info("loading scene {}", config.resolvedScene());
    auto t0 = Clock::now();
    Scene scene = loadSceneFor(config);
    addConfigLights(config, scene);
    const double loadSeconds = secondsSince(t0);
    std::string viewLabel;
    const View view = pickView(config, scene, viewLabel);
    const auto [width, height] = fitResolution(view, config.image.width, config.image.height);
    spdlog::info("scene '{}': {} triangles, {} area + {} point lights; view {} at {}x{} ({:.2f} s)", scene.name,
                 scene.mesh.triangles.size(), scene.areaLights.size(), scene.pointLights.size(), viewLabel, width,
                 height, loadSeconds);

    // The GPU is only needed when some render is driven by the aamap.
    const bool needSnapshot = std::any_of(config.renders.begin(), config.renders.end(),
                                          [](const RenderConfig& r) { return r.strategy == "aamap"; });
    std::optional<SnapshotOutcome> snapshot;
    if (needSnapshot) snapshot = renderSnapshot(config, scene, view, width, height, options, outDir);
    else spdlog::info("no render uses the aamap: snapshot skipped");

    spdlog::info("building BVH");
    const Tracer tracer(scene);
    const double bvhSeconds = tracer.bvhBuildSeconds();
    const MachineInfo machine = currentMachine();
    const float exposure = static_cast<float>(config.image.exposure);

    for (const RenderConfig& r : config.renders) {
        const StrategyKind kind = strategyKind(r.strategy);
        TraceSettings ts;
        ts.width = width;
        ts.height = height;
        ts.seed = config.seed;
        ts.threads = options.threads >= 0 ? options.threads : config.threads;
        ts.shading.areaLightSamples = config.shading.areaLightSamples;
        Progress progress(fmt::format("trace {}", r.name));
        ts.onTileDone = [&progress](int done, int total) { progress.update(done, total); };
        StrategySettings ss;
        ss.kind = kind;
        ss.strata = r.strata();
        ss.aamap = kind == StrategyKind::Aamap ? &snapshot->result.aamap : nullptr;

        const TraceResult tr = tracer.render(view, ts, ss);
        progress.finish();
        writeExr(outDir / (r.name + ".exr"), tr.image);
        writePng(outDir / (r.name + ".png"), toneMap(tr.image, exposure));
        writePng(outDir / (r.name + ".rpp.png"), falseColour(tr.primaryRays, r.rpp));

        RenderRecord rec;
        rec.name = r.name;
        rec.scene = config.resolvedScene();
        rec.view = viewLabel;
        rec.width = width;
        rec.height = height;
        rec.strategy = r.strategy;
        rec.parameters = {{"rpp", r.rpp}, {"strata", r.strata()}, {"seed", config.seed},
                          {"shading_area_light_samples", config.shading.areaLightSamples}};
        rec.maxRaysPerPixel = r.rpp;
        rec.times.load = loadSeconds;
        rec.times.bvhBuild = bvhSeconds;
        rec.times.trace = tr.seconds;
        if (kind == StrategyKind::Aamap) {
            const SnapshotResult& s = snapshot->result;
            rec.parameters["snapshot"] = nlohmann::ordered_json::parse(config.canonicalJson())["snapshot"];
            rec.times.snapshotTotal = s.totalSeconds;
            rec.times.readback = s.readbackSeconds;
            for (const PassTiming& p : s.passTimes) rec.times.snapshotPassesGpuMs.emplace_back(p.pass, p.gpuMilliseconds);
            rec.vulkanDevice = snapshot->device;
        }
        // readback is part of snapshot_total, so it is not added again
        rec.times.total = rec.times.load + rec.times.bvhBuild + rec.times.snapshotTotal + rec.times.trace;
        rec.rays = {tr.rays.primary, tr.rays.shadow, tr.rays.other};
        const double sum = std::accumulate(tr.primaryRays.pixels().begin(), tr.primaryRays.pixels().end(), 0.0);
        rec.meanPrimaryRpp = sum / static_cast<double>(std::max<std::size_t>(1, tr.primaryRays.size()));
        rec.nonFiniteSamples = tr.nonFiniteSamples;
        rec.gitRevision = options.gitRevision;
        rec.configHash = results.configHash;
        rec.machine = machine;
        rec.outputs = {r.name + ".exr", r.name + ".png", r.name + ".rpp.png"};
        if (tr.nonFiniteSamples > 0) spdlog::warn("{}: {} non-finite samples dropped", r.name, tr.nonFiniteSamples);
        spdlog::info("{}: {:.2f} s, {:.2f} primary rays/pixel, {} rays in all", r.name, tr.seconds, rec.meanPrimaryRpp,
                     rec.rays.total());
        results.renders.push_back(std::move(rec));
        writeResults(outDir / "results.json", results);
    }
    spdlog::info("wrote {} in {:.2f} s", (outDir / "results.json").string(), secondsSince(runStart));
    return results;
}

}  // namespace aamap
