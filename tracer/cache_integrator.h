#pragma once
// Cache mode (docs/tracer.md, the shading budget): Direct shading plus the indirect diffuse light
// an IndirectDiffuseSource (the irradiance cache, tracer/irradiance_source.h) gives at the diffuse
// hits under a primary ray, the hits of glossy samples included.
#include "tracer/direct_integrator.h"

namespace aamap {

// Indirect diffuse light for CacheIntegrator (implemented by the irradiance cache).
class IndirectDiffuseSource {
public:
    virtual ~IndirectDiffuseSource() = default;
    // Indirect irradiance E (W/m^2) at a diffuse hit, about hit.shading; the integrator reflects
    // hit.albedo / pi * E. Counts the rays it traces in `rays`.
    virtual glm::vec3 indirectIrradiance(const SurfaceHit& hit, const Sampler& sampler, int depth,
                                         RayCounts& rays) const = 0;
};

class CacheIntegrator final : public DirectIntegrator {
public:
    // `indirect` is not owned and must outlive the integrator.
    CacheIntegrator(const EmbreeScene& geometry, const LightSet& lights, const ShadingSettings& shading,
                    const IndirectDiffuseSource& indirect);

protected:
    void addIndirectDiffuse(const SurfaceHit& hit, const Sampler& sampler, int depth, RayCounts& rays,
                            glm::vec3& L) const override;

private:
    const IndirectDiffuseSource& indirect_;
};

}  // namespace aamap
