#pragma once
// A minimal RadianceFn for the irradiance cache straight on Embree (independent of the
// integrator): Lambertian hits, area lights only, m x m stratified shadow rays, light sources
// black to hemisphere rays (their direct light is sampled already), deeper bounces through the
// cache. For the cache's tests and pre-pass measurements only.
#include <cmath>
#include <limits>

#include <embree3/rtcore.h>
#include <glm/geometric.hpp>

#include "tracer/embree_scene.h"
#include "tracer/irradiance_cache.h"
#include "tracer/lights.h"
#include "tracer/ray_offset.h"
#include "tracer/sampler.h"

namespace aamap::testing {

class CacheHarness {
public:
    CacheHarness(const EmbreeScene& geometry, const LightSet& lights, int lightGrid)
        : geometry_(geometry), lights_(lights), m_(lightGrid) {}

    void attach(const IrradianceCache& cache) { cache_ = &cache; }

    RadianceFn fn() const {
        return [this](const glm::vec3& o, const glm::vec3& d, int depth, std::uint64_t seed) {
            return radiance(o, d, depth, seed);
        };
    }

    RadianceSample radiance(const glm::vec3& o, const glm::vec3& d, int depth, std::uint64_t seed) const {
        RTCIntersectContext context;
        rtcInitIntersectContext(&context);
        RTCRayHit rh;
        rh.ray = makeRay(o, d, std::numeric_limits<float>::infinity());
        rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
        rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
        rtcIntersect1(geometry_.handle(), &context, &rh);
        RadianceSample s;
        if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return s;
        s.distance = rh.ray.tfar;
        const Triangle& tri = geometry_.triangle(rh.hit.primID);
        const ShadingMaterial& mat = geometry_.material(tri.material);
        const bool front = glm::dot(tri.normal, d) < 0.0f;
        if (mat.emissive && front) return s;
        const glm::vec3 p = tri.v0 + rh.hit.u * tri.e1 + rh.hit.v * tri.e2;
        const glm::vec3 n = front ? tri.normal : -tri.normal;
        const glm::vec3 origin = p + rayOffset(p, tri.vertexScale) * n;
        const Sampler sampler(seed, 0, 0);
        glm::vec3 e(0.0f);
        const float invM = 1.0f / static_cast<float>(m_);
        for (std::size_t li = 0; li < lights_.areas.size(); ++li) {
            const AreaLightSampler& light = lights_.areas[li];
            float sum = 0.0f;
            for (int j = 0; j < m_ * m_; ++j) {
                const LightPoint q = light.sample(
                    sampler.jittered2D(dims::areaLight(depth, static_cast<int>(li), j), j % m_, j / m_, invM));
                const glm::vec3 w = q.position - origin;
                const float d2 = glm::dot(w, w);
                const glm::vec3 l = w / std::sqrt(d2);
                const float cosS = glm::dot(n, l), cosL = -glm::dot(q.normal, l);
                if (cosS <= 0.0f || cosL <= 0.0f) continue;
                RTCRay ray = makeRay(origin, w, 1.0f - 1e-4f);
                rtcOccluded1(geometry_.handle(), &context, &ray);
                if (ray.tfar >= 0.0f) sum += cosS * cosL / d2;
            }
            e += light.radiance() * (sum * light.area() * invM * invM);
        }
        if (cache_ != nullptr) e += cache_->irradiance(p, n, depth);
        s.radiance = mat.kdOverPi * e;
        return s;
    }

private:
    static RTCRay makeRay(const glm::vec3& o, const glm::vec3& d, float tfar) {
        RTCRay r;
        r.org_x = o.x;
        r.org_y = o.y;
        r.org_z = o.z;
        r.dir_x = d.x;
        r.dir_y = d.y;
        r.dir_z = d.z;
        r.tnear = 0.0f;
        r.tfar = tfar;
        r.time = 0.0f;
        r.mask = ~0u;
        r.id = 0;
        r.flags = 0;
        return r;
    }

    const EmbreeScene& geometry_;
    const LightSet& lights_;
    int m_;
    const IrradianceCache* cache_ = nullptr;
};

}  // namespace aamap::testing
