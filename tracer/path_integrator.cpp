// Path mode: unbiased path tracing, the ground truth for shading. Next-event estimation at every
// non-delta vertex (one light sample, light picked on the power CDF, plus every directional light
// and one environment-map sample), MIS with the power heuristic between light and BSDF sampling,
// Russian roulette by throughput. Rays that leave the scene bring back the environment. Depth counts path
// segments as Mitsuba's max_depth does.
#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>

#include "tracer/bsdf.h"
#include "tracer/integrator.h"

namespace aamap {

glm::vec3 Integrator::nextEvent(const SurfaceHit& hit, const Sampler& sampler, int depth, float diffusePick,
                                RayCounts& rays) const {
    glm::vec3 L = nextEventFinite(hit, sampler, depth, diffusePick, rays);
    if (!lights_.directionals.empty() || lights_.environment) L += nextEventInfinite(hit, sampler, depth, diffusePick, rays);
    return L;
}

glm::vec3 Integrator::nextEventInfinite(const SurfaceHit& hit, const Sampler& sampler, int depth, float diffusePick,
                                        RayCounts& rays) const {
    const ShadingMaterial& m = *hit.material;
    const glm::vec3 origin = hit.position + hit.offset * hit.geometric;
    glm::vec3 L(0.0f);
    for (const DirectionalSource& d : lights_.directionals) {  // delta lights: no MIS
        const float cosSurface = glm::dot(hit.shading, d.toLight);
        if (glm::dot(hit.geometric, d.toLight) <= 0.0f || cosSurface <= 0.0f) continue;
        if (!unoccludedToward(origin, d.toLight, rays)) continue;
        const bsdf::Eval e = bsdf::evalSmooth(m, hit.albedo, hit.shading, hit.wo, d.toLight, cosSurface, diffusePick);
        L += e.f * d.irradiance * cosSurface;
    }
    if (!lights_.environment || lights_.environment->constant()) return L;
    const EnvironmentSampler::Sample s = lights_.environment->sample(sampler.get2D(dims::path(depth, dims::PathSlot::EnvLight)));
    if (!(s.pdf > 0.0f)) return L;
    const float cosSurface = glm::dot(hit.shading, s.direction);
    if (glm::dot(hit.geometric, s.direction) <= 0.0f || cosSurface <= 0.0f) return L;
    if (!unoccludedToward(origin, s.direction, rays)) return L;
    const bsdf::Eval e = bsdf::evalSmooth(m, hit.albedo, hit.shading, hit.wo, s.direction, cosSurface, diffusePick);
    return L + e.f * s.radiance * (cosSurface * powerHeuristic(s.pdf, e.pdf) / s.pdf);
}

glm::vec3 Integrator::escapedPath(const glm::vec3& dir, bool specularBefore, float pdfBefore) const {
    if (!lights_.environment) return glm::vec3(0.0f);
    const EnvironmentSampler& env = *lights_.environment;
    // Only a map is light-sampled (nextEventInfinite); a constant sky comes from here alone.
    const float w = specularBefore || env.constant() ? 1.0f : powerHeuristic(pdfBefore, env.pdf(dir));
    return env.radiance(dir) * w;
}

glm::vec3 Integrator::nextEventFinite(const SurfaceHit& hit, const Sampler& sampler, int depth, float diffusePick,
                                      RayCounts& rays) const {
    if (lights_.selectCdf.empty()) return glm::vec3(0.0f);
    const ShadingMaterial& m = *hit.material;
    glm::vec2 u = sampler.get2D(dims::path(depth, dims::PathSlot::Light));
    const std::size_t l = lights_.select(u.x);
    const float pick = lights_.selectPdf[l];
    const glm::vec3 origin = hit.position + hit.offset * hit.geometric;
    const std::size_t nPoints = lights_.points.size();
    if (l < nPoints) {  // a delta light: BSDF sampling never finds it, so no MIS
        const PointLightSource& p = lights_.points[l];
        const glm::vec3 w = p.position - hit.position;
        const float d2 = glm::dot(w, w);
        if (!(d2 > 0.0f)) return glm::vec3(0.0f);
        const glm::vec3 wi = w * (1.0f / std::sqrt(d2));
        const float cosSurface = glm::dot(hit.shading, wi);
        const float lobe = p.angular(-wi);
        if (glm::dot(hit.geometric, wi) <= 0.0f || cosSurface <= 0.0f || lobe <= 0.0f) return glm::vec3(0.0f);
        if (!unoccluded(origin, p.position, 1.0f, rays)) return glm::vec3(0.0f);
        const bsdf::Eval e = bsdf::evalSmooth(m, hit.albedo, hit.shading, hit.wo, wi, cosSurface, diffusePick);
        return e.f * p.intensity * (lobe * cosSurface / (d2 * pick));
    }
    const AreaLightSampler& a = lights_.areas[l - nPoints];
    LightView view = viewOf(a, hit.position);
    const LightPoint q = a.sample(view, hit.position, u);
    const glm::vec3 w = q.position - hit.position;
    const float d2 = glm::dot(w, w);
    if (!(d2 > 0.0f)) return glm::vec3(0.0f);
    const float d = std::sqrt(d2);
    const glm::vec3 wi = w * (1.0f / d);
    const float cosSurface = glm::dot(hit.shading, wi);
    const float cosLight = -glm::dot(q.normal, wi);
    if (glm::dot(hit.geometric, wi) <= 0.0f || cosSurface <= 0.0f || cosLight <= 0.0f) return glm::vec3(0.0f);
    const float tfar = 1.0f - rayOffset(q.position, a.vertexScale()) / d;
    if (!(tfar > 0.0f) || !unoccluded(origin, q.position, tfar, rays)) return glm::vec3(0.0f);
    const bsdf::Eval e = bsdf::evalSmooth(m, hit.albedo, hit.shading, hit.wo, wi, cosSurface, diffusePick);
    const float pdfLight = pick / a.inversePdf(view, cosLight, d2);  // solid angle
    return e.f * a.radiance() * (cosSurface * powerHeuristic(pdfLight, e.pdf) / pdfLight);
}

glm::vec3 Integrator::tracePath(const SurfaceHit& first, const Sampler& sampler, RayCounts& rays) const {
    glm::vec3 L(0.0f), beta(1.0f);
    SurfaceHit hit = first;
    bool specularBefore = true;  // the camera "sampled" the primary direction: no MIS on it
    float pdfBefore = 0.0f;      // solid-angle pdf of the BSDF sample that led here
    glm::vec3 before(0.0f);      // the vertex that BSDF sample left from (where light sampling views the light)
    const std::size_t nPoints = lights_.points.size();
    for (int depth = 0;; ++depth) {
        const ShadingMaterial& m = *hit.material;
        if (m.emissive && hit.front) {
            float w = 1.0f;
            const std::int32_t area = lights_.areaOfTriangle.empty() ? -1 : lights_.areaOfTriangle[hit.primitive];
            if (!specularBefore && area >= 0) {
                // What light sampling from the vertex before would have paid for this point:
                // P(light) times its solid-angle pdf there.
                const AreaLightSampler& a = lights_.areas[static_cast<std::size_t>(area)];
                const float cosLight = glm::dot(hit.geometric, hit.wo);
                const float pdfLight = lights_.selectPdf[nPoints + static_cast<std::size_t>(area)] /
                                       a.inversePdf(viewOf(a, before), cosLight, hit.distance * hit.distance);
                w = powerHeuristic(pdfBefore, pdfLight);
            }
            L += beta * m.ke * w;
        }
        if (depth + 1 >= shading_.maxDepth) break;  // one more segment would exceed maxDepth

        const float lobeU = sampler.get1D(dims::path(depth, dims::PathSlot::Lobe));
        glm::vec3 dir;
        if (m.kind == MaterialKind::Glass) {
            // One branch, chosen with the Fresnel probability: weight ks either way.
            const float cosI = std::min(glm::dot(hit.wo, hit.shading), 1.0f);
            if (!(cosI > 0.0f)) break;
            const float eta = hit.front ? m.ior : 1.0f / m.ior;
            float cosT = 0.0f;
            const float F = bsdf::fresnelDielectric(cosI, eta, cosT);
            if (lobeU < F) {
                dir = bsdf::reflect(hit.wo, hit.shading);
                if (glm::dot(dir, hit.geometric) <= 0.0f) break;
            } else {
                dir = bsdf::refract(hit.wo, hit.shading, eta, cosI, cosT);
                if (glm::dot(dir, hit.geometric) >= 0.0f) break;
            }
            beta *= m.ks;
            specularBefore = true;
        } else {
            // Mirror: the delta lobe with probability by reflectance, else its Lambert part.
            float specularPick = 0.0f;
            if (m.kind == MaterialKind::Mirror) {
                const float s = bsdf::luminance(m.ks), dl = m.diffuse ? bsdf::luminance(m.kd) : 0.0f;
                specularPick = s + dl > 0.0f ? s / (s + dl) : 1.0f;
            }
            if (lobeU < specularPick) {
                dir = bsdf::reflect(hit.wo, hit.shading);
                if (glm::dot(dir, hit.geometric) <= 0.0f) break;
                beta *= m.ks * (1.0f / specularPick);
                specularBefore = true;
            } else {
                const float diffusePick = m.kind == MaterialKind::Mirror ? 1.0f - specularPick
                                          : m.glossy                      ? m.diffuseWeight
                                                                          : 1.0f;
                if (!m.diffuse && !m.glossy) break;  // black
                L += beta * nextEvent(hit, sampler, depth, diffusePick, rays);
                const glm::vec2 u = sampler.get2D(dims::path(depth, dims::PathSlot::Bsdf));
                if (!bsdf::sampleSmooth(m, hit.shading, hit.wo, lobeU, u, dir)) break;
                const float cosI = glm::dot(hit.shading, dir);
                if (cosI <= 0.0f || glm::dot(hit.geometric, dir) <= 0.0f) break;
                const bsdf::Eval e = bsdf::evalSmooth(m, hit.albedo, hit.shading, hit.wo, dir, cosI, diffusePick);
                if (!(e.pdf > 0.0f)) break;
                beta *= e.f * (cosI / e.pdf);
                pdfBefore = e.pdf;
                specularBefore = false;
            }
        }
        if (shading_.russianRoulette && depth + 1 >= shading_.rouletteDepth) {
            const float survive = std::min(bsdf::maxComponent(beta), 0.95f);
            if (!(sampler.get1D(dims::path(depth, dims::PathSlot::Roulette)) < survive)) break;
            beta *= 1.0f / survive;
        }
        const glm::vec3 origin = hit.originFor(dir);
        before = hit.position;
        // The cone goes on with its angle after any bounce (pbrt-v4's camera-based approximation
        // likewise ignores a diffuse bounce's widening): texture noise there is indirect light.
        if (!intersect(origin, dir, hit, rays.other, hit.cone)) {
            L += beta * escapedPath(dir, specularBefore, pdfBefore);
            break;
        }
    }
    return L;
}

}  // namespace aamap
