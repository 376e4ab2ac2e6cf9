#include "tracer/integrator.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <glm/geometric.hpp>

#include "tracer/shadow_packet.h"

namespace aamap {

Integrator::Integrator(const EmbreeScene& geometry, const LightSet& lights, const ShadingSettings& shading)
    : geometry_(geometry),
      lights_(lights),
      scene_(geometry.handle()),
      // m = round(sqrt(N)) in [1, 1024]: m x m samples, within the sampler's dimension layout.
      lightGrid_(std::clamp(static_cast<int>(std::lround(std::sqrt(std::max(1, shading.areaLightSamples)))), 1, 1024)) {}

glm::vec3 Integrator::primary(const glm::vec3& origin, const glm::vec3& dir, const Sampler& sampler,
                              RayCounts& rays) const {
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    RTCRayHit rh;
    rh.ray.org_x = origin.x;
    rh.ray.org_y = origin.y;
    rh.ray.org_z = origin.z;
    rh.ray.dir_x = dir.x;
    rh.ray.dir_y = dir.y;
    rh.ray.dir_z = dir.z;
    rh.ray.tnear = 0.0f;
    rh.ray.tfar = std::numeric_limits<float>::infinity();
    rh.ray.time = 0.0f;
    rh.ray.mask = ~0u;
    rh.ray.id = 0;
    rh.ray.flags = 0;
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
    rtcIntersect1(scene_, &context, &rh);
    ++rays.primary;
    if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return glm::vec3(0.0f);  // misses are black

    const Triangle& tri = geometry_.triangle(rh.hit.primID);
    const ShadingMaterial& mat = geometry_.material(tri.material);
    const bool frontFacing = glm::dot(tri.normal, dir) < 0.0f;
    // One-sided emitters: the front shows Ke; the back is an ordinary surface of that material.
    if (mat.emissive && frontFacing) return mat.ke;

    // Rebuild the hit point from the triangle (error relative to its vertices, not to t * |dir|).
    const float u = rh.hit.u, v = rh.hit.v;
    const glm::vec3 p = tri.v0 + u * tri.e1 + v * tri.e2;
    const glm::vec3 ng = frontFacing ? tri.normal : -tri.normal;
    glm::vec3 ns = geometry_.shadingNormal(rh.hit.primID, u, v);
    if (glm::dot(ns, ng) < 0.0f) ns = -ns;  // vertex normals may disagree with the winding
    const SurfacePoint sp{p, p + rayOffset(p) * ng, ng, ns, &mat};
    return shadeSurface(sp, sampler, 0, rays);
}

glm::vec3 Integrator::shadeSurface(const SurfacePoint& sp, const Sampler& sampler, int depth, RayCounts& rays) const {
    switch (sp.material->kind) {
        case MaterialKind::Diffuse: return directDiffuse(sp, sampler, depth, rays);
        // Specular transport is not modelled yet: mirrors and glass are shaded as their diffuse
        // part, which keeps their Kd visible and the ray budget honest.
        case MaterialKind::Mirror: return directDiffuse(sp, sampler, depth, rays);
        case MaterialKind::Glass: return directDiffuse(sp, sampler, depth, rays);
    }
    return glm::vec3(0.0f);
}

glm::vec3 Integrator::directDiffuse(const SurfacePoint& sp, const Sampler& sampler, int depth, RayCounts& rays) const {
    glm::vec3 irradiance(0.0f);  // sum of E_i = L_i cos / d^2 (point: I cos / d^2)

    for (const PointLightSource& light : lights_.points) {
        // Geometry from the true hit point; the shadow ray leaves from the offset origin.
        const glm::vec3 w = light.position - sp.position;
        const float d2 = glm::dot(w, w);
        if (!(d2 > 0.0f)) continue;
        const glm::vec3 l = w * (1.0f / std::sqrt(d2));
        // The geometric test decides the side (a shadow ray into the surface would self-hit);
        // the shading normal weights.
        if (glm::dot(sp.geometric, l) <= 0.0f) continue;
        const float cosSurface = glm::dot(sp.shading, l);
        if (cosSurface <= 0.0f) continue;
        const float lobe = light.lobe ? glm::dot(light.normal, -l) : 1.0f;
        if (lobe <= 0.0f) continue;
        if (!unoccluded(sp.origin, light.position, rays)) continue;
        irradiance += light.intensity * (lobe * cosSurface / d2);
    }

    const int m = lightGrid_;
    const float invM = 1.0f / static_cast<float>(m);
    const float invCount = invM * invM;
    const int count = m * m;
    ShadowBatch8 batch;
    for (std::size_t li = 0; li < lights_.areas.size(); ++li) {
        const AreaLightSampler& light = lights_.areas[li];
        float sum = 0.0f;  // sum of cos cos' / d^2 over the visible samples, in sample order
        for (int first = 0; first < count; first += ShadowBatch8::kWidth) {
            const int lanes = std::min(ShadowBatch8::kWidth, count - first);
            for (int i = 0; i < lanes; ++i) {
                const int j = first + i;
                const std::uint64_t dim = dims::areaLight(depth, static_cast<int>(li), j);
                const LightPoint q = light.sample(sampler.jittered2D(dim, j % m, j / m, invM));
                batch.setSample(i, q.position, q.normal);
            }
            batch.padFrom(lanes);
            batch.prepare(lanes, sp.position, sp.origin, sp.geometric, sp.shading);
            sum += batch.trace(scene_, lanes, rays);
        }
        irradiance += light.radiance() * (sum * light.area() * invCount);
    }
    return sp.material->kdOverPi * irradiance;
}

bool Integrator::unoccluded(const glm::vec3& origin, const glm::vec3& target, RayCounts& rays) const {
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    RTCRay ray;
    ray.org_x = origin.x;
    ray.org_y = origin.y;
    ray.org_z = origin.z;
    // Unnormalised: t = 1 is the target, so no square root is needed.
    ray.dir_x = target.x - origin.x;
    ray.dir_y = target.y - origin.y;
    ray.dir_z = target.z - origin.z;
    ray.tnear = 0.0f;
    ray.tfar = 1.0f;
    ray.time = 0.0f;
    ray.mask = ~0u;
    ray.id = 0;
    ray.flags = 0;
    rtcOccluded1(scene_, &context, &ray);
    ++rays.shadow;
    return ray.tfar >= 0.0f;  // Embree sets tfar to -inf on a hit
}

}  // namespace aamap
