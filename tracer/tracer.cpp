#include "tracer/tracer.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <vector>

#include <fmt/format.h>
#include <glm/geometric.hpp>
#include <glm/vec3.hpp>
#include <spdlog/spdlog.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/info.h>
#include <tbb/task_arena.h>

#include "scene/camera.h"
#include "tracer/embree_scene.h"
#include "tracer/integrator.h"
#include "tracer/irradiance_source.h"
#include "tracer/lights.h"
#include "tracer/pixel_facts.h"
#include "tracer/ray_packet.h"
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
                 const std::vector<std::uint32_t>& shapes, std::uint64_t seed, int width, int height,
                 const PixelFilter& filter)
        : camera_(camera),
          integrator_(integrator),
          geometry_(geometry),
          shapes_(shapes),
          seed_(seed),
          width_(width),
          height_(height),
          invW_(1.0f / static_cast<float>(width)),
          invH_(1.0f / static_cast<float>(height)),
          // The angle one pixel subtends on the view axis (the geometric mean of its sides).
          pixelAngle_(std::sqrt(2.0f * camera.tanHalfH * invW_ * 2.0f * camera.tanHalfV * invH_)),
          filter_(filter) {}

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

    // The hot path of uniform/aamap sampling: one thread-local lookup per pixel. With k > 1 the
    // k x k primary rays of the pixel are coherent (one origin, directions within a pixel): they
    // are traced as Embree packets of the width the integrator asks for (Integrator::packetWidth:
    // 8 wide, 4 wide for the last 2-4, singly for a last one), then shaded in sample order
    // (Integrator::primaryPacket), so the sum (and the image) is the same as tracing them singly.
    // Path mode advances a packet's lanes as paths in lockstep, its last 2-4 in an 8-wide packet too.
    glm::vec3 pixel(int x, int y, int k) const override {
        ThreadCounters& counters = counters_.local();
        glm::dvec3 sum(0.0);
        int kept = 0;
        const auto accumulate = [&](const glm::vec3& L) {
            if (!isFinite(L)) {
                ++counters.nonFinite;
                return;
            }
            sum += glm::dvec3(L);
            ++kept;
        };
        tracePackets(x, y, k, k * k, [](int i) { return i; }, counters, accumulate);
        return kept > 0 ? glm::vec3(sum / static_cast<double>(kept)) : glm::vec3(0.0f);
    }

    Halves pixelHalves(int x, int y, int k) const override {
        ThreadCounters& counters = counters_.local();
        glm::dvec3 sum(0.0), half[2] = {glm::dvec3(0.0), glm::dvec3(0.0)};
        int kept = 0, halfKept[2] = {0, 0}, index = 0;
        const auto accumulate = [&](const glm::vec3& L) {
            const int i = index++, side = (i % k + i / k) & 1;
            if (!isFinite(L)) {
                ++counters.nonFinite;
                return;
            }
            sum += glm::dvec3(L);  // in pixel()'s order, so the mean is pixel()'s
            ++kept;
            half[side] += glm::dvec3(L);
            ++halfKept[side];
        };
        tracePackets(x, y, k, k * k, [](int i) { return i; }, counters, accumulate);
        return halvesOf(sum, kept, half, halfKept);
    }

    // The same packets for a batch of strata of one pixel (the variance strategy's rounds).
    void samples(int x, int y, const int* strata, int count, int k, PrimarySample* out) const override {
        ThreadCounters& counters = counters_.local();
        int done = 0;
        const auto store = [&](const glm::vec3& L) {
            PrimarySample& s = out[done++];
            s = PrimarySample{};
            s.finite = isFinite(L);
            if (s.finite) s.radiance = L;
            else ++counters.nonFinite;
        };
        tracePackets(x, y, k, count, [strata](int i) { return strata[i]; }, counters, store);
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
    // Samples index(0), ..., index(count - 1) of pixel (x, y), handed to `accumulate` in that
    // order, in packets as wide as the integrator asks for the samples left.
    template <class Index, class Accumulate>
    void tracePackets(int x, int y, int k, int count, const Index& index, ThreadCounters& counters,
                      Accumulate& accumulate) const {
        for (int first = 0; first < count;) {
            const int left = count - first;
            const auto from = [&index, first](int lane) { return index(first + lane); };
            const int width = integrator_.packetWidth(left);
            if (width == 1) {
                const int s = index(first);
                accumulate(radiance(x, y, s % k, s / k, k, counters, nullptr));
                ++first;
            } else if (width == 4) {
                first += tracePacket<4>(x, y, k, from, std::min(left, 4), counters, accumulate);
            } else {
                constexpr int W = Integrator::kMaxPacket;
                first += tracePacket<W>(x, y, k, from, std::min(left, W), counters, accumulate);
            }
        }
    }

    // Samples index(0), ..., index(count - 1) of pixel (x, y) as one packet of primary rays,
    // shaded by the integrator and handed to `accumulate` in that order; returns count.
    template <int W, class Index, class Accumulate>
    int tracePacket(int x, int y, int k, const Index& index, int count, ThreadCounters& counters,
                    Accumulate& accumulate) const {
        RayPacket<W> packet;
        for (int lane = 0; lane < count; ++lane) {
            const int s = index(lane);
            packet.set(lane, camera_.origin, direction(x, y, s % k, s / k, k));
        }
        packet.traceFirst(geometry_.handle(), count, true);
        Sampler samplers[W];
        float spreads[W];
        glm::vec3 L[W];
        for (int lane = 0; lane < count; ++lane) {
            samplers[lane] = Sampler(pixelIndex(x, y), static_cast<std::uint32_t>(index(lane)), seed_);
            spreads[lane] = spread(packet.dir[lane], k);
        }
        integrator_.primaryPacket(packet, count, samplers, spreads, L, counters.rays);
        for (int lane = 0; lane < count; ++lane) accumulate(L[lane]);
        return count;
    }

    std::uint64_t pixelIndex(int x, int y) const { return static_cast<std::uint64_t>(y) * width_ + x; }

    // The unit direction of stratum (sx, sy) of pixel (x, y): jittered by the sample's own sampler,
    // then placed by the pixel filter (the identity for the default box).
    glm::vec3 direction(int x, int y, int sx, int sy, int k) const {
        const Sampler sampler(pixelIndex(x, y), static_cast<std::uint32_t>(sy * k + sx), seed_);
        const glm::vec2 j = filter_.positionInPixel(sampler.stratified2D(dims::kFilm, sx, sy, k));
        // Film point exactly as the rasteriser defines pixel (x, y).
        const float u = (static_cast<float>(x) + j.x) * invW_;
        const float v = (static_cast<float>(y) + j.y) * invH_;
        return glm::normalize(camera_.direction(u, v));
    }

    // The cone angle of one of the k x k rays of a pixel along unit `dir`: its stratum's share of
    // the pixel, which shrinks off the view axis as cos^2 radially and cos across (their mean).
    float spread(const glm::vec3& dir, int k) const {
        const float c = std::max(glm::dot(dir, camera_.forward), 0.0f);
        return pixelAngle_ * c * std::sqrt(c) / static_cast<float>(k);
    }

    glm::vec3 radiance(int x, int y, int sx, int sy, int k, ThreadCounters& counters, PrimarySample* hit) const {
        const Sampler sampler(pixelIndex(x, y), static_cast<std::uint32_t>(sy * k + sx), seed_);
        const glm::vec3 dir = direction(x, y, sx, sy, k);
        if (hit != nullptr) probe(dir, *hit, counters.rays);
        return integrator_.primary(camera_.origin, dir, sampler, counters.rays, spread(dir, k));
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
    float pixelAngle_;
    const PixelFilter& filter_;
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

PixelFacts Tracer::pixelFacts(const View& view, int width, int height, int threads) const {
    if (width <= 0 || height <= 0) throw std::invalid_argument(fmt::format("facts size {}x{} is empty", width, height));
    return tracePixelFacts(impl_->geometry, impl_->lights, impl_->shapes, PinholeCamera::fromView(view), width, height,
                           threads);
}

TraceResult Tracer::render(const View& view, const TraceSettings& settings, const StrategySettings& strategySettings) const {
    const auto start = std::chrono::steady_clock::now();
    const int W = settings.width, H = settings.height;
    if (W <= 0 || H <= 0) throw std::invalid_argument(fmt::format("render size {}x{} is empty", W, H));
    if (settings.threads < 0) throw std::invalid_argument(fmt::format("threads must be >= 0, got {}", settings.threads));
    const auto strategy = makeStrategy(strategySettings, W, H);
    const PixelFilter filter(settings.filter);  // checks its settings before any work
    // Convolution mode: the strategy renders box pixels, and the filter applies to the image.
    const bool convolve = settings.filter.mode == PixelFilterMode::Convolution;
    const PixelFilter pixelBox;
    const PixelFilter& filmFilter = convolve ? pixelBox : filter;
    const PinholeCamera camera = PinholeCamera::fromView(view);
    // The integrator for the shading mode; in Cache mode also the irradiance cache it reads (its
    // pre-pass done).
    RenderShading shading =
        makeRenderShading(impl_->geometry, impl_->lights, settings.shading, camera, W, H, settings.threads);
    const Integrator& integrator = *shading.integrator;
    const EmbreeSource source(camera, integrator, impl_->geometry, impl_->shapes, settings.seed, W, H, filmFilter);

    StrategyImages images(W, H);
    const StrategyDescriptor* descriptor = findStrategy(strategySettings.name);
    if (descriptor != nullptr && descriptor->splitsHalves && strategySettings.strata >= 2) images.halfDifference = ImageRGB(W, H);
    Scheduler scheduler(W, H, settings.onTileDone);
    scheduler.expectTilePhases(strategy->tilePhases());
    if (settings.onTileFinished)
        scheduler.onTileFinished([&](int x0, int y0, int x1, int y1) {
            settings.onTileFinished({x0, y0, x1, y1, images.image, images.primaryRays});
        });
    const int threads = settings.threads > 0 ? settings.threads : tbb::info::default_concurrency();
    tbb::task_arena arena(threads);
    if (shading.source) {
        // Cache mode: the strategy renders once with lookups that no record covers left out (the
        // image is dropped), records are built for the points they needed, and then the render
        // proper finds a record wherever its samples land (docs/irradiance-cache.md, "Probe").
        const auto probeStart = std::chrono::steady_clock::now();
        spdlog::info("irradiance cache: probe render (the points no record covers)");
        shading.source->setProbe(true);
        const EmbreeSource probe(camera, integrator, impl_->geometry, impl_->shapes, settings.seed, W, H, filmFilter);
        StrategyImages scratch(W, H);
        arena.execute([&] { strategy->render(probe, Scheduler(W, H), scratch); });
        shading.source->setProbe(false);
        TraceResult probeCounts;
        probe.addCounts(probeCounts);
        shading.addProbedRecords(probeCounts.rays,
                                 std::chrono::duration<double>(std::chrono::steady_clock::now() - probeStart).count());
    }
    arena.execute([&] { strategy->render(source, scheduler, images); });

    TraceResult result;
    // Weights are the kernel's alone, not the neighbours' sample counts: a count-weighted splat
    // would let an edge pixel of many rays outweigh its one-ray neighbours.
    result.image = convolve ? filter.convolve(images.image) : std::move(images.image);
    if (!images.halfDifference.empty())  // linear in the samples: filtered as the image is
        result.halfDifference = convolve ? filter.convolve(images.halfDifference) : std::move(images.halfDifference);
    result.primaryRays = std::move(images.primaryRays);
    result.traced = std::move(images.traced);
    result.strategy = strategy->describe();
    source.addCounts(result);
    result.cache = shading.stats();
    result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return result;
}

}  // namespace aamap
