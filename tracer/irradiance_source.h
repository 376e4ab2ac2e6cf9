#pragma once
// Cache mode's indirect diffuse light (docs/tracer.md, the shading budget): an IndirectDiffuseSource over the
// irradiance cache, whose hemisphere rays are shaded as Direct mode shades (its own
// DirectIntegrator). Wiring, ray accounting and the candidate grid: docs/irradiance-cache.md, "Wiring".
#include <memory>
#include <span>

#include <glm/vec3.hpp>
#include <tbb/enumerable_thread_specific.h>

#include "tracer/cache_integrator.h"
#include "tracer/direct_integrator.h"
#include "tracer/irradiance_cache.h"
#include "tracer/tracer_types.h"

namespace aamap {

struct PinholeCamera;

class IrradianceSource final : public IndirectDiffuseSource {
public:
    // `sceneBounds` sets the cache's scale (-ar). The hemisphere rays' hits are shaded with
    // `shading` as Direct mode shades them (geometry and lights must outlive the source). The
    // cache is empty until build().
    IrradianceSource(const IrradianceCacheSettings& settings, const Bounds& sceneBounds, const EmbreeScene& geometry,
                     const LightSet& lights, const ShadingSettings& shading);

    // The pre-pass: records at `points` (and what their interpolation needs).
    void build(std::span<const CachePoint> points);

    // E at the hit from the frozen cache (level 0). Rays of a miss are charged to `rays`.
    glm::vec3 indirectIrradiance(const SurfaceHit& hit, const Sampler& sampler, int depth,
                                 RayCounts& rays) const override;

    const IrradianceCache& cache() const { return cache_; }
    // Probe mode and the points it found uncovered (IrradianceCache::setProbe, takeMisses).
    void setProbe(bool on) { cache_.setProbe(on); }
    std::vector<CachePoint> takeMisses() { return cache_.takeMisses(); }
    // Rays traced by build() (hemisphere rays and what their shading traced), summed over threads.
    RayCounts prepassRays() const;

    // The cache's RadianceFn: what arrives at `origin` along -dir. Light sources are black (their
    // direct light is sampled at every diffuse hit already, as Radiance hides sources from ambient
    // rays); a diffuse hit reflects its direct light plus, for depth < bounces, albedo/pi times the
    // cache at level `depth`; mirror and glass follow their specular branches with Direct shading.
    RadianceSample radiance(const glm::vec3& origin, const glm::vec3& dir, int depth, std::uint64_t seed) const;

private:
    glm::vec3 specular(const SurfaceHit& hit, const Sampler& sampler, int depth, RayCounts& rays) const;

    // The hemisphere rays' shading: Direct's, which never reads this source (no lookups under
    // radianceDirect or directLight), so the render's own integrator would shade them alike.
    DirectIntegrator direct_;
    IrradianceCache cache_;
    mutable tbb::enumerable_thread_specific<RayCounts> prepassRays_;
};

// What a render shades with: in Cache mode with bounces > 0 an IrradianceSource whose pre-pass
// has run, and the integrator that reads it; otherwise just the integrator (Cache mode with
// bounces 0 shades exactly as Direct). Members in this order: the integrator goes first.
struct RenderShading {
    std::unique_ptr<IrradianceSource> source;  // null without a cache
    std::unique_ptr<Integrator> integrator;
    CacheStats prepass;                         // filled by makeRenderShading and addProbedRecords

    // After a probe render (source->setProbe): records for the points it found uncovered, then
    // `prepass` updated (records, rays with the probe's own, seconds).
    void addProbedRecords(const RayCounts& probeRays, double probeSeconds);

    // `prepass` plus the cache's misses during the render; logs them (many misses: the candidate
    // grid is too coarse for the view).
    CacheStats stats() const;
};

// Candidate grid for a W x H render: ceil(W/step) x ceil(H/step), but at least min(W, 32) x
// min(H, 32) so that small images still get a useful pre-pass.
void cacheGrid(int width, int height, int step, int& gridW, int& gridH);

// Builds the shading for one render: the integrator makeIntegrator picks for shading.mode and, for
// one that reads an indirect source, the source and its pre-pass over the first hits of the
// camera's candidate grid. `threads` (0 = all) is used when shading.cache.threads is 0.
RenderShading makeRenderShading(const EmbreeScene& geometry, const LightSet& lights, const ShadingSettings& shading,
                                const PinholeCamera& camera, int width, int height, int threads);

}  // namespace aamap
