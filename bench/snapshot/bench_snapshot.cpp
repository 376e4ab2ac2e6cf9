// bench_snapshot: the Snapshot (raster + aamap) of a scene, per-pass GPU ms and total.
//   bench_snapshot [--scene builtin:cornell|file.obj|file.gltf] [--view file.vf] [--lights file.yaml]
//                  [--size 512] [--scale 1.5] ...
#include <cstdio>
#include <exception>

#include <CLI/CLI.hpp>

#include "core/heap.h"
#include "engine/vk/context.h"
#include "eval/light_list.h"
#include "scene/light_file.h"
#include "scene/load_scene.h"
#include "scene/view_file.h"
#include "snapshot_bench.h"

int main(int argc, char** argv) {
    aamap::keepFreedMemoryForReuse();  // as the aamap executable
    CLI::App app{"Snapshot + aamap benchmark (GPU)"};
    std::string sceneSpec = "builtin:cornell";
    aamap::bench::SnapshotBenchOptions options;
    aamap::ContextOptions contextOptions;
    int size = 512;
    bool explain = false;
    app.add_option("--scene", sceneSpec, "scene spec: builtin:<name> or an .obj/.gltf/.glb file");
    std::string viewFile, lightFile;
    int viewIndex = 0;
    app.add_option("--view", viewFile, "Radiance .vf view file (default: the scene's first view)");
    app.add_option("--view-index", viewIndex, "which view of the view file");
    app.add_option("--lights", lightFile, "light file added to the scene (docs/lights.md)");
    app.add_option("--size", size, "render resolution (square)");
    app.add_option("--scale", options.settings.scale, "snapshot resolution / render resolution");
    app.add_option("--area-samples", options.settings.areaLightSamples, "at most this many point samples per area light");
    app.add_option("--area-solid-angle", options.settings.areaLightSolidAngle,
                   "steradians of an area light's mean solid angle over the view per sample (0: always --area-samples)");
    std::string mapName = "luminance";
    app.add_option("--map", mapName, "snapshot.map: luminance, geometric, combined or subpixel");
    app.add_option("--subpixel", options.settings.subpixel, "the subpixel map's samples per pixel side k");
    std::string shadingName = aamap::passes::toString(options.settings.subpixelShading);
    app.add_option("--subpixel-shading", shadingName, "the subpixel map's shading: pixel (shared) or sample");
    app.add_option("--shadow-resolution", options.settings.shadows.resolution, "shadow cube-face size (texels)");
    app.add_option("--shadow-texel-pixels", options.settings.shadows.texelPixels,
                   "snapshot.shadow_texel_pixels: shadow faces by need (0: every light at --shadow-resolution)");
    app.add_option("--shadow-pcf", options.settings.shadows.pcf, "shadow PCF kernel side (1: one tap)");
    bool noShadows = false;
    app.add_flag("--no-shadows", noShadows, "snapshot without shadow cube maps");
    bool hardShadows = false;
    app.add_flag("--hard-shadows", hardShadows, "area-light samples cast hard shadows (no soft-shadow filter)");
    app.add_option("--warmup", options.warmup, "untimed runs first");
    app.add_option("--iterations", options.iterations, "timed runs (the median is reported)");
    app.add_option("--device", contextOptions.device, "Vulkan device index or name substring");
    app.add_flag("--validation", contextOptions.validation, "enable the Vulkan validation layer");
    app.add_flag("--explain", explain, "print the compiled render graph");
    CLI11_PARSE(app, argc, argv);
    options.width = options.height = size;
    if (!aamap::passes::parse(mapName, options.settings.map)) {
        std::fprintf(stderr, "unknown --map '%s'\n", mapName.c_str());
        return 2;
    }
    if (!aamap::passes::parse(shadingName, options.settings.subpixelShading)) {
        std::fprintf(stderr, "unknown --subpixel-shading '%s' (pixel or sample)\n", shadingName.c_str());
        return 2;
    }
    options.settings.shadows.enabled = !noShadows;
    options.settings.shadows.softShadows = !hardShadows;
    options.settings.keepDebugImages = false;  // the aamap alone, as the experiment pipeline reads it

    try {
        aamap::Scene scene = aamap::loadScene(sceneSpec);
        if (!lightFile.empty()) aamap::addLights(scene, aamap::loadLightFile(lightFile));
        const std::vector<aamap::View> views = viewFile.empty() ? scene.views : aamap::loadViewFile(viewFile);
        if (viewIndex < 0 || static_cast<std::size_t>(viewIndex) >= views.size()) {
            std::fprintf(stderr, "scene '%s' has no view %d; pass --view FILE.vf\n", sceneSpec.c_str(), viewIndex);
            return 2;
        }
        aamap::VulkanContext context(contextOptions);
        const auto result = aamap::bench::runSnapshotBench(context, scene, views[static_cast<std::size_t>(viewIndex)], options);
        std::printf("scene: %s (%zu triangles)\n%s", sceneSpec.c_str(), scene.mesh.triangles.size(),
                    aamap::bench::formatSnapshotBench(result, options).c_str());
        if (explain) std::printf("%s\n", result.explain.c_str());
        if (context.validationMessageCount() > 0) {
            std::fprintf(stderr, "%llu validation messages\n",
                         static_cast<unsigned long long>(context.validationMessageCount()));
            return 1;
        }
    } catch (const std::exception& e) {
        std::fprintf(stderr, "bench_snapshot: %s\n", e.what());
        return 1;
    }
    return 0;
}
