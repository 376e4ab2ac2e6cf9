#include "eval/experiment.h"

#include <algorithm>
#include <chrono>
#include <memory>
#include <numeric>
#include <optional>
#include <tuple>

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
#include "eval/runner.h"
#include "eval/strategy_settings.h"
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

// The real backend: scene and BVH on first need, Snapshot on the GPU, Embree tracer.
class TracerBackend : public RenderBackend {
public:
    TracerBackend(const ExperimentConfig& config, const RunOptions& options) : config_(config), options_(options) {}

    SceneInfo prepare() override {
        spdlog::info("loading scene {}", config_.resolvedScene());
        const auto t0 = Clock::now();
        scene_ = loadSceneFor(config_);
        addConfigLights(config_, scene_);
        SceneInfo info;
        info.loadSeconds = secondsSince(t0);
        view_ = pickView(config_, scene_, info.viewLabel);
        std::tie(info.width, info.height) = fitResolution(view_, config_.image.width, config_.image.height);
        info.scene = config_.resolvedScene();
        spdlog::info("scene '{}': {} triangles, {} area + {} point lights; view {} at {}x{} ({:.2f} s)", scene_.name,
                     scene_.mesh.triangles.size(), scene_.areaLights.size(), scene_.pointLights.size(),
                     info.viewLabel, info.width, info.height, info.loadSeconds);
        spdlog::info("building BVH");
        tracer_ = std::make_unique<Tracer>(scene_);
        info.bvhSeconds = tracer_->bvhBuildSeconds();
        info_ = info;
        return info;
    }

    SnapshotOutput snapshot() override {
        auto context = std::make_unique<VulkanContext>(ContextOptions{options_.validation, options_.device});
        if (options_.validation && !context->validationEnabled())
            throw EnvironmentError("validation was requested but VK_LAYER_KHRONOS_validation is not available");
        SnapshotOutput out;
        out.device = context->deviceName();
        spdlog::info("snapshot on '{}' at {}x{} (scale {})", out.device, info_.width, info_.height, config_.snapshot.scale);
        {
            SnapshotRenderer renderer(*context, scene_);
            SnapshotResult r = renderer.render(view_, info_.width, info_.height, snapshotSettings(config_));
            out.aamap = std::move(r.aamap);
            out.snapshot = std::move(r.snapshot);
            out.laplacian = std::move(r.laplacian);
            out.totalSeconds = r.totalSeconds;
            out.readbackSeconds = r.readbackSeconds;
            for (const PassTiming& p : r.passTimes) out.passesGpuMs.emplace_back(p.pass, p.gpuMilliseconds);
        }  // GPU objects freed here, so their destruction is validated too
        if (context->validationEnabled() && context->validationMessageCount() > 0)
            throw ValidationFailure(fmt::format("{} Vulkan validation message(s), logged above",
                                                context->validationMessageCount()));
        spdlog::info("snapshot: {:.1f} ms", out.totalSeconds * 1e3);
        return out;
    }

    TraceOutput trace(const RenderConfig& render, const ImageGrey* aamap,
                      const std::function<void(int, int)>& progress) override {
        TraceSettings ts;
        ts.width = info_.width;
        ts.height = info_.height;
        ts.seed = config_.seed;
        ts.threads = options_.threads >= 0 ? options_.threads : config_.threads;
        ts.shading = toShadingSettings(config_, render);
        ts.onTileDone = progress;
        const TraceResult tr = tracer_->render(view_, ts, toStrategySettings(render, aamap));
        TraceOutput out;
        out.image = tr.image;
        out.primaryRays = tr.primaryRays;
        out.rays = {tr.rays.primary, tr.rays.shadow, tr.rays.other};
        out.nonFiniteSamples = tr.nonFiniteSamples;
        out.seconds = tr.seconds;
        return out;
    }

private:
    const ExperimentConfig& config_;
    RunOptions options_;
    Scene scene_;
    View view_;
    SceneInfo info_;
    std::unique_ptr<Tracer> tracer_;
};

}  // namespace

Results runExperiment(const ExperimentConfig& config, const std::filesystem::path& outDir, const RunOptions& options) {
    TracerBackend backend(config, options);
    RunnerOptions ro;
    ro.gitRevision = options.gitRevision;
    ro.plots = options.plots;
    return runExperimentWith(config, outDir, backend, ro);
}

}  // namespace aamap
