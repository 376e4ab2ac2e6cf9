#include "tracer/integrator.h"

#include <limits>

#include <glm/geometric.hpp>
#include <spdlog/spdlog.h>

namespace aamap {

Integrator::Integrator(const EmbreeScene& geometry, const LightSet& lights, const ShadingSettings& shading,
                       const char* name, LightSampling autoSampling)
    : geometry_(geometry),
      lights_(lights),
      shading_(shading),
      scene_(geometry.handle()),
      bySolidAngle_(shading.lightSampling == LightSampling::SolidAngle ||
                    (shading.lightSampling == LightSampling::Auto && autoSampling == LightSampling::SolidAngle)) {
    shading_.maxDepth = std::max(shading_.maxDepth, 1);
    shading_.maxSpecularDepth = std::max(shading_.maxSpecularDepth, 0);
    const bool perHit = shading_.lightSelection == LightSelection::Contribution && lights_.perHitSelectable();
    const char* selection = !lights_.many() ? "few: every light per hit"
                            : perHit        ? "many: per-hit contribution CDF"
                                            : "many: power-CDF selection";
    spdlog::debug("integrator: {}, {} lights ({}), max depth {}, max specular depth {}", name, lights_.count(),
                  selection, shading_.maxDepth, shading_.maxSpecularDepth);
}

namespace {

// A normal or bump map at a hit (docs/tracer.md, "Normal and bump maps"): the tilted normal of
// Mitsuba's shading frame, which the map does not turn to the viewer. Seen from the back, a
// twosided outside the map mirrors the tilt through the tangent plane, otherwise the tilted normal
// turns over. Where the viewer is below the tilted normal, the hit reflects nothing: Mitsuba's
// BSDFs need the viewer above it, and a twosided inside the map, which turns it to the viewer,
// then passes only light from below the surface, which the side tests keep out.
void applyMap(const EmbreeScene& geometry, std::uint32_t primID, float u, float v, SurfaceHit& hit) {
    const ShadingMaterial& m = *hit.material;
    const glm::vec3 n = geometry.shadingNormal(primID, u, v);
    const glm::vec3 tilted = geometry.perturbedNormal(m, primID, u, v, n);
    const bool back = glm::dot(n, hit.geometric) < 0.0f;
    hit.shading = !back ? tilted : m.mapMirroredOnBack ? tilted - 2.0f * glm::dot(tilted, n) * n : -tilted;
    if (m.kind == MaterialKind::Glass || glm::dot(hit.wo, hit.shading) > 0.0f || m.unlit == nullptr) return;
    hit.material = m.unlit;
    hit.albedo = glm::vec3(0.0f);
}

}  // namespace

void Integrator::fillHit(std::uint32_t primID, float u, float v, float tfar, const glm::vec3& dir, RayCone cone,
                         SurfaceHit& hit) const {
    const Triangle& tri = geometry_.triangle(primID);
    const ShadingMaterial& mat = geometry_.atHit(geometry_.material(tri.material), primID, u, v);
    hit.front = glm::dot(tri.normal, dir) < 0.0f;
    // Rebuild the hit point from the triangle (error relative to its vertices, not to t * |dir|).
    hit.position = tri.v0 + u * tri.e1 + v * tri.e2;
    hit.geometric = hit.front ? tri.normal : -tri.normal;
    hit.shading = geometry_.shadingNormal(primID, u, v);
    if (glm::dot(hit.shading, hit.geometric) < 0.0f) hit.shading = -hit.shading;  // normals may disagree with the winding
    hit.wo = -dir;
    hit.cone = {cone.at(tfar), cone.spread};
    hit.albedo = mat.diffuse ? geometry_.albedo(mat, primID, u, v, dir, hit.cone.width) : glm::vec3(0.0f);
    hit.offset = rayOffset(hit.position, tri.vertexScale);
    hit.distance = tfar;
    hit.primitive = primID;
    hit.material = &mat;
    if (mat.perturbed()) applyMap(geometry_, primID, u, v, hit);
}

bool Integrator::intersect(const glm::vec3& origin, const glm::vec3& dir, SurfaceHit& hit, std::uint64_t& counter,
                           RayCone cone) const {
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    RTCRayHit rh = makeRayHit(origin, dir);
    rtcIntersect1(scene_, &context, &rh);
    ++counter;
    if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return false;
    fillHit(rh.hit.primID, rh.hit.u, rh.hit.v, rh.ray.tfar, dir, cone, hit);
    return true;
}

glm::vec3 Integrator::primary(const glm::vec3& origin, const glm::vec3& dir, const Sampler& sampler, RayCounts& rays,
                              float spread) const {
    SurfaceHit hit;
    if (!intersect(origin, dir, hit, rays.primary, cameraCone(spread))) return escapedCamera(dir);
    return shadeCamera(hit, sampler, rays);
}

glm::vec3 Integrator::primaryFromHit(const RTCRayHit& rh, const glm::vec3& dir, const Sampler& sampler,
                                     RayCounts& rays, float spread) const {
    ++rays.primary;
    if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return escapedCamera(dir);
    SurfaceHit hit;
    fillHit(rh.hit.primID, rh.hit.u, rh.hit.v, rh.ray.tfar, dir, cameraCone(spread), hit);
    return shadeCamera(hit, sampler, rays);
}

template <int W>
void Integrator::primaryLanes(const RayPacket<W>& primaries, int count, const Sampler* samplers, const float* spreads,
                              glm::vec3* out, RayCounts& rays) const {
    for (int lane = 0; lane < count; ++lane)
        out[lane] = primaryFromHit(primaries.hit(lane), primaries.dir[lane], samplers[lane], rays, spreads[lane]);
}

void Integrator::primaryPacket(const RayPacket<4>& primaries, int count, const Sampler* samplers,
                               const float* spreads, glm::vec3* out, RayCounts& rays) const {
    primaryLanes(primaries, count, samplers, spreads, out, rays);
}

void Integrator::primaryPacket(const RayPacket<kMaxPacket>& primaries, int count, const Sampler* samplers,
                               const float* spreads, glm::vec3* out, RayCounts& rays) const {
    primaryLanes(primaries, count, samplers, spreads, out, rays);
}

bool Integrator::unoccluded(const glm::vec3& origin, const glm::vec3& target, float tfar, RayCounts& rays) const {
    // Unnormalised: t = 1 is the target, so no square root is needed.
    return !occluded(origin, target - origin, tfar, rays);
}

bool Integrator::unoccludedToward(const glm::vec3& origin, const glm::vec3& dir, RayCounts& rays) const {
    return !occluded(origin, dir, std::numeric_limits<float>::infinity(), rays);
}

bool Integrator::occluded(const glm::vec3& origin, const glm::vec3& dir, float tfar, RayCounts& rays) const {
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    RTCRay ray;
    ray.org_x = origin.x;
    ray.org_y = origin.y;
    ray.org_z = origin.z;
    ray.dir_x = dir.x;
    ray.dir_y = dir.y;
    ray.dir_z = dir.z;
    ray.tnear = 0.0f;
    ray.tfar = tfar;
    ray.time = 0.0f;
    ray.mask = ~0u;
    ray.id = 0;
    ray.flags = 0;
    rtcOccluded1(scene_, &context, &ray);
    ++rays.shadow;
    return !(ray.tfar >= 0.0f);  // Embree sets tfar to -inf on a hit
}

}  // namespace aamap
