#pragma once
// Radiance along a ray: the shading budget (docs/tracer.md), separate from the primary-ray
// (antialiasing) budget. Three modes (ShadingSettings::mode):
// - Direct: emission, direct light from every light type (point lights one shadow ray each, area
//   lights an m x m stratified pattern per hit traced as 8-wide packets; with many lights, m x m
//   samples spread over a per-hit contribution CDF, or the global power CDF, their shadow rays
//   traced 8 at a time too), BSDF samples of glossy lobes (their emission hits MIS-weighted
//   against the light samples, what else they hit shaded as Direct shades it) and mirror/glass
//   recursion;
// - Cache: Direct plus indirect diffuse from an IndirectDiffuseSource (the irradiance cache);
// - Path: unbiased path tracing with next-event estimation, MIS and Russian roulette
//   (path_integrator.cpp).
#include <algorithm>
#include <cstdint>

#include <embree3/rtcore.h>
#include <glm/vec3.hpp>

#include "tracer/bsdf.h"
#include "tracer/embree_scene.h"
#include "tracer/lights.h"
#include "tracer/ray_offset.h"
#include "tracer/ray_packet.h"
#include "tracer/sampler.h"
#include "tracer/tracer_types.h"

namespace aamap {

// Random-number dimensions of the integrator beyond dims::areaLight (bit 63). Bit 62 marks these.
namespace dims {
// EnvLight, EnvBsdf, EnvLobe: the environment's light and BSDF samples (Direct/Cache: m x m each
// per hit; Path: one light sample per vertex).
enum class PathSlot : std::uint64_t {
    Light = 0, Bsdf = 1, Lobe = 2, Roulette = 3, ManyLights = 4, EnvLight = 5, EnvBsdf = 6, EnvLobe = 7,
    Glossy = 8  // Direct/Cache: the glossy lobe's BSDF samples at a hit
};
// Slot `slot` at path vertex `depth` (< 2^20), sample `sample` (< 2^24) within the slot.
constexpr std::uint64_t path(int depth, PathSlot slot, int sample = 0) {
    return (1ull << 62) | (static_cast<std::uint64_t>(depth) << 36) | (static_cast<std::uint64_t>(slot) << 28) |
           (2ull * static_cast<std::uint64_t>(sample));
}
}  // namespace dims

// MIS weight of a sample from the strategy with pdf a against one with pdf b (Veach's power
// heuristic, exponent 2).
inline float powerHeuristic(float a, float b) {
    const float a2 = a * a, b2 = b * b;
    return a2 + b2 > 0.0f ? a2 / (a2 + b2) : 0.0f;
}

// The segment origin + t dir, t in [0, tfar], that a shadow ray tests.
struct ShadowSegment {
    glm::vec3 origin, dir;
    float tfar;
};

// A ray's first hit, with what shading needs. Normals face the side the ray came from.
struct SurfaceHit {
    glm::vec3 position;   // rebuilt from the triangle (error relative to its vertices)
    glm::vec3 geometric;  // unit geometric normal on the viewer's side
    glm::vec3 shading;    // unit shading normal on the viewer's side
    glm::vec3 wo;         // unit direction back to the viewer
    glm::vec3 albedo;     // diffuse albedo here (texture applied)
    float offset;         // scale-aware self-intersection offset (ray_offset.h)
    float distance;       // along the (unit) ray
    RayCone cone;         // the ray's cone, its width taken here: rays leaving the hit carry it on
    std::uint32_t primitive;
    bool front;           // the triangle's front side (its winding) was hit
    const ShadingMaterial* material;

    // Where a ray leaving in direction `dir` starts: pushed off the surface to dir's side.
    glm::vec3 originFor(const glm::vec3& dir) const {
        const float s = dir.x * geometric.x + dir.y * geometric.y + dir.z * geometric.z;
        return position + (s >= 0.0f ? offset : -offset) * geometric;
    }
};

// The deterministic specular branches of a mirror or glass hit: calls follow(dir, weight) for the
// mirror direction (weight 1), or for glass's Fresnel-reflected (F) and refracted (1 - F)
// directions, skipping directions on the wrong side of the surface; returns the sum. Direct
// shading and the irradiance cache's hemisphere rays both split this way.
template <class Follow>
glm::vec3 sumSpecularBranches(const SurfaceHit& hit, Follow&& follow) {
    const ShadingMaterial& m = *hit.material;
    glm::vec3 L(0.0f);
    const glm::vec3 r = bsdf::reflect(hit.wo, hit.shading);
    const bool reflectionLeaves = glm::dot(r, hit.geometric) > 0.0f;
    if (m.kind == MaterialKind::Mirror) {
        if (reflectionLeaves) L += follow(r, 1.0f);
        return L;
    }
    const float cosI = std::min(glm::dot(hit.wo, hit.shading), 1.0f);
    if (!(cosI > 0.0f)) return L;
    if (m.thin) {  // a thin sheet: reflect 2R / (1 + R), the rest straight through
        const float R = bsdf::thinDielectricReflectance(cosI, m.ior);
        if (reflectionLeaves) L += follow(r, R);
        if (R < 1.0f) L += follow(-hit.wo, 1.0f - R);
        return L;
    }
    const float eta = hit.front ? m.ior : 1.0f / m.ior;
    float cosT = 0.0f;
    const float F = bsdf::fresnelDielectric(cosI, eta, cosT);
    if (reflectionLeaves) L += follow(r, F);
    if (F < 1.0f) {
        const glm::vec3 t = bsdf::refract(hit.wo, hit.shading, eta, cosI, cosT);
        // Radiance inside is eta^2 times what crosses out (Mitsuba's dielectric scales alike). The
        // branch's weight, which decides when a branch is too faint to follow, stays without the
        // factor (a closed object's entry and exit cancel it), as path mode's roulette does.
        if (glm::dot(t, hit.geometric) < 0.0f) L += follow(t, 1.0f - F) * (1.0f / (eta * eta));
    }
    return L;
}

class Integrator;

// The hook for indirect diffuse light in Cache mode (implemented by the irradiance cache).
class IndirectDiffuseSource {
public:
    virtual ~IndirectDiffuseSource() = default;
    // Indirect irradiance E (W/m^2) at a diffuse hit, about hit.shading; the integrator reflects
    // hit.albedo / pi * E. May call back into the integrator (radianceDirect, directLight).
    virtual glm::vec3 indirectIrradiance(const Integrator& integrator, const SurfaceHit& hit, const Sampler& sampler,
                                         int depth, RayCounts& rays) const = 0;
};

class Integrator {
public:
    // `indirect` is used in Cache mode only (not owned; may be null: then Cache shades as Direct).
    Integrator(const EmbreeScene& geometry, const LightSet& lights, const ShadingSettings& shading,
               const IndirectDiffuseSource* indirect = nullptr);

    // Radiance arriving at `origin` from unit direction -dir. Counts every ray it traces in `rays`
    // (the primary ray in rays.primary). Allocates nothing. spread: the angle (radians) the ray's
    // share of its pixel subtends, for texture filtering (0: unfiltered).
    glm::vec3 primary(const glm::vec3& origin, const glm::vec3& dir, const Sampler& sampler, RayCounts& rays,
                      float spread = 0.0f) const;
    // The same, for a primary ray the caller has already traced from `origin` along unit `dir`
    // (rh: its Embree result, e.g. one lane of a packet of coherent primary rays).
    glm::vec3 primaryFromHit(const RTCRayHit& rh, const glm::vec3& dir, const Sampler& sampler, RayCounts& rays,
                             float spread = 0.0f) const;
    // Path mode (ShadingMode::Path only): primaryFromHit for the lanes [0, count) of a packet of
    // primary rays already traced, each with its own sampler and spread, into out[0, count). Each
    // lane's radiance is the one primaryFromHit gives it; the paths' shadow and bounce rays are
    // traced as packets too.
    static constexpr int kPathPacket = 8;
    void primaryPaths(const RayPacket<kPathPacket>& primaries, int count, const Sampler* samplers,
                      const float* spreads, glm::vec3* out, RayCounts& rays) const;

    // Building blocks (also for the irradiance cache). intersect: false on a miss; counts the ray
    // in rays.other. radianceDirect: what Direct mode sees along a secondary ray (emission + direct
    // light + specular recursion; no cache), depth = path vertex index for the sampler dimensions.
    // cone: the footprint the ray brings from `origin` (hit.cone gets its width at the hit).
    bool intersect(const glm::vec3& origin, const glm::vec3& dir, SurfaceHit& hit, std::uint64_t& counter,
                   RayCone cone = {}) const;
    glm::vec3 radianceDirect(const glm::vec3& origin, const glm::vec3& dir, const Sampler& sampler, int depth,
                             RayCounts& rays) const;
    // Reflected radiance towards hit.wo from direct light (all light types), non-delta lobes only,
    // by light samples alone (m x m per area light).
    glm::vec3 directLight(const SurfaceHit& hit, const Sampler& sampler, int depth, RayCounts& rays) const;

    // Radiance of the environment along a ray that leaves the scene in unit direction `dir`
    // (black without one). Every mode returns it for escaping rays that are not hemisphere rays
    // of the irradiance cache (the environment is sampled as direct light there).
    glm::vec3 escaped(const glm::vec3& dir) const {
        return lights_.environment ? lights_.environment->radiance(dir) : glm::vec3(0.0f);
    }
    // A camera ray's escape: black when emitters are hidden from the camera.
    glm::vec3 escapedCamera(const glm::vec3& dir) const {
        return shading_.hideEmitters ? glm::vec3(0.0f) : escaped(dir);
    }

    int areaLightGrid() const { return lightGrid_; }  // m: m x m samples per area light per hit
    const ShadingSettings& settings() const { return shading_; }

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
    // and m x m BSDF samples with MIS; a constant environment BSDF samples only), for Direct/Cache.
    glm::vec3 directInfinite(const SurfaceHit& hit, const Sampler& sampler, int depth, int grid, RayCounts& rays) const;
    glm::vec3 environmentDirect(const SurfaceHit& hit, const glm::vec3& origin, const Sampler& sampler, int depth,
                                int grid, RayCounts& rays) const;
    // Path mode (path_integrator.cpp): the whole path from a primary hit.
    glm::vec3 tracePath(const SurfaceHit& first, const Sampler& sampler, RayCounts& rays) const;
    // Path mode's steps (path_integrator.cpp). PathState: one path between two vertices;
    // PathVertex: what scattering at a vertex asks the ray tracer for.
    struct PathState;
    struct PathVertex;
    // Shades s.hit: adds its emission, prepares next-event estimation and samples the next
    // direction (out says which rays to trace). Rays for lights at infinity are traced here.
    void scatterPathVertex(PathState& s, const Sampler& sampler, PathVertex& out, RayCounts& rays) const;
    // Adds the vertex's next-event estimate; visible: its shadow segment was clear.
    void addNextEvent(PathState& s, const PathVertex& v, bool visible) const;
    // Ends a path whose next ray left the scene: what the environment sends back along it.
    void endPath(PathState& s, const PathVertex& v) const;
    // One point or area light from the power CDF, MIS-weighted against BSDF sampling, before its
    // shadow ray: false if it adds nothing whatever the visibility; else what it adds when the
    // segment is clear.
    bool prepareNextEventFinite(const SurfaceHit& hit, const Sampler& sampler, int depth, float diffusePick,
                                glm::vec3& contribution, ShadowSegment& segment) const;
    // Every directional light and one environment-map sample (a constant environment is left to
    // BSDF sampling), their shadow rays traced here.
    glm::vec3 nextEventInfinite(const SurfaceHit& hit, const Sampler& sampler, int depth, float diffusePick,
                                RayCounts& rays) const;
    // What a BSDF-sampled ray that left the scene brings back, MIS-weighted against the
    // environment's light samples (pdfBefore: the BSDF sample's solid-angle pdf).
    glm::vec3 escapedPath(const glm::vec3& dir, bool specularBefore, float pdfBefore) const;
    // True if nothing blocks the segment from origin to target (shortened by `shorten` at the
    // target end). Traces one shadow ray.
    bool unoccluded(const glm::vec3& origin, const glm::vec3& target, float shorten, RayCounts& rays) const;
    // True if nothing blocks the ray from origin along unit `dir` to infinity. One shadow ray.
    bool unoccludedToward(const glm::vec3& origin, const glm::vec3& dir, RayCounts& rays) const;
    bool occluded(const glm::vec3& origin, const glm::vec3& dir, float tfar, RayCounts& rays) const;
    // How area light `a` is sampled from receiver point p under ShadingSettings::lightSampling.
    LightView viewOf(const AreaLightSampler& a, const glm::vec3& p) const { return a.view(p, bySolidAngle_); }
    // The hit of a ray along unit `dir` on triangle primID at barycentrics (u, v), distance tfar.
    void fillHit(std::uint32_t primID, float u, float v, float tfar, const glm::vec3& dir, RayCone cone,
                 SurfaceHit& hit) const;
    template <int W>
    void fillHit(const RayPacket<W>& packet, int lane, RayCone cone, SurfaceHit& hit) const {
        fillHit(packet.rays.hit.primID[lane], packet.rays.hit.u[lane], packet.rays.hit.v[lane],
                packet.rays.ray.tfar[lane], packet.dir[lane], cone, hit);
    }
    // The cone of a camera ray: width 0 at the eye; no spread when textures are not filtered.
    RayCone cameraCone(float spread) const {
        return {0.0f, shading_.textureFilter == TextureFilter::None ? 0.0f : spread};
    }

    const EmbreeScene& geometry_;
    const LightSet& lights_;
    ShadingSettings shading_;
    const IndirectDiffuseSource* indirect_;
    RTCScene scene_;
    int lightGrid_;
    int glossyGrid_;     // g: g x g glossy samples at a ray tree's first glossy hit (then 1)
    bool bySolidAngle_;  // ShadingSettings::lightSampling resolved for the mode
};

}  // namespace aamap
