// Tracer throughput: time, rays/s and primary samples/s for uniform n x n sampling.
//   bench_tracer [--scene builtin:cornell] [--view FILE.vf] [--view-index 0] [--light-file FILE]
//                [--size 512] [--fit-view] [--strata 6] [--threads 0]
//                [--light-samples 16] [--repeat 3] [--mode direct|path|cache] [--max-depth 5]
//                [--ab 1] [--ad 512] [--as 128] [--aa 0.2] [--ar 64] [--cache-grid-step 4] [--out FILE.exr]
//                [--filter box|tent|gaussian] [--filter-mode convolution|importance]
//                [--light-sampling auto|solid_angle|area]
// Reports the best of --repeat runs: the machine is shared and noisy, the minimum is the
// least disturbed figure. Cache mode also reports the pre-pass (best of the runs) apart.
#include <algorithm>
#include <string>
#include <thread>
#include <vector>

#include <CLI/CLI.hpp>
#include <fmt/format.h>
#include <tbb/info.h>

#include "core/heap.h"
#include "core/image_io.h"
#include "eval/light_list.h"
#include "scene/light_file.h"
#include "scene/load_scene.h"
#include "scene/view_file.h"
#include "tracer/shading_params.h"
#include "tracer/tracer.h"

int main(int argc, char** argv) {
    aamap::keepFreedMemoryForReuse();  // as the aamap executable
    CLI::App app{"Tracer throughput benchmark (uniform n x n sampling)"};
    std::string sceneSpec = "builtin:cornell";
    int size = 512, strata = 6, threads = 0, lightSamples = 16, repeat = 3, maxDepth = 5;
    std::string mode = aamap::toString(aamap::ShadingSettings().mode), filter = "box", lightSampling = "auto";
    std::string filterMode = aamap::toString(aamap::PixelFilterSettings{}.mode);
    aamap::IrradianceCacheSettings cache;
    int gridStep = 4;
    std::string viewFile, lightFile, outFile;
    int viewIndex = 0;
    bool fitView = false;
    app.add_option("--scene", sceneSpec, "builtin:<name> or an .obj/.gltf/.glb file")->capture_default_str();
    app.add_option("--view", viewFile, "Radiance view file (.vf); default: the scene's own views");
    app.add_option("--view-index", viewIndex, "which view of the list")->capture_default_str()->check(CLI::NonNegativeNumber);
    app.add_option("--light-file", lightFile, "add the lights of a light file (docs/lights.md), e.g. configs/lights/conference.yaml");
    app.add_option("--out", outFile, "write the last run's image (linear, 32-bit float EXR) for before/after comparisons");
    app.add_flag("--fit-view", fitView, "fit the view's aspect ratio within --size x --size (square pixels), as `aamap run` does");
    app.add_option("--size", size, "render resolution (square)")->capture_default_str()->check(CLI::Range(1, 16384));
    app.add_option("--strata", strata, "n: n x n rays per pixel")->capture_default_str()->check(CLI::Range(1, 32));
    app.add_option("--threads", threads, "0 = all hardware threads")->capture_default_str()->check(CLI::NonNegativeNumber);
    app.add_option("--light-samples", lightSamples, "shadow rays per area light per hit")
        ->capture_default_str()
        ->check(CLI::Range(1, 4096));
    app.add_option("--repeat", repeat, "timed runs; the best is reported")->capture_default_str()->check(CLI::Range(1, 100));
    app.add_option("--mode", mode, "shading: direct, path or cache")
        ->capture_default_str()
        ->check(CLI::IsMember(aamap::findParam(aamap::shadingParams(), "mode")->choices));
    app.add_option("--light-sampling", lightSampling, "area lights: auto, solid_angle or area (shading.light_sampling)")
        ->capture_default_str()
        ->check(CLI::IsMember(aamap::findParam(aamap::shadingParams(), "light_sampling")->choices));
    app.add_option("--ab", cache.bounces, "cache mode: diffuse bounces")->capture_default_str()->check(CLI::Range(0, 8));
    app.add_option("--ad", cache.divisions, "cache mode: hemisphere divisions")->capture_default_str()->check(CLI::Range(1, 65536));
    app.add_option("--as", cache.supersamples, "cache mode: supersamples")->capture_default_str()->check(CLI::Range(0, 65536));
    app.add_option("--aa", cache.accuracy, "cache mode: accuracy")->capture_default_str()->check(CLI::Range(1e-4, 1.0));
    app.add_option("--cache-grid-step", gridStep, "cache mode: one candidate ray per step x step pixels")
        ->capture_default_str()
        ->check(CLI::Range(1, 1024));
    app.add_option("--ar", cache.resolution, "cache mode: resolution")->capture_default_str()->check(CLI::Range(0, 1 << 20));
    app.add_option("--max-depth", maxDepth, "path mode: longest path in segments")->capture_default_str()->check(CLI::Range(1, 1000));
    app.add_option("--filter", filter, "pixel filter, default radius (tracer/pixel_filter.h)")
        ->capture_default_str()
        ->check(CLI::IsMember({"box", "tent", "gaussian"}));
    app.add_option("--filter-mode", filterMode, "how the pixel filter applies (image.filter_mode)")
        ->capture_default_str()
        ->check(CLI::IsMember({"convolution", "importance"}));
    CLI11_PARSE(app, argc, argv);

    aamap::Scene scene;
    std::vector<aamap::View> views;
    try {
        scene = aamap::loadScene(sceneSpec);
        if (!lightFile.empty()) {
            const std::vector<aamap::LightSpec> lights = aamap::loadLightFile(lightFile);
            aamap::addLights(scene, lights);
        }
        views = viewFile.empty() ? scene.views : aamap::loadViewFile(viewFile);
    } catch (const std::exception& e) {
        fmt::print(stderr, "bench_tracer: error: {}\n", e.what());
        return 2;
    }
    if (views.empty()) {
        fmt::print(stderr, "bench_tracer: error: {}: the scene has no view (give --view)\n", sceneSpec);
        return 2;
    }
    if (viewIndex >= static_cast<int>(views.size())) {
        fmt::print(stderr, "bench_tracer: error: --view-index {} but only {} views\n", viewIndex, views.size());
        return 2;
    }
    const aamap::View& view = views[static_cast<std::size_t>(viewIndex)];
    const auto [width, height] = fitView ? aamap::fitResolution(view, size, size) : std::pair{size, size};
    fmt::print("machine: {} hardware threads, TBB default concurrency {}; using {}\n",
               std::thread::hardware_concurrency(), tbb::info::default_concurrency(),
               threads > 0 ? std::to_string(threads) : std::string("all"));
    fmt::print("scene '{}': {} triangles, {} area lights, {} point lights\n", scene.name,
               scene.mesh.triangles.size(), scene.areaLights.size(), scene.pointLights.size());

    const aamap::Tracer tracer(scene);
    fmt::print("BVH build: {:.2f} ms\n", tracer.bvhBuildSeconds() * 1e3);

    aamap::TraceSettings settings;
    settings.width = width;
    settings.height = height;
    settings.threads = threads;
    settings.shading.areaLightSamples = lightSamples;
    aamap::parse(mode, settings.shading.mode);  // CLI11 checked the name against the schema's
    aamap::parse(lightSampling, settings.shading.lightSampling);  // CLI11 checked the name
    settings.shading.cache = cache;
    settings.shading.cache.gridStep = gridStep;
    settings.shading.maxDepth = maxDepth;
    settings.shading.hideEmitters = scene.render.hideEmitters;  // a Mitsuba file's integrator's, as its view
    aamap::parse(filter, settings.filter.type);
    aamap::parse(filterMode, settings.filter.mode);
    aamap::StrategySettings strategy;
    strategy.strata = strata;

    double best = 1e30, bestPrepass = 1e30;
    aamap::TraceResult result;
    for (int r = 0; r < repeat; ++r) {
        result = tracer.render(view, settings, strategy);
        fmt::print("  run {}: {:.3f} s\n", r + 1, result.seconds);
        if (result.cache.built)
            fmt::print("    cache: {}x{} grid, {} points, {} records, pre-pass {:.3f} s ({} rays), render {:.3f} s, "
                       "{} misses ({} rays)\n",
                       result.cache.gridWidth, result.cache.gridHeight, result.cache.candidates, result.cache.records,
                       result.cache.prepassSeconds, result.cache.prepassRays.total(),
                       result.seconds - result.cache.prepassSeconds, result.cache.misses, result.cache.missRays);
        // Cache mode: the pre-pass is timed and counted apart (its rays are not in result.rays).
        best = std::min(best, result.seconds - result.cache.prepassSeconds);
        bestPrepass = std::min(bestPrepass, result.cache.prepassSeconds);
    }
    const auto& rays = result.rays;
    fmt::print("{}x{} uniform n={} ({} spp), {} filter ({}), mode {}, {}\n", width, height, strata, strata * strata, filter,
               filterMode, mode,
               mode == "path"    ? fmt::format("max depth {}", maxDepth)
               : mode == "cache" ? fmt::format("{} light samples/hit, -ab {} -ad {} -as {} -aa {} -ar {}", lightSamples,
                                               cache.bounces, cache.divisions, cache.supersamples, cache.accuracy,
                                               cache.resolution)
                                 : fmt::format("{} light samples/hit", lightSamples));
    fmt::print("rays: {} primary, {} shadow, {} other, {} total; {} non-finite samples\n", rays.primary,
               rays.shadow, rays.other, rays.total(), result.nonFiniteSamples);
    fmt::print("best {}time {:.3f} s | {:.2f} M rays/s | {:.2f} M samples/s (primary)\n", result.cache.built ? "render " : "", best,
               static_cast<double>(rays.total()) / best * 1e-6, static_cast<double>(rays.primary) / best * 1e-6);
    if (!outFile.empty()) aamap::writeExr(outFile, result.image);
    if (result.cache.built)
        fmt::print("cache: best pre-pass {:.3f} s | {} records | {} pre-pass rays ({:.2f} M rays/s) | render + pre-pass "
                   "{:.3f} s\n",
                   bestPrepass, result.cache.records, result.cache.prepassRays.total(),
                   static_cast<double>(result.cache.prepassRays.total()) / bestPrepass * 1e-6, best + bestPrepass);
    return 0;
}
