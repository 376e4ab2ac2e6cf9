#include "tracer/tracer.h"

#include <chrono>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <vector>

#include <fmt/format.h>
#include <glm/geometric.hpp>
#include <glm/vec3.hpp>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/info.h>
#include <tbb/task_arena.h>

#include "scene/camera.h"
#include "tracer/embree_scene.h"
#include "tracer/integrator.h"
#include "tracer/irradiance_source.h"
#include "tracer/lights.h"
#include "tracer/sampler.h"
#include "tracer/strategy.h"

namespace aamap {
namespace {

// Counted per thread, summed once at the end: no shared atomics on the ray path.
struct ThreadCounters {
    RayCounts rays;
    std::uint64_t nonFinite = 0;
};

bool isFinite(const glm::vec3& c) { return std::isfinite(c.x) && std::isfinite(c.y) && std::isfinite(c.z); }

// The strategies' view of the scene: one primary sample = one integrator call.
class EmbreeSource final : public SampleSource {
public:
    EmbreeSource(const PinholeCamera& camera, const Integrator& integrator, const EmbreeScene& geometry,
                 const std::vector<std::uint32_t>& shapes, std::uint64_t seed, int width, int height)
        : camera_(camera),
          integrator_(integrator),
          geometry_(geometry),
          shapes_(shapes),
          seed_(seed),
          width_(width),
          height_(height),
          invW_(1.0f / static_cast<float>(width)),
          invH_(1.0f / static_cast<float>(height)) {}

    int width() const override { return width_; }
    int height() const override { return height_; }

    PrimarySample sample(int x, int y, int sx, int sy, int k, bool withHit) const override {
        ThreadCounters& counters = counters_.local();
        PrimarySample s;
        const glm::vec3 L = radiance(x, y, sx, sy, k, counters, withHit ? &s : nullptr);
        s.finite = isFinite(L);
        if (s.finite) s.radiance = L;
        else ++counters.nonFinite;
        return s;
    }

    // The hot path of uniform/aamap sampling: one thread-local lookup per pixel.
    glm::vec3 pixel(int x, int y, int k) const override {
        ThreadCounters& counters = counters_.local();
        glm::dvec3 sum(0.0);
        int kept = 0;
        for (int sy = 0; sy < k; ++sy) {
            for (int sx = 0; sx < k; ++sx) {
                const glm::vec3 L = radiance(x, y, sx, sy, k, counters, nullptr);
                if (!isFinite(L)) {
                    ++counters.nonFinite;
                    continue;
                }
                sum += glm::dvec3(L);
                ++kept;
            }
        }
        return kept > 0 ? glm::vec3(sum / static_cast<double>(kept)) : glm::vec3(0.0f);
    }

    void addCounts(TraceResult& result) const {
        for (const ThreadCounters& c : counters_) {
            result.rays.primary += c.rays.primary;
            result.rays.shadow += c.rays.shadow;
            result.rays.other += c.rays.other;
            result.nonFiniteSamples += c.nonFinite;
        }
    }

private:
    glm::vec3 radiance(int x, int y, int sx, int sy, int k, ThreadCounters& counters, PrimarySample* hit) const {
        const std::uint64_t pixelIndex = static_cast<std::uint64_t>(y) * width_ + x;
        const Sampler sampler(pixelIndex, static_cast<std::uint32_t>(sy * k + sx), seed_);
        const glm::vec2 j = sampler.stratified2D(dims::kFilm, sx, sy, k);
        // Film point exactly as the rasteriser defines pixel (x, y).
        const float u = (static_cast<float>(x) + j.x) * invW_;
        const float v = (static_cast<float>(y) + j.y) * invH_;
        const glm::vec3 dir = glm::normalize(camera_.direction(u, v));
        if (hit != nullptr) probe(dir, *hit, counters.rays);
        return integrator_.primary(camera_.origin, dir, sampler, counters.rays);
    }

    // Depth and shape of the primary hit for the rpict and shape-id criteria. The integrator does
    // not report its primary hit, so this traces the same ray once more (counted in rays.other).
    void probe(const glm::vec3& dir, PrimarySample& s, RayCounts& rays) const {
        RTCIntersectContext context;
        rtcInitIntersectContext(&context);
        RTCRayHit rh = makeRayHit(camera_.origin, dir);
        rtcIntersect1(geometry_.handle(), &context, &rh);
        ++rays.other;
        if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return;  // a miss: depth +inf, kNoShape
        s.depth = rh.ray.tfar;
        s.shape = rh.hit.primID < shapes_.size() ? shapes_[rh.hit.primID] : geometry_.triangle(rh.hit.primID).material;
    }

    const PinholeCamera& camera_;
    const Integrator& integrator_;
    const EmbreeScene& geometry_;
    const std::vector<std::uint32_t>& shapes_;
    std::uint64_t seed_;
    int width_, height_;
    float invW_, invH_;
    mutable tbb::enumerable_thread_specific<ThreadCounters> counters_;
};

}  // namespace

struct Tracer::Impl {
    EmbreeScene geometry;
    LightSet lights;
    std::vector<std::uint32_t> shapes;  // per triangle: the object it came from (shape-id sampling)
    explicit Impl(const Scene& scene)
        : geometry(scene), lights(buildLights(scene, geometry)), shapes(scene.mesh.objectIds) {}
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
    const PinholeCamera camera = PinholeCamera::fromView(view);
    // Cache mode: builds the irradiance cache (its pre-pass) and the Integrator that reads it.
    const RenderShading shading =
        makeRenderShading(impl_->geometry, impl_->lights, settings.shading, camera, W, H, settings.threads);
    const Integrator& integrator = *shading.integrator;
    const EmbreeSource source(camera, integrator, impl_->geometry, impl_->shapes, settings.seed, W, H);

    StrategyImages images(W, H);
    Scheduler scheduler(W, H, settings.onTileDone);
    scheduler.expectTilePhases(strategy->tilePhases());
    const int threads = settings.threads > 0 ? settings.threads : tbb::info::default_concurrency();
    tbb::task_arena arena(threads);
    arena.execute([&] { strategy->render(source, scheduler, images); });

    TraceResult result;
    result.image = std::move(images.image);
    result.primaryRays = std::move(images.primaryRays);
    result.traced = std::move(images.traced);
    result.strategy = strategy->describe();
    source.addCounts(result);
    result.cache = shading.stats();
    result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return result;
}

}  // namespace aamap
