#pragma once
// Direct mode (docs/tracer.md, the shading budget): emission, direct light from every light type
// (point lights one shadow ray each, area lights an m x m stratified pattern per hit traced as
// 8-wide packets; with many lights, m x m samples spread over a per-hit contribution CDF, or the
// global power CDF, their shadow rays traced 8 at a time too), BSDF samples of glossy lobes (their
// emission hits MIS-weighted against the light samples, what else they hit shaded as Direct shades
// it) and mirror/glass recursion. The irradiance cache shades its hemisphere rays with one
// (radianceDirect, directLight), and CacheIntegrator adds the cache's light to it.
#include "tracer/integrator.h"

namespace aamap {

class DirectIntegrator : public Integrator {
public:
    DirectIntegrator(const EmbreeScene& geometry, const LightSet& lights, const ShadingSettings& shading);

    // What Direct mode sees along a secondary ray (emission + direct light + specular recursion;
    // never an indirect source's light), depth = path vertex index for the sampler dimensions.
    // Counts its rays in `rays` (this ray in rays.other).
    glm::vec3 radianceDirect(const glm::vec3& origin, const glm::vec3& dir, const Sampler& sampler, int depth,
                             RayCounts& rays) const;
    // Reflected radiance towards hit.wo from direct light (all light types), non-delta lobes only,
    // by light samples alone (m x m per area light).
    glm::vec3 directLight(const SurfaceHit& hit, const Sampler& sampler, int depth, RayCounts& rays) const;

protected:
    DirectIntegrator(const EmbreeScene& geometry, const LightSet& lights, const ShadingSettings& shading,
                     const char* name);

    glm::vec3 shadeCamera(const SurfaceHit& hit, const Sampler& sampler, RayCounts& rays) const final;
    // Adds to L the indirect diffuse light a diffuse hit under a primary ray reflects (Direct: none;
    // CacheIntegrator: the cache's). Called once per such hit, never for the cache's own rays.
    virtual void addIndirectDiffuse(const SurfaceHit& /*hit*/, const Sampler& /*sampler*/, int /*depth*/,
                                    RayCounts& /*rays*/, glm::vec3& /*L*/) const {}

private:
    // What direct light at a hit spends: grid m (m x m light samples per area light, or in all
    // with many lights, and for the environment) and the glossy samples taken there, against
    // which the light samples' glossy part is MIS-weighted (0: light samples alone).
    struct LightBudget {
        int grid;
        int glossySamples;
    };
    glm::vec3 directLight(const SurfaceHit& hit, const Sampler& sampler, int depth, LightBudget budget,
                          RayCounts& rays) const;
    // Direct/Cache shading of a hit, following mirror/glass bounces and glossy samples up to
    // maxSpecularDepth. emission: the weight of the hit's own emission (an MIS weight under a
    // glossy sample). grid: the light grid m here (0: ShadingSettings' own).
    glm::vec3 shadeDirect(const SurfaceHit& hit, const Sampler& sampler, int depth, int specular, float weight,
                          RayCounts& rays, float emission = 1.0f, int grid = 0) const;
    // How many BSDF samples of the glossy lobe shadeDirect takes at a hit (0: none).
    int glossySampleCount(const ShadingMaterial& m, int specular, float weight) const;
    // The glossy lobe's reflection of the scene: `count` BSDF samples, what each hits shaded as
    // shadeDirect shades (emission MIS-weighted against the light samples); escaping samples add
    // nothing (the environment is direct light, environmentDirect).
    // Their hits take grid / g light samples per axis (at least 1), so the g x g subtrees together
    // take about as many light samples as the hit itself.
    glm::vec3 glossyReflection(const SurfaceHit& hit, const Sampler& sampler, int depth, int specular, float weight,
                               int count, int grid, RayCounts& rays) const;
    // The solid-angle density with which directLight's light samples at `from` reach point `at`
    // (a hit on area light `area`, seen along at.wo), summed over its samples: n_light pdf.
    float lightSamplesPdf(const SurfaceHit& from, const SurfaceHit& at, std::size_t area, int grid) const;
    glm::vec3 traceSpecular(const glm::vec3& origin, const glm::vec3& dir, RayCone cone, const Sampler& sampler,
                            int depth, int specular, float weight, int grid, RayCounts& rays) const;
    glm::vec3 directFewLights(const SurfaceHit& hit, const Sampler& sampler, int depth, LightBudget budget,
                              RayCounts& rays) const;
    glm::vec3 directManyLights(const SurfaceHit& hit, const Sampler& sampler, int depth, LightBudget budget,
                               RayCounts& rays) const;
    // Many lights, LightSelection::Contribution: samples distributed over a per-hit CDF.
    glm::vec3 directPerHitLights(const SurfaceHit& hit, const Sampler& sampler, int depth, LightBudget budget,
                                 RayCounts& rays) const;
    // The view of the last area light sampled from one hit: per-hit selection takes runs of
    // samples from one light, which then share its solid angles and sampling setup.
    struct LastLightView {
        std::size_t light = ~std::size_t{0};
        LightView view;
    };
    // One shadow sample of light l for the many-light paths, divided by its selection probability,
    // before its shadow ray: what it adds if the segment origin -> target (t up to tfar) is clear.
    struct PendingShadow {
        glm::vec3 target;
        glm::vec3 contribution;
        float tfar;
    };
    // False if the sample adds nothing whatever the visibility (faces away, zero weight).
    // budget: as directLight's (the glossy lobe's part is MIS-weighted against its glossy samples).
    bool prepareLightSample(const SurfaceHit& hit, std::size_t l, glm::vec2 u, float pick, LightBudget budget,
                            LastLightView& last, PendingShadow& out) const;
    // Traces the shadow rays of count <= 8 prepared samples from `origin` as one packet; the sum
    // of the contributions of those that reach their light, in sample order.
    glm::vec3 traceLightSamples(const glm::vec3& origin, const PendingShadow* samples, int count,
                                RayCounts& rays) const;
    // The lights at infinity (directional lights one shadow ray each, the environment m x m light
    // and m x m BSDF samples with MIS; a constant environment BSDF samples only).
    glm::vec3 directInfinite(const SurfaceHit& hit, const Sampler& sampler, int depth, int grid, RayCounts& rays) const;
    glm::vec3 environmentDirect(const SurfaceHit& hit, const glm::vec3& origin, const Sampler& sampler, int depth,
                                int grid, RayCounts& rays) const;

    int lightGrid_;   // m: m x m samples per area light per hit
    int glossyGrid_;  // g: g x g glossy samples at a ray tree's first glossy hit (then 1)
};

}  // namespace aamap
