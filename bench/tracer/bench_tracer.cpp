// Tracer throughput on a Cornell-box-like scene built in code: time, rays/s and samples/s.
//   bench_tracer [--size 512] [--strata 6] [--threads 0] [--light-samples 16] [--repeat 3]
// The scene comes from benchScene(); swap in the real built-in Cornell box when it lands.
#include <algorithm>
#include <cstdlib>
#include <cstring>
#include <string>
#include <thread>

#include <fmt/format.h>
#include <tbb/info.h>

#include "tests/tracer/scene_builder.h"
#include "tracer/tracer.h"

namespace {

aamap::Scene benchScene() { return aamap::testing::cornellLikeScene(); }

int intArg(int argc, char** argv, const char* name, int fallback) {
    for (int i = 1; i + 1 < argc; ++i)
        if (std::strcmp(argv[i], name) == 0) return std::atoi(argv[i + 1]);
    return fallback;
}

}  // namespace

int main(int argc, char** argv) {
    const int size = intArg(argc, argv, "--size", 512);
    const int strata = intArg(argc, argv, "--strata", 6);
    const int threads = intArg(argc, argv, "--threads", 0);
    const int lightSamples = intArg(argc, argv, "--light-samples", 16);
    const int repeat = std::max(1, intArg(argc, argv, "--repeat", 3));

    const aamap::Scene scene = benchScene();
    fmt::print("machine: {} hardware threads, TBB default concurrency {}; using {}\n",
               std::thread::hardware_concurrency(), tbb::info::default_concurrency(),
               threads > 0 ? std::to_string(threads) : std::string("all"));
    fmt::print("scene '{}': {} triangles, {} area lights, {} point lights\n", scene.name,
               scene.mesh.triangles.size(), scene.areaLights.size(), scene.pointLights.size());

    const aamap::Tracer tracer(scene);
    fmt::print("BVH build: {:.2f} ms\n", tracer.bvhBuildSeconds() * 1e3);

    aamap::TraceSettings settings;
    settings.width = settings.height = size;
    settings.threads = threads;
    settings.shading.areaLightSamples = lightSamples;
    aamap::StrategySettings strategy;
    strategy.strata = strata;

    double best = 1e30;
    aamap::TraceResult result;
    for (int r = 0; r < repeat; ++r) {
        result = tracer.render(scene.views.front(), settings, strategy);
        fmt::print("  run {}: {:.3f} s\n", r + 1, result.seconds);
        best = std::min(best, result.seconds);
    }
    const auto& rays = result.rays;
    fmt::print("{}x{} uniform n={} ({} spp), {} light samples/hit\n", size, size, strata, strata * strata,
               lightSamples);
    fmt::print("rays: {} primary, {} shadow, {} other, {} total; {} non-finite samples\n", rays.primary,
               rays.shadow, rays.other, rays.total(), result.nonFiniteSamples);
    fmt::print("best time {:.3f} s | {:.2f} M rays/s | {:.2f} M samples/s (primary)\n", best,
               static_cast<double>(rays.total()) / best * 1e-6, static_cast<double>(rays.primary) / best * 1e-6);
    return 0;
}
