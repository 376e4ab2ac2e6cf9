#pragma once
// Radiance along a ray: the shading budget (docs/tracer.md), separate from the primary-ray
// (antialiasing) budget. The tracer renders through the abstract Integrator; makeIntegrator picks
// the class for ShadingSettings::mode, once per render:
// - DirectIntegrator (direct_integrator.h): emission, direct light from every light type, BSDF
//   samples of glossy lobes and mirror/glass recursion;
// - CacheIntegrator (cache_integrator.h): Direct plus indirect diffuse from an
//   IndirectDiffuseSource (the irradiance cache);
// - PathIntegrator (path_integrator.h): unbiased path tracing with next-event estimation, MIS and
//   Russian roulette.
// Integrator itself holds what they share: the scene, the hit record (fillHit), shadow rays, the
// environment and how area lights are viewed.
#include <algorithm>
#include <cstdint>
#include <memory>

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

class IndirectDiffuseSource;

// What the tracer renders with (one per render, from makeIntegrator), and the steps every
// integrator shares. Const and stateless per call: threads share one.
class Integrator {
public:
    virtual ~Integrator() = default;
    Integrator(const Integrator&) = delete;
    Integrator& operator=(const Integrator&) = delete;

    // Radiance arriving at `origin` from unit direction -dir. Counts every ray it traces in `rays`
    // (the primary ray in rays.primary). Allocates nothing. spread: the angle (radians) the ray's
    // share of its pixel subtends, for texture filtering (0: unfiltered).
    glm::vec3 primary(const glm::vec3& origin, const glm::vec3& dir, const Sampler& sampler, RayCounts& rays,
                      float spread = 0.0f) const;
    // The same, for a primary ray the caller has already traced from `origin` along unit `dir`
    // (rh: its Embree result, e.g. one lane of a packet of coherent primary rays).
    glm::vec3 primaryFromHit(const RTCRayHit& rh, const glm::vec3& dir, const Sampler& sampler, RayCounts& rays,
                             float spread = 0.0f) const;

    // The packet the tracer traces the next `samples` (>= 1) coherent primary rays of a pixel in:
    // 1 (one ray, primary()), 4 or kMaxPacket (primaryPacket). By default 4 wide for 2-4 of them.
    static constexpr int kMaxPacket = 8;
    virtual int packetWidth(int samples) const { return samples == 1 ? 1 : samples <= 4 ? 4 : kMaxPacket; }
    // primaryFromHit for the lanes [0, count) of a packet of primary rays already traced, each with
    // its own sampler and spread, into out[0, count): each lane's radiance is the one
    // primaryFromHit gives it (by default the lanes are shaded one by one, in lane order).
    virtual void primaryPacket(const RayPacket<4>& primaries, int count, const Sampler* samplers,
                               const float* spreads, glm::vec3* out, RayCounts& rays) const;
    virtual void primaryPacket(const RayPacket<kMaxPacket>& primaries, int count, const Sampler* samplers,
                               const float* spreads, glm::vec3* out, RayCounts& rays) const;

    // The first hit along unit `dir` from `origin`: false on a miss; counts the ray in `counter`.
    // cone: the footprint the ray brings from `origin` (hit.cone gets its width at the hit).
    bool intersect(const glm::vec3& origin, const glm::vec3& dir, SurfaceHit& hit, std::uint64_t& counter,
                   RayCone cone = {}) const;

    // Radiance of the environment along a ray that leaves the scene in unit direction `dir`
    // (black without one). Every integrator returns it for escaping rays that are not hemisphere
    // rays of the irradiance cache (the environment is sampled as direct light there).
    glm::vec3 escaped(const glm::vec3& dir) const {
        return lights_.environment ? lights_.environment->radiance(dir) : glm::vec3(0.0f);
    }
    // A camera ray's escape: black when emitters are hidden from the camera.
    glm::vec3 escapedCamera(const glm::vec3& dir) const {
        return shading_.hideEmitters ? glm::vec3(0.0f) : escaped(dir);
    }

    const ShadingSettings& settings() const { return shading_; }

protected:
    // name: for the log. autoSampling: what ShadingSettings::lightSampling's Auto means for this
    // integrator (docs/tracer.md, "Lights").
    Integrator(const EmbreeScene& geometry, const LightSet& lights, const ShadingSettings& shading, const char* name,
               LightSampling autoSampling);

    // The radiance a camera ray brings back from its first hit (hit.cone: the camera's cone).
    virtual glm::vec3 shadeCamera(const SurfaceHit& hit, const Sampler& sampler, RayCounts& rays) const = 0;

    // True if nothing blocks the segment from origin to target (shortened by `shorten` at the
    // target end). Traces one shadow ray.
    bool unoccluded(const glm::vec3& origin, const glm::vec3& target, float shorten, RayCounts& rays) const;
    // True if nothing blocks the ray from origin along unit `dir` to infinity. One shadow ray.
    bool unoccludedToward(const glm::vec3& origin, const glm::vec3& dir, RayCounts& rays) const;
    bool occluded(const glm::vec3& origin, const glm::vec3& dir, float tfar, RayCounts& rays) const;
    // How area light `a` is sampled from receiver point p under ShadingSettings::lightSampling.
    LightView viewOf(const AreaLightSampler& a, const glm::vec3& p) const { return a.view(p, bySolidAngle_); }
    bool bySolidAngle() const { return bySolidAngle_; }
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
    RTCScene scene_;

private:
    template <int W>
    void primaryLanes(const RayPacket<W>& primaries, int count, const Sampler* samplers, const float* spreads,
                      glm::vec3* out, RayCounts& rays) const;

    bool bySolidAngle_;  // ShadingSettings::lightSampling resolved for this integrator
};

// The integrator for shading.mode: the one place that maps a mode to its class. Cache mode reads
// `indirect` (not owned, may be null: then it shades as Direct, which is what Cache mode without
// a cache is).
std::unique_ptr<Integrator> makeIntegrator(const EmbreeScene& geometry, const LightSet& lights,
                                           const ShadingSettings& shading,
                                           const IndirectDiffuseSource* indirect = nullptr);
// Whether shading's integrator reads an IndirectDiffuseSource: Cache mode with bounces > 0, for
// which makeRenderShading builds the irradiance cache.
bool readsIndirectDiffuse(const ShadingSettings& shading);

}  // namespace aamap
