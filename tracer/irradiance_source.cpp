#include "tracer/irradiance_source.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>

#include <glm/geometric.hpp>
#include <spdlog/spdlog.h>

#include "scene/camera.h"
#include "tracer/bsdf.h"

namespace aamap {
namespace {

// Where the current thread's hemisphere rays are charged: the render's per-thread counts while
// indirectIrradiance() runs on it (a miss computes its record serially on the calling thread),
// null during build(), whose rays go to the pre-pass counts.
thread_local RayCounts* tRenderRays = nullptr;

Bounds triangleBounds(const EmbreeScene& geometry) {
    Bounds b;
    if (geometry.triangleCount() == 0) return b;
    b.lo = glm::vec3(std::numeric_limits<float>::infinity());
    b.hi = -b.lo;
    for (std::uint32_t i = 0; i < geometry.triangleCount(); ++i) {
        const Triangle& t = geometry.triangle(i);
        for (const glm::vec3& v : {t.v0, t.v0 + t.e1, t.v0 + t.e2}) {
            b.lo = glm::min(b.lo, v);
            b.hi = glm::max(b.hi, v);
        }
    }
    return b;
}

}  // namespace

IrradianceSource::IrradianceSource(const IrradianceCacheSettings& settings, const Bounds& sceneBounds,
                                   const EmbreeScene& geometry, const LightSet& lights, const ShadingSettings& shading)
    : direct_(geometry, lights, shading),
      cache_(settings, sceneBounds, [this](const glm::vec3& o, const glm::vec3& d, int depth, std::uint64_t seed) {
          return radiance(o, d, depth, seed);
      }) {}

namespace {

// The normal the cache is asked about. A normal or bump map's tilted normal is not: the cache's
// hemisphere is not clipped by the surface, so a tilted one would gather the surface itself
// (light a path tracer rejects); a mapped hit takes its irradiance about the geometric normal.
glm::vec3 cacheNormal(const SurfaceHit& hit) { return hit.material->perturbed() ? hit.geometric : hit.shading; }

}  // namespace

void IrradianceSource::build(std::span<const CachePoint> points) {
    RayCounts* const previous = tRenderRays;
    tRenderRays = nullptr;  // the calling thread takes part in the pre-pass too
    cache_.build(points);
    tRenderRays = previous;
}

glm::vec3 IrradianceSource::indirectIrradiance(const SurfaceHit& hit, const Sampler&, int, RayCounts& rays) const {
    RayCounts* const previous = tRenderRays;
    tRenderRays = &rays;
    const glm::vec3 e = cache_.irradiance(hit.position, cacheNormal(hit), 0);
    tRenderRays = previous;
    return e;
}

RayCounts IrradianceSource::prepassRays() const {
    RayCounts sum;
    for (const RayCounts& r : prepassRays_) {
        sum.primary += r.primary;
        sum.shadow += r.shadow;
        sum.other += r.other;
    }
    return sum;
}

RadianceSample IrradianceSource::radiance(const glm::vec3& origin, const glm::vec3& dir, int depth,
                                          std::uint64_t seed) const {
    RayCounts& rays = tRenderRays != nullptr ? *tRenderRays : prepassRays_.local();
    RadianceSample s;
    SurfaceHit hit;
    if (!direct_.intersect(origin, dir, hit, rays.other)) return s;
    s.distance = hit.distance;
    const ShadingMaterial& m = *hit.material;
    // Hidden light sources: an emitter's own emission is left out (L never adds Ke), since every
    // diffuse hit samples its direct light already (Radiance does the same to ambient rays). What
    // an emitter reflects is not hidden: a glowing wall with an albedo passes light on.
    const Sampler sampler(seed, 0, 0);
    glm::vec3 L(0.0f);
    if (m.kind != MaterialKind::Diffuse) L += specular(hit, sampler, depth, rays);
    else if (m.diffuse || m.glossy) L += direct_.directLight(hit, sampler, depth, rays);
    if (m.diffuse && depth < cache_.settings().bounces)
        L += bsdf::lambertEquivalent(m, hit.albedo, glm::dot(hit.wo, hit.shading)) * bsdf::kInvPi *
             cache_.irradiance(hit.position, cacheNormal(hit), depth);
    s.radiance = L;
    return s;
}

// A mirror or glass hit: its Lambert part's direct light, then each specular branch continues with
// radianceDirect (Direct shading, emission included: light seen in a mirror is not sampled as
// direct light). The branches are those of DirectIntegrator::shadeDirect (sumSpecularBranches).
glm::vec3 IrradianceSource::specular(const SurfaceHit& hit, const Sampler& sampler, int depth,
                                     RayCounts& rays) const {
    const ShadingMaterial& m = *hit.material;
    glm::vec3 L(0.0f);
    if (m.diffuse) L += direct_.directLight(hit, sampler, depth, rays);
    if (direct_.settings().maxSpecularDepth < 1) return L;
    const glm::vec3 tint = m.kind == MaterialKind::Mirror
                               ? bsdf::deltaReflectance(m, std::clamp(glm::dot(hit.wo, hit.shading), 0.0f, 1.0f))
                               : m.ks;
    const auto follow = [&](const glm::vec3& d, float branch) {
        if (branch * bsdf::maxComponent(tint) < 1e-3f) return glm::vec3(0.0f);  // shadeDirect's cutoff
        return tint * branch * direct_.radianceDirect(hit.originFor(d), d, sampler, depth + 1, rays);
    };
    L += sumSpecularBranches(hit, follow);
    return L;
}

CacheStats RenderShading::stats() const {
    CacheStats s = prepass;
    if (!source) return s;
    const IrradianceCacheStats c = source->cache().stats();
    s.misses = c.renderMisses;
    s.missRays = c.renderRays;
    spdlog::info("irradiance cache: {} records, pre-pass {:.3f} s, {} rays; {} misses in the render ({} hemisphere rays)",
                 s.records, s.prepassSeconds, s.prepassRays.total(), s.misses, s.missRays);
    return s;
}

namespace {

// The pre-pass's rays: the cache's own, plus the candidate grid's camera rays as primary.
RayCounts prepassRaysOf(const IrradianceSource& source, const CacheStats& s) {
    RayCounts r = source.prepassRays();
    r.primary += static_cast<std::uint64_t>(s.gridWidth) * static_cast<std::uint64_t>(s.gridHeight);
    return r;
}

}  // namespace

void RenderShading::addProbedRecords(const RayCounts& probeRays, double probeSeconds) {
    const auto start = std::chrono::steady_clock::now();
    const std::vector<CachePoint> missed = source->takeMisses();
    if (!missed.empty()) source->build(missed);
    CacheStats& s = prepass;
    s.probed = missed.size();
    s.records = source->cache().stats().records;
    s.prepassRays = prepassRaysOf(*source, s);
    s.probeRays = probeRays;
    s.prepassSeconds += probeSeconds + std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    spdlog::info("irradiance cache: the probe render found {} points no record covered", missed.size());
}

void cacheGrid(int width, int height, int step, int& gridW, int& gridH) {
    step = std::max(step, 1);
    gridW = std::max((width + step - 1) / step, std::min(width, 32));
    gridH = std::max((height + step - 1) / step, std::min(height, 32));
}

RenderShading makeRenderShading(const EmbreeScene& geometry, const LightSet& lights, const ShadingSettings& shading,
                                const PinholeCamera& camera, int width, int height, int threads) {
    RenderShading out;
    if (!readsIndirectDiffuse(shading)) {
        out.integrator = makeIntegrator(geometry, lights, shading);
        return out;
    }
    const auto start = std::chrono::steady_clock::now();
    IrradianceCacheSettings settings = shading.cache;
    if (settings.threads == 0) settings.threads = threads;
    out.source = std::make_unique<IrradianceSource>(settings, triangleBounds(geometry), geometry, lights, shading);
    out.integrator = makeIntegrator(geometry, lights, shading, out.source.get());
    int gridW = 0, gridH = 0;
    cacheGrid(width, height, shading.cache.gridStep, gridW, gridH);
    const std::vector<CachePoint> points = cameraCachePoints(geometry, camera, gridW, gridH);
    out.source->build(points);

    CacheStats& s = out.prepass;
    s.built = true;
    s.gridWidth = gridW;
    s.gridHeight = gridH;
    s.candidates = points.size();
    s.records = out.source->cache().stats().records;
    s.prepassRays = prepassRaysOf(*out.source, s);
    s.prepassSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return out;
}

}  // namespace aamap
