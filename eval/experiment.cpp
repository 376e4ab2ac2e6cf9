#include "eval/experiment.h"
#include "eval/sweep_runner.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <memory>
#include <numeric>
#include <optional>
#include <tuple>
#include <vector>

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <glm/geometric.hpp>
#include <spdlog/spdlog.h>

#include "core/error.h"
#include "core/image_io.h"
#include "core/log.h"
#include "engine/vk/check.h"
#include "engine/vk/context.h"
#include "passes/cpu_aamap.h"
#include "passes/snapshot.h"
#include "scene/builtin_scenes.h"
#include "scene/camera.h"
#include "scene/framing.h"
#include "scene/light_file.h"
#include "scene/lights.h"
#include "scene/load_scene.h"
#include "scene/view_file.h"
#include "eval/runner.h"
#include "eval/yaml_reader.h"
#include "eval/strategy_settings.h"
#include "tracer/block_sums.h"
#include "tracer/shading_params.h"
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

// The config's view file, its errors without a line pointing at the config's `view`.
std::vector<View> loadConfigViewFile(const ExperimentConfig& config, const std::filesystem::path& file) {
    try {
        return loadViewFile(file);
    } catch (const InputError& e) {
        if (e.line() > 0) throw;
        const SourceLocation& at = config.viewLocation;
        throw InputError(at.file, at.line, at.column, fmt::format("view '{}': {}", *config.view, e.what()));
    }
}

// Precedence: the config's camera, its view file, the scene's own views, a view framing the
// scene's bounds (with a warning). width x height: the image box the camera fills.
View pickView(const ExperimentConfig& config, const Scene& scene, std::string& label, int width, int height) {
    if (config.camera) {
        const CameraConfig& c = *config.camera;
        const auto vec = [](const std::array<double, 3>& v) { return glm::vec3(v[0], v[1], v[2]); };
        try {
            View v = lookAtView(vec(c.position), vec(c.lookAt), vec(c.up), static_cast<float>(c.fov), width, height);
            v.name = label = "camera";
            return v;
        } catch (const std::invalid_argument& e) {
            const SourceLocation& at = config.cameraLocation;
            throw InputError(at.file, at.line, at.column, fmt::format("camera: {}", e.what()));
        }
    }
    std::vector<View> views;
    std::string source;
    if (const auto file = config.resolvedView()) {
        views = loadConfigViewFile(config, *file);
        source = file->filename().string();
    } else {
        views = scene.views;
        source = scene.name.empty() ? config.scene : scene.name;
    }
    const SourceLocation& at = config.viewIndexLocation;
    if (views.empty() && config.viewIndex == 0) {
        spdlog::warn("{} has no camera: using a view that frames the scene's bounds (set 'camera' or 'view' to choose one)",
                     source);
        label = "framed";
        return framingView(sceneBounds(scene), width, height);
    }
    if (views.empty())
        throw InputError(config.viewLocation.file, config.viewLocation.line, config.viewLocation.column,
                         fmt::format("{} has no view; set 'camera', or 'view' to a Radiance .vf file", source));
    if (config.viewIndex >= static_cast<int>(views.size()))
        throw InputError(at.file, at.line, at.column,
                         fmt::format("view_index {} is out of range: {} has {} view(s)", config.viewIndex, source,
                                     views.size()));
    const View& view = views[static_cast<std::size_t>(config.viewIndex)];
    label = view.name.empty() ? fmt::format("{}#{}", source, config.viewIndex) : view.name;
    return view;
}

// The light file's and the inline list's lights (quads and disks become emissive geometry).
void addConfigLights(const ExperimentConfig& config, Scene& scene) { addLights(scene, config.lights); }

SnapshotSettings snapshotSettings(const ExperimentConfig& c) {
    SnapshotSettings s(c.snapshot);  // the snapshot section, as the passes take it
    s.filter.exposure = static_cast<float>(c.image.exposure);  // edges as the viewer will see them
    s.flipThreshold = static_cast<float>(c.metrics.flipThreshold);  // what the metrics count as an error
    s.keepDebugImages = true;
    // The GPU block-sum pass only when a render subsamples (otherwise the graph culls it).
    s.blockSums = std::any_of(c.renders.begin(), c.renders.end(), [](const RenderConfig& r) {
        const StrategyDescriptor* d = findStrategy(r.strategy);
        return d != nullptr && d->needsBlockSums;
    });
    return s;
}

// The real backend: scene and BVH on first need, Snapshot on the GPU, Embree tracer.
class TracerBackend : public RenderBackend {
public:
    TracerBackend(const ExperimentConfig& config, const RunOptions& options) : config_(config), options_(options) {}

    SceneInfo prepare() override {
        spdlog::info("loading scene {}", config_.resolvedScene());
        SceneInfo info;
        WarningCapture loaderWarnings;
        PreparedScene prepared = prepareScene(config_);
        info.loaderWarnings = loaderWarnings.take();
        scene_ = std::move(prepared.scene);
        view_ = prepared.view;
        if (!config_.sizeGiven() && scene_.imageWidth > 0)
            info.warnings.push_back(fmt::format("image size {}x{} from the scene file's film (the config's own "
                                                "image.width/height win)",
                                                scene_.imageWidth, scene_.imageHeight));
        effective_ = withSceneRenderSettings(config_, scene_, info.warnings);
        for (const std::string& note : info.warnings) spdlog::info("{}", note);
        info.loadSeconds = prepared.loadSeconds;
        info.viewLabel = prepared.viewLabel;
        info.width = prepared.width;
        info.height = prepared.height;
        info.scene = config_.resolvedScene();
        spdlog::info("scene '{}': {} triangles, {}; view {} at {}x{} ({:.2f} s)", scene_.name,
                     scene_.mesh.triangles.size(), describeLights(scene_), info.viewLabel, info.width, info.height,
                     info.loadSeconds);
        if (auto unlit = unlitSceneWarning(scene_)) info.warnings.push_back(std::move(*unlit));
        if (config_.usesAamap())
            for (std::string& note : snapshotLimitations(scene_)) info.warnings.push_back(std::move(note));
        spdlog::info("building BVH");
        tracer_ = std::make_unique<Tracer>(scene_);
        info.bvhSeconds = tracer_->bvhBuildSeconds();
        info_ = info;
        return info;
    }

    SnapshotOutput snapshot() override {
        std::unique_ptr<VulkanContext> context;
        try {
            context = std::make_unique<VulkanContext>(ContextOptions{options_.validation, options_.device});
        } catch (const RequestedDeviceError&) {
            throw;  // the user asked for that device: say so rather than quietly use the CPU
        } catch (const EnvironmentError& e) {
            if (config_.snapshot.map != passes::AamapSource::Luminance)
                throw EnvironmentError(fmt::format("snapshot.map: {} needs a Vulkan device, and there is none usable ({})",
                                                   passes::toString(config_.snapshot.map), e.what()));
            spdlog::warn("no usable Vulkan device ({}); building the aamap on the CPU instead", e.what());
            return cpuSnapshot(e.what());
        }
        if (options_.validation && !context->validationEnabled())
            throw EnvironmentError("validation was requested but VK_LAYER_KHRONOS_validation is not available");
        SnapshotOutput out;
        out.device = context->deviceName();
        spdlog::info("snapshot on '{}' at {}x{} (scale {})", out.device, info_.width, info_.height, config_.snapshot.scale);
        try {
            // The graph runs several times. The first execution, with what precedes it, is setup,
            // reported apart like scene load and BVH build: pipelines, uploads, the driver's
            // first-use work (lavapipe compiles shader variants at the first draw and takes a few
            // frames to reach its steady state) and the read-back of the report's debug images.
            // Then warm-up executions, and timed ones whose median is the Snapshot's per-frame cost,
            // the one charged to every aamap-driven render, as a GPU frame time is measured: they
            // read back only what the strategies consume (the aamap, block sums when asked).
            constexpr int kWarmupExecutions = 3;
            constexpr int kTimedExecutions = 3;
            const auto setupStart = Clock::now();
            SnapshotRenderer renderer(*context, scene_);
            const SnapshotSettings settings = snapshotSettings(config_);
            SnapshotResult withImages = renderer.render(view_, info_.width, info_.height, settings);
            SnapshotSettings perFrame = settings;
            perFrame.keepDebugImages = false;
            for (int i = 0; i < kWarmupExecutions; ++i) renderer.render(view_, info_.width, info_.height, perFrame);
            out.setupSeconds = secondsSince(setupStart);
            std::vector<SnapshotResult> timed;
            for (int i = 0; i < kTimedExecutions; ++i) {
                timed.push_back(renderer.render(view_, info_.width, info_.height, perFrame));
                if (timed.back().aamap.pixels() != withImages.aamap.pixels())  // the same graph, the same inputs
                    spdlog::warn("the Snapshot's executions gave different aamaps; using the median-time one");
            }
            std::sort(timed.begin(), timed.end(),
                      [](const SnapshotResult& a, const SnapshotResult& b) { return a.totalSeconds < b.totalSeconds; });
            SnapshotResult& r = timed[timed.size() / 2];
            out.warnings = withImages.warnings;
            out.snapshot = std::move(withImages.snapshot);
            out.laplacian = std::move(withImages.laplacian);
            if (!r.blockSums.empty()) {
                gpuBlockSumsMap_ = r.aamap;  // out.aamap: moved below
                gpuBlockSums_ = BlockSums::fromTables(r.blockSums.width, r.blockSums.height,
                                                      std::move(r.blockSums.sums), std::move(r.blockSums.counts));
            }
            out.aamap = std::move(r.aamap);
            out.totalSeconds = r.totalSeconds;
            out.readbackSeconds = r.readbackSeconds;
            for (const PassTiming& p : r.passTimes) out.passesGpuMs.emplace_back(p.pass, p.gpuMilliseconds);
        } catch (const vk::VulkanError& e) {  // GPU objects are freed by then, as on success
            // The device failed after it was created (lost, out of memory, ...): same fallback as no device.
            const std::string reason = fmt::format("the Vulkan device '{}' failed during the Snapshot: {}", out.device,
                                                   vk::resultName(e.result()));
            context.reset();
            gpuBlockSums_.reset();
            if (config_.snapshot.map != passes::AamapSource::Luminance)
                throw EnvironmentError(fmt::format("snapshot.map: {} needs a Vulkan device, and {} ({})",
                                                   passes::toString(config_.snapshot.map), reason, e.what()));
            spdlog::warn("{} ({}); building the aamap on the CPU instead", reason, e.what());
            return cpuSnapshot(reason);
        }  // GPU objects freed here, so their destruction is validated too
        if (context->validationEnabled() && context->validationMessageCount() > 0)
            throw ValidationFailure(fmt::format("{} Vulkan validation message(s), logged above",
                                                context->validationMessageCount()));
        spdlog::info("snapshot: {:.1f} ms per frame, after {:.1f} ms of setup", out.totalSeconds * 1e3,
                     out.setupSeconds * 1e3);
        return out;
    }

    // No Vulkan device: the tracer renders the snapshot (1 ray per pixel, direct light) and the CPU
    // filter chain -- the GPU chain's reference -- builds the aamap. results.json records the
    // path in vulkan_device ("cpu-fallback: <why>"). The luminance chain only: a geometric map
    // needs the G-buffer, so those configs fail instead (above).
    SnapshotOutput cpuSnapshot(const std::string& reason) {
        const auto t0 = Clock::now();
        const SnapshotSettings settings = snapshotSettings(config_);
        TraceSettings ts;
        ts.width = std::max(1, static_cast<int>(std::lround(info_.width * settings.scale)));
        ts.height = std::max(1, static_cast<int>(std::lround(info_.height * settings.scale)));
        ts.seed = config_.seed;
        ts.threads = options_.threads >= 0 ? options_.threads : config_.threads;
        ts.shading.areaLightSamples = std::max(1, settings.areaLightSamples);
        StrategySettings uniform;  // uniform, n = 1
        SnapshotOutput out;
        out.snapshot = tracer_->render(view_, ts, uniform).image;
        cpu::AamapImages maps = cpu::buildAamap(out.snapshot, info_.width, info_.height, settings.filter);
        out.aamap = std::move(maps.aamap);
        out.laplacian = std::move(maps.laplacian);
        out.device = "cpu-fallback: " + reason.substr(0, reason.find('\n'));
        out.totalSeconds = secondsSince(t0);
        spdlog::info("snapshot on the CPU: {:.1f} ms", out.totalSeconds * 1e3);
        return out;
    }

    TraceOutput trace(const RenderConfig& render, const ImageGrey* aamap,
                      const std::function<void(int, int)>& progress) override {
        TraceSettings ts = traceSettingsFor(effective_, render, info_.width, info_.height, options_.threads);
        ts.onTileDone = progress;
        StrategySettings ss = toStrategySettings(render, aamap);
        ss.exposure = static_cast<float>(config_.image.exposure);  // display-space tests (Space's gradients)
        std::string blockSums;
        if (findStrategy(ss.name)->needsBlockSums) {
            // The Snapshot's GPU tables when this run rendered it and the map is that one; the CPU
            // fallback for a cached Snapshot or another map, such as the oracle's (both give the
            // same plan for the same map: tests/gpu/test_gpu_block_sums).
            const bool gpu = gpuBlockSums_ && aamap != nullptr && aamap->width() == gpuBlockSumsMap_.width() &&
                             aamap->height() == gpuBlockSumsMap_.height() && aamap->pixels() == gpuBlockSumsMap_.pixels();
            if (gpu) ss.blockSums = &*gpuBlockSums_;
            blockSums = gpu ? "gpu" : "cpu";
        }
        const TraceResult tr = tracer_->render(view_, ts, ss);
        TraceOutput out;
        out.blockSums = blockSums;
        out.image = tr.image;
        out.primaryRays = tr.primaryRays;
        out.halfDifference = tr.halfDifference;
        out.rays = {tr.rays.primary, tr.rays.shadow, tr.rays.other};
        out.nonFiniteSamples = tr.nonFiniteSamples;
        out.seconds = tr.seconds;
        return out;
    }

    std::optional<std::pair<int, int>> renderSizeWithoutScene() const override {
        return aamap::renderSizeWithoutScene(config_);
    }

    bool hasPixelFacts() const override { return true; }
    PixelFacts pixelFacts() override { return tracer_->pixelFacts(view_, info_.width, info_.height, options_.threads); }

private:
    const ExperimentConfig& config_;
    ExperimentConfig effective_;  // with what the scene file decides (withSceneRenderSettings)
    RunOptions options_;
    Scene scene_;
    View view_;
    SceneInfo info_;
    std::unique_ptr<Tracer> tracer_;
    std::optional<BlockSums> gpuBlockSums_;  // from this run's Snapshot, if it built them
    ImageGrey gpuBlockSumsMap_;              // the map they sum
};

}  // namespace

std::optional<std::pair<int, int>> renderSizeWithoutScene(const ExperimentConfig& config) {
    if (!config.sizeGiven() && sceneDecidesRendering(config)) return std::nullopt;
    if (!config.camera && !config.resolvedView()) return std::nullopt;
    Scene none;
    std::string label;
    const View view = pickView(config, none, label, config.image.width, config.image.height);
    return fitResolution(view, config.image.width, config.image.height);
}

PreparedScene prepareScene(const ExperimentConfig& config) {
    const auto t0 = Clock::now();
    PreparedScene p;
    p.scene = loadSceneFor(config);
    addConfigLights(config, p.scene);
    p.loadSeconds = secondsSince(t0);
    // The scene's own image size (a Mitsuba film) unless the config gives one.
    int width = config.image.width, height = config.image.height;
    if (!config.sizeGiven() && p.scene.imageWidth > 0) {
        width = p.scene.imageWidth;
        height = p.scene.imageHeight;
    }
    p.view = pickView(config, p.scene, p.viewLabel, width, height);
    std::tie(p.width, p.height) = fitResolution(p.view, width, height);
    return p;
}

ExperimentConfig withSceneRenderSettings(const ExperimentConfig& config, const Scene& scene,
                                         std::vector<std::string>& notes) {
    ExperimentConfig c = config;
    const SceneRenderSettings& r = scene.render;
    const std::string from = fmt::format("the scene file's <integrator type=\"{}\"> ({})", r.integrator, r.at);
    if (!r.integrator.empty()) {
        std::vector<std::string> applied;
        if (!c.given("shading.max_depth")) {
            // Unlimited in the file: the longest path the config allows, where roulette ends it.
            c.shading.maxDepth = std::min(r.maxDepth.value_or(kMaxPathDepth), kMaxPathDepth);
            applied.push_back(fmt::format("shading.max_depth {}{}", c.shading.maxDepth,
                                          r.maxDepth ? "" : " (unlimited there)"));
        }
        if (!c.given("shading.roulette_depth") && r.rrDepth) {
            c.shading.rouletteDepth = *r.rrDepth;
            applied.push_back(fmt::format("shading.roulette_depth {}", c.shading.rouletteDepth));
        }
        if (!applied.empty())
            notes.push_back(fmt::format("{} from {}; the config's own values win", fmt::join(applied, " and "), from));
        if (!c.given("shading.hide_emitters") && r.hideEmitters) {
            c.shading.hideEmitters = true;
            notes.push_back(fmt::format("shading.hide_emitters true from {} (it hides directly visible emitters); the "
                                        "config's own value wins",
                                        from));
        }
    }
    if (r.sampleCount) {
        // Its author's converged sample count: a reference with fewer rays is noisier than meant.
        const bool fewer = c.reference.type == ReferenceType::Uniform && c.reference.rpp < *r.sampleCount;
        const int n = static_cast<int>(std::ceil(std::sqrt(static_cast<double>(*r.sampleCount))));
        notes.push_back(fmt::format("the scene file's sampler asks {} samples per pixel; the renders' rays per pixel "
                                    "come from the config (renders[].rpp){}",
                                    *r.sampleCount,
                                    fewer ? fmt::format(", and its reference traces {} (reference.rpp: {} would "
                                                        "match the file)",
                                                        c.reference.rpp, n * n)
                                          : ""));
    }
    if (!r.filter.empty() && r.filter != toString(c.image.filter.type)) {
        PixelFilterType known{};
        const bool given = c.given("image.filter");
        if (!given && parse(r.filter, known)) {
            // The film's filter with its default size (Mitsuba's and aamap's defaults agree).
            c.image.filter.type = known;
            c.image.filter.radius = 0.0f;
            notes.push_back(fmt::format("image.filter {} from the scene file's film (the config's own image.filter "
                                        "wins)",
                                        r.filter));
        } else {
            notes.push_back(fmt::format("the scene file's film filters pixels with a '{}' filter; the renders use "
                                        "image.filter {}{}",
                                        r.filter, toString(c.image.filter.type),
                                        given ? " as the config says" : " (aamap has no such filter)"));
        }
    }
    return c;
}

SnapshotSettings snapshotSettingsFor(const ExperimentConfig& config) { return snapshotSettings(config); }

TraceSettings traceSettingsFor(const ExperimentConfig& config, const RenderConfig& render, int width, int height,
                               int threads) {
    TraceSettings ts;
    ts.width = width;
    ts.height = height;
    ts.seed = config.seed;
    ts.threads = threads >= 0 ? threads : config.threads;
    ts.shading = toShadingSettings(config, render);
    ts.filter = config.image.filter;
    return ts;
}

Results runExperiment(const ExperimentConfig& config, const std::filesystem::path& outDir, const RunOptions& options) {
    checkInputs(config);
    TracerBackend backend(config, options);
    RunnerOptions ro;
    ro.gitRevision = options.gitRevision;
    ro.plots = options.plots;
    ro.cacheDir = options.cacheDir;
    return runExperimentWith(config, outDir, backend, ro);
}

std::filesystem::path experimentCacheDir(const std::filesystem::path& outDir, const RunOptions& options) {
    return options.cacheDir.empty() ? outDir / "cache" : options.cacheDir;
}

std::vector<WorkItem> listMissingWork(const Experiment& experiment, const std::filesystem::path& outDir,
                                      const RunOptions& options) {
    const std::filesystem::path cache = experimentCacheDir(outDir, options);
    std::vector<WorkItem> items;
    for (const ExperimentConfig& variant : experiment.variants)
        for (WorkItem& w : missingWork(variant, cache, options.threads))
            if (std::none_of(items.begin(), items.end(), [&](const WorkItem& i) { return i.key == w.key; }))
                items.push_back(std::move(w));
    // Snapshots first: the renders driven by their aamaps wait for them.
    std::stable_partition(items.begin(), items.end(), [](const WorkItem& w) { return w.kind == "snapshot"; });
    return items;
}

void computeExperimentItem(const Experiment& experiment, const std::string& key, const std::filesystem::path& outDir,
                           const RunOptions& options) {
    for (const ExperimentConfig& variant : experiment.variants) {
        if (!hasWorkItem(variant, key)) continue;
        TracerBackend backend(variant, options);
        RunnerOptions ro;
        ro.gitRevision = options.gitRevision;
        ro.cacheDir = experimentCacheDir(outDir, options);
        computeWorkItem(variant, key, backend, ro);
        return;
    }
    throw InputError(experiment.variants.front().file,
                     fmt::format("--only {}: no Snapshot or render of this experiment has that cache key (see --list-work)", key));
}

void checkInputs(const ExperimentConfig& config) {
    const SourceLocation& at = config.sceneLocation;
    if (config.scene.starts_with("builtin:")) {
        const std::string name = config.scene.substr(8);
        const std::vector<std::string> known = builtinSceneNames();
        if (std::find(known.begin(), known.end(), name) == known.end()) {
            const std::string hint = yaml::closest(name, known);
            throw InputError(at.file, at.line, at.column,
                             fmt::format("scene '{}': unknown built-in scene{} (known: {})", config.scene,
                                         hint.empty() ? "" : fmt::format("; did you mean 'builtin:{}'?", hint),
                                         fmt::join(known, ", ")));
        }
    } else {
        std::error_code ec;
        if (!std::filesystem::is_regular_file(config.resolvedScene(), ec))
            throw InputError(at.file, at.line, at.column,
                             fmt::format("scene '{}': no such file ({})", config.scene, config.resolvedScene()));
    }
    // The camera, or the view file and view_index within it (a Mitsuba film may still change the
    // size, not the view).
    if (config.resolvedView() || config.camera) {
        Scene none;
        std::string label;
        pickView(config, none, label, config.image.width, config.image.height);
    }
}

void runSweptExperiment(const Experiment& experiment, const std::filesystem::path& outDir, const RunOptions& options) {
    if (experiment.sweptKeys.empty()) {
        runExperiment(experiment.variants.front(), outDir, options);  // which checks its inputs
        return;
    }
    // Every variant's inputs before any runs: a typo in the last scene must not wait for the others.
    for (const ExperimentConfig& variant : experiment.variants) checkInputs(variant);
    RunnerOptions ro;
    ro.gitRevision = options.gitRevision;
    ro.plots = options.plots;
    ro.cacheDir = options.cacheDir;
    runSweepWith(experiment, outDir,
                 [&](const ExperimentConfig& config) { return std::make_unique<TracerBackend>(config, options); }, ro);
}

}  // namespace aamap
