#include "tracer/tracer.h"

#include <atomic>
#include <chrono>
#include <cmath>
#include <stdexcept>

#include <fmt/format.h>
#include <glm/geometric.hpp>
#include <glm/vec3.hpp>
#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/info.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include "scene/camera.h"
#include "tracer/embree_scene.h"
#include "tracer/integrator.h"
#include "tracer/lights.h"
#include "tracer/sampler.h"
#include "tracer/strategy.h"

namespace aamap {
namespace {

constexpr int kTileSize = 16;

// Counted per thread, summed once at the end: no shared atomics on the ray path.
struct ThreadCounters {
    RayCounts rays;
    std::uint64_t nonFinite = 0;
};

bool isFinite(const glm::vec3& c) { return std::isfinite(c.x) && std::isfinite(c.y) && std::isfinite(c.z); }

struct TileJob {
    const PinholeCamera& camera;
    const Integrator& integrator;
    const SamplingStrategy& strategy;
    std::uint64_t seed;
    int width, height;
    ImageRGB& image;
    Image<std::uint16_t>& primaryRays;

    void run(int x0, int y0, int x1, int y1, ThreadCounters& counters) const {
        const float invW = 1.0f / static_cast<float>(width);
        const float invH = 1.0f / static_cast<float>(height);
        for (int y = y0; y < y1; ++y) {
            for (int x = x0; x < x1; ++x) {
                const int k = strategy.stratificationFor(x, y);
                primaryRays.at(x, y) = static_cast<std::uint16_t>(k * k);
                if (k <= 0) continue;  // the strategy fills this pixel later
                const std::uint64_t pixelIndex = static_cast<std::uint64_t>(y) * width + x;
                glm::dvec3 sum(0.0);
                int kept = 0;
                for (int sy = 0; sy < k; ++sy) {
                    for (int sx = 0; sx < k; ++sx) {
                        const Sampler sampler(pixelIndex, static_cast<std::uint32_t>(sy * k + sx), seed);
                        const glm::vec2 j = sampler.stratified2D(dims::kFilm, sx, sy, k);
                        // Film point exactly as the rasteriser defines pixel (x, y).
                        const float u = (static_cast<float>(x) + j.x) * invW;
                        const float v = (static_cast<float>(y) + j.y) * invH;
                        const glm::vec3 dir = glm::normalize(camera.direction(u, v));
                        const glm::vec3 L = integrator.primary(camera.origin, dir, sampler, counters.rays);
                        if (!isFinite(L)) {
                            ++counters.nonFinite;
                            continue;
                        }
                        sum += glm::dvec3(L);
                        ++kept;
                    }
                }
                image.at(x, y) = kept > 0 ? glm::vec3(sum / static_cast<double>(kept)) : glm::vec3(0.0f);
            }
        }
    }
};

}  // namespace

struct Tracer::Impl {
    EmbreeScene geometry;
    LightSet lights;
    explicit Impl(const Scene& scene) : geometry(scene), lights(buildLights(scene, geometry)) {}
};

Tracer::Tracer(const Scene& scene) : impl_(std::make_unique<Impl>(scene)) {}
Tracer::~Tracer() = default;

double Tracer::bvhBuildSeconds() const { return impl_->geometry.buildSeconds(); }

TraceResult Tracer::render(const View& view, const TraceSettings& settings, const StrategySettings& strategySettings) const {
    const auto start = std::chrono::steady_clock::now();
    const int W = settings.width, H = settings.height;
    if (W <= 0 || H <= 0) throw std::invalid_argument(fmt::format("render size {}x{} is empty", W, H));
    if (settings.threads < 0) throw std::invalid_argument(fmt::format("threads must be >= 0, got {}", settings.threads));
    const auto strategy = makeStrategy(strategySettings, W, H);
    const Integrator integrator(impl_->geometry, impl_->lights, settings.shading);
    const PinholeCamera camera = PinholeCamera::fromView(view);

    TraceResult result;
    result.image = ImageRGB(W, H, glm::vec3(0.0f));
    result.primaryRays = Image<std::uint16_t>(W, H, 0);
    const TileJob job{camera, integrator, *strategy, settings.seed, W, H, result.image, result.primaryRays};

    const int tilesX = (W + kTileSize - 1) / kTileSize;
    const int tilesY = (H + kTileSize - 1) / kTileSize;
    const int tileCount = tilesX * tilesY;
    std::atomic<int> tilesDone{0};
    tbb::enumerable_thread_specific<ThreadCounters> counters;

    const int threads = settings.threads > 0 ? settings.threads : tbb::info::default_concurrency();
    tbb::task_arena arena(threads);
    arena.execute([&] {
        // Grain 1: tiles are already coarse, and cost varies a lot between them.
        tbb::parallel_for(tbb::blocked_range<int>(0, tileCount, 1), [&](const tbb::blocked_range<int>& r) {
            ThreadCounters& local = counters.local();
            for (int t = r.begin(); t != r.end(); ++t) {
                const int x0 = (t % tilesX) * kTileSize, y0 = (t / tilesX) * kTileSize;
                job.run(x0, y0, std::min(x0 + kTileSize, W), std::min(y0 + kTileSize, H), local);
                const int done = tilesDone.fetch_add(1, std::memory_order_relaxed) + 1;
                if (settings.onTileDone) settings.onTileDone(done, tileCount);
            }
        });
    });
    strategy->fill(result.image, result.primaryRays);

    for (const ThreadCounters& c : counters) {
        result.rays.primary += c.rays.primary;
        result.rays.shadow += c.rays.shadow;
        result.rays.other += c.rays.other;
        result.nonFiniteSamples += c.nonFinite;
    }
    result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return result;
}

}  // namespace aamap
