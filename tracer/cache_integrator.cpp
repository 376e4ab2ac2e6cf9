#include "tracer/cache_integrator.h"

#include <glm/geometric.hpp>

#include "tracer/bsdf.h"

namespace aamap {

CacheIntegrator::CacheIntegrator(const EmbreeScene& geometry, const LightSet& lights, const ShadingSettings& shading,
                                 const IndirectDiffuseSource& indirect)
    : DirectIntegrator(geometry, lights, shading, "cache"), indirect_(indirect) {}

void CacheIntegrator::addIndirectDiffuse(const SurfaceHit& hit, const Sampler& sampler, int depth, RayCounts& rays,
                                         glm::vec3& L) const {
    // The hit's diffuse lobe as a Lambert surface of the same reflectance towards the viewer.
    L += bsdf::lambertEquivalent(*hit.material, hit.albedo, glm::dot(hit.wo, hit.shading)) * bsdf::kInvPi *
         indirect_.indirectIrradiance(hit, sampler, depth, rays);
}

}  // namespace aamap
