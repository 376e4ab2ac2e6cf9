#include "tracer/direct_integrator.h"

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>
#include <spdlog/spdlog.h>

#include "tracer/bsdf.h"
#include "tracer/shadow_packet.h"

namespace aamap {
namespace {

// Direct/Cache mode: specular branches whose weight (product of reflectances) falls below this
// are dropped, as Radiance's -lw does; it bounds the glass split tree (docs/tracer.md).
constexpr float kSpecularCutoff = 1e-3f;
// Per-hit light selection: the ManyLights sample index of its y shift, beyond any sample index
// (m <= 1024: at most 2^20 samples).
constexpr int kShiftSample = (1 << 24) - 1;
// The most glossy samples per axis at a ray tree's first glossy hit: g = min(m, 4), g x g rays.
// Each one shades what it hits with the full light budget, so the count is kept small.
constexpr int kMaxGlossyGrid = 4;
// Glossy samples are taken at hits reached by fewer specular or glossy bounces than this: the
// first glossy reflection and a glossy reflection seen in it; deeper ones take light samples alone
// (each glossy level multiplies the rays by its samples' count of point-light shadow rays).
constexpr int kMaxGlossyDepth = 2;

// The light sample's share of the glossy lobe: the power heuristic over the two strategies'
// densities times their sample counts (nLight pdfLight against nGlossy pdfGlossy); 1 when no
// glossy samples are taken.
float lightShare(float nLightPdf, int glossySamples, float glossyPdf) {
    if (glossySamples == 0) return 1.0f;
    return powerHeuristic(nLightPdf, static_cast<float>(glossySamples) * glossyPdf);
}


}  // namespace

DirectIntegrator::DirectIntegrator(const EmbreeScene& geometry, const LightSet& lights, const ShadingSettings& shading)
    : DirectIntegrator(geometry, lights, shading, "direct") {}

// Many samples per hit make the light the noise: Auto samples area lights by solid angle.
DirectIntegrator::DirectIntegrator(const EmbreeScene& geometry, const LightSet& lights, const ShadingSettings& shading,
                                   const char* name)
    : Integrator(geometry, lights, shading, name, LightSampling::SolidAngle),
      // m = round(sqrt(N)) in [1, 1024]: m x m samples, within the sampler's dimension layout.
      lightGrid_(std::clamp(static_cast<int>(std::lround(std::sqrt(std::max(1, shading.areaLightSamples)))), 1, 1024)),
      glossyGrid_(std::min(lightGrid_, kMaxGlossyGrid)) {
    spdlog::debug("integrator: {}x{} area light samples per hit", lightGrid_, lightGrid_);
}

glm::vec3 DirectIntegrator::shadeCamera(const SurfaceHit& hit, const Sampler& sampler, RayCounts& rays) const {
    return shadeDirect(hit, sampler, 0, 0, 1.0f, rays);
}

glm::vec3 DirectIntegrator::radianceDirect(const glm::vec3& origin, const glm::vec3& dir, const Sampler& sampler,
                                           int depth, RayCounts& rays) const {
    SurfaceHit hit;
    if (!intersect(origin, dir, hit, rays.other)) return escaped(dir);
    // weight 0 marks "not under a primary ray": no cache lookup (the cache's own rays land here).
    return shadeDirect(hit, sampler, depth, 0, 0.0f, rays);
}

glm::vec3 DirectIntegrator::traceSpecular(const glm::vec3& origin, const glm::vec3& dir, RayCone cone,
                                          const Sampler& sampler, int depth, int specular, float weight, int grid,
                                          RayCounts& rays) const {
    SurfaceHit hit;
    if (!intersect(origin, dir, hit, rays.other, cone)) return escaped(dir);
    return shadeDirect(hit, sampler, depth, specular, weight, rays, 1.0f, grid);
}

int DirectIntegrator::glossySampleCount(const ShadingMaterial& m, int specular, float weight) const {
    // Only under a primary ray (weight > 0; the irradiance cache's rays see light-sampled lobes),
    // within the specular budget, which glossy and delta bounces share, and kMaxGlossyDepth.
    if (!m.glossy || !(weight > 0.0f) || specular >= std::min(shading_.maxSpecularDepth, kMaxGlossyDepth)) return 0;
    // A wide lobe reflects a blur of the surroundings, the kind of light direct mode leaves out
    // (as it does diffuse interreflection), at g x g times the hit's cost: light samples only.
    if (bsdf::lobeAlpha(m) > shading_.glossyReflectionAlpha) return 0;
    return specular == 0 ? glossyGrid_ * glossyGrid_ : 1;
}

glm::vec3 DirectIntegrator::shadeDirect(const SurfaceHit& hit, const Sampler& sampler, int depth, int specular,
                                        float weight, RayCounts& rays, float emission, int grid) const {
    const ShadingMaterial& m = *hit.material;
    if (grid == 0) grid = lightGrid_;
    glm::vec3 L(0.0f);
    // One-sided emitters: the front emits Ke; both sides also reflect like their material. The
    // camera's own hit (depth, specular 0 under a primary ray) hides it when emitters are hidden.
    const bool cameraHit = depth == 0 && specular == 0 && weight > 0.0f;
    if (m.emissive && hit.front && !(cameraHit && shading_.hideEmitters)) L += m.ke * emission;
    if (m.oneSided && !hit.front) return L;  // a one-sided BSDF's back reflects nothing
    const int glossy = glossySampleCount(m, specular, weight);
    if (m.diffuse || m.glossy) L += directLight(hit, sampler, depth, {grid, glossy}, rays);
    if (m.diffuse && weight > 0.0f) addIndirectDiffuse(hit, sampler, depth, rays, L);
    if (glossy > 0) L += glossyReflection(hit, sampler, depth, specular, weight, glossy, grid, rays);
    if (specular >= shading_.maxSpecularDepth || m.kind == MaterialKind::Diffuse) return L;
    // Branch weights only cut off specular trees; under radianceDirect (weight 0) use the
    // reflectance alone so the same cutoff applies.
    const float w = weight > 0.0f ? weight : 1.0f;
    const auto follow = [&](const glm::vec3& dir, const glm::vec3& tint, float branch) {
        const float next = w * branch * bsdf::maxComponent(tint);
        if (next < kSpecularCutoff) return glm::vec3(0.0f);
        // Planar mirrors and glass keep the cone's angle (curvature is not modelled).
        const glm::vec3 Li = traceSpecular(hit.originFor(dir), dir, hit.cone, sampler, depth + 1, specular + 1,
                                           weight > 0.0f ? next : 0.0f, grid, rays);
        return tint * branch * Li;
    };
    // Mirror: one branch (its reflectance may depend on the angle); glass: the Fresnel-reflected
    // and refracted branches, deterministically.
    const glm::vec3 tint = m.kind == MaterialKind::Mirror
                               ? bsdf::deltaReflectance(m, std::clamp(glm::dot(hit.wo, hit.shading), 0.0f, 1.0f))
                               : m.ks;
    L += sumSpecularBranches(hit, [&](const glm::vec3& dir, float branch) { return follow(dir, tint, branch); });
    return L;
}

glm::vec3 DirectIntegrator::glossyReflection(const SurfaceHit& hit, const Sampler& sampler, int depth, int specular,
                                             float weight, int count, int grid, RayCounts& rays) const {
    const ShadingMaterial& m = *hit.material;
    const int g = count == 1 ? 1 : glossyGrid_;  // count is g x g or 1
    const int below = std::max(1, grid / g);
    const float invG = 1.0f / static_cast<float>(g);
    glm::vec3 sum(0.0f);
    for (int j = 0; j < count; ++j) {
        const glm::vec2 u = sampler.jittered2D(dims::path(depth, dims::PathSlot::Glossy, j), j % g, j / g, invG);
        glm::vec3 dir;
        if (!bsdf::sampleGlossy(m, hit.shading, hit.wo, u, dir)) continue;
        const float cosI = glm::dot(hit.shading, dir);
        if (cosI <= 0.0f || glm::dot(hit.geometric, dir) <= 0.0f) continue;
        const bsdf::Lobes lobes = bsdf::evalLobes(m, hit.albedo, hit.shading, hit.wo, dir);
        if (!(lobes.glossyPdf > 0.0f)) continue;
        const glm::vec3 tint = lobes.glossy * (cosI / lobes.glossyPdf);
        // As the specular branches: a faint branch is not followed (Radiance's -lw).
        const float next = weight * bsdf::maxComponent(tint);
        if (!(next >= kSpecularCutoff)) continue;
        SurfaceHit at;
        if (!intersect(hit.originFor(dir), dir, at, rays.other, hit.cone)) continue;
        // The hit's emission, weighed against the light samples that could have found it.
        float emission = 1.0f;
        const ShadingMaterial& am = *at.material;
        if (am.emissive && at.front && !lights_.areaOfTriangle.empty()) {
            const std::int32_t area = lights_.areaOfTriangle[at.primitive];
            if (area >= 0)
                emission = powerHeuristic(static_cast<float>(count) * lobes.glossyPdf,
                                          lightSamplesPdf(hit, at, static_cast<std::size_t>(area), grid));
        }
        // Each sample draws from its own stream below, so the g x g subtrees are independent.
        const Sampler branch = count == 1 ? sampler : sampler.branch(static_cast<std::uint64_t>(j));
        sum += tint * shadeDirect(at, branch, depth + 1, specular + 1, next, rays, emission, below);
    }
    return sum * (1.0f / static_cast<float>(count));
}

float DirectIntegrator::lightSamplesPdf(const SurfaceHit& from, const SurfaceHit& at, std::size_t area,
                                        int grid) const {
    const AreaLightSampler& a = lights_.areas[area];
    const float cosLight = glm::dot(at.geometric, at.wo);
    if (!(cosLight > 0.0f)) return 0.0f;
    const float inv = a.inversePdf(viewOf(a, from.position), cosLight, at.distance * at.distance);
    if (!(inv > 0.0f)) return 0.0f;
    const float n = static_cast<float>(grid * grid);
    if (!lights_.many()) return n / inv;  // m x m samples of every light
    // m x m samples in all, light l taken with its selection probability.
    const std::size_t l = lights_.points.size() + area;
    float pick = lights_.selectPdf[l];
    if (shading_.lightSelection == LightSelection::Contribution && lights_.perHitSelectable()) {
        float total = 0.0f;
        for (std::size_t i = 0; i < lights_.count(); ++i) total += lights_.contribution(i, from.position, from.shading);
        pick = total > 0.0f ? lights_.contribution(l, from.position, from.shading) / total : 0.0f;
    }
    return n * pick / inv;
}

glm::vec3 DirectIntegrator::directLight(const SurfaceHit& hit, const Sampler& sampler, int depth,
                                        RayCounts& rays) const {
    return directLight(hit, sampler, depth, {lightGrid_, 0}, rays);
}

glm::vec3 DirectIntegrator::directLight(const SurfaceHit& hit, const Sampler& sampler, int depth, LightBudget budget,
                                        RayCounts& rays) const {
    glm::vec3 L = lights_.count() == 0 ? glm::vec3(0.0f)
                  : lights_.many()     ? directManyLights(hit, sampler, depth, budget, rays)
                                       : directFewLights(hit, sampler, depth, budget, rays);
    if (!lights_.directionals.empty() || lights_.environment) L += directInfinite(hit, sampler, depth, budget.grid, rays);
    return L;
}

glm::vec3 DirectIntegrator::directInfinite(const SurfaceHit& hit, const Sampler& sampler, int depth, int grid,
                                           RayCounts& rays) const {
    const glm::vec3 origin = hit.position + hit.offset * hit.geometric;
    glm::vec3 L(0.0f);
    for (const DirectionalSource& d : lights_.directionals) {
        // As for point lights: the geometric normal decides the side, the shading normal weights.
        if (glm::dot(hit.geometric, d.toLight) <= 0.0f) continue;
        const float cosSurface = glm::dot(hit.shading, d.toLight);
        if (cosSurface <= 0.0f || !unoccludedToward(origin, d.toLight, rays)) continue;
        const bsdf::Lobes lobes = bsdf::evalLobes(*hit.material, hit.albedo, hit.shading, hit.wo, d.toLight);
        L += (lobes.diffuse + lobes.glossy) * d.irradiance * cosSurface;
    }
    if (lights_.environment) L += environmentDirect(hit, origin, sampler, depth, grid, rays);
    return L;
}

glm::vec3 DirectIntegrator::environmentDirect(const SurfaceHit& hit, const glm::vec3& origin, const Sampler& sampler,
                                              int depth, int grid, RayCounts& rays) const {
    // m x m stratified samples of each strategy, MIS-weighted with the power heuristic (equal
    // counts, so the weights take the pdfs alone). A constant environment takes the BSDF samples
    // only, with weight 1: they are its ideal importance (exact for an unoccluded Lambert hit).
    const EnvironmentSampler& env = *lights_.environment;
    const ShadingMaterial& mat = *hit.material;
    const float diffusePick = mat.glossy ? mat.diffuseWeight : 1.0f;
    const int m = grid;
    const float invM = 1.0f / static_cast<float>(m);
    const int count = m * m;
    glm::vec3 sum(0.0f);
    if (!env.constant()) {
        for (int j = 0; j < count; ++j) {
            const EnvironmentSampler::Sample s =
                env.sample(sampler.jittered2D(dims::path(depth, dims::PathSlot::EnvLight, j), j % m, j / m, invM));
            if (!(s.pdf > 0.0f) || glm::dot(hit.geometric, s.direction) <= 0.0f) continue;
            const float cosSurface = glm::dot(hit.shading, s.direction);
            if (cosSurface <= 0.0f || !(bsdf::maxComponent(s.radiance) > 0.0f)) continue;
            const bsdf::Eval e = bsdf::evalSmooth(mat, hit.albedo, hit.shading, hit.wo, s.direction, cosSurface, diffusePick);
            if (!(bsdf::maxComponent(e.f) > 0.0f) || !unoccludedToward(origin, s.direction, rays)) continue;
            sum += e.f * s.radiance * (cosSurface * powerHeuristic(s.pdf, e.pdf) / s.pdf);
        }
    }
    for (int j = 0; j < count; ++j) {
        const float lobeU = sampler.get1D(dims::path(depth, dims::PathSlot::EnvLobe, j));
        const glm::vec2 u = sampler.jittered2D(dims::path(depth, dims::PathSlot::EnvBsdf, j), j % m, j / m, invM);
        glm::vec3 dir;
        if (!bsdf::sampleSmooth(mat, hit.shading, hit.wo, lobeU, u, dir)) continue;
        const float cosSurface = glm::dot(hit.shading, dir);
        if (cosSurface <= 0.0f || glm::dot(hit.geometric, dir) <= 0.0f) continue;
        const bsdf::Eval e = bsdf::evalSmooth(mat, hit.albedo, hit.shading, hit.wo, dir, cosSurface, diffusePick);
        if (!(e.pdf > 0.0f)) continue;
        const glm::vec3 Le = env.radiance(dir);
        if (!(bsdf::maxComponent(Le) > 0.0f) || !unoccludedToward(origin, dir, rays)) continue;
        const float w = env.constant() ? 1.0f : powerHeuristic(e.pdf, env.pdf(dir));
        sum += e.f * Le * (cosSurface * w / e.pdf);
    }
    return sum * (invM * invM);
}

glm::vec3 DirectIntegrator::directFewLights(const SurfaceHit& hit, const Sampler& sampler, int depth,
                                            LightBudget budget, RayCounts& rays) const {
    const int glossySamples = budget.glossySamples;
    const ShadingMaterial& mat = *hit.material;
    const glm::vec3 origin = hit.position + hit.offset * hit.geometric;
    // A Lambert surface's BRDF does not depend on the direction: it needs the irradiance alone.
    // Every other BSDF is evaluated per sample (bsdf::evalLobes), its glossy lobe MIS-weighted
    // against the glossy samples.
    const bool lambert = mat.model == BsdfModel::Classic && !mat.glossy;
    glm::vec3 irradiance(0.0f);  // sum of E_i = L_i cos / d^2 (point: I cos / d^2), for a Lambert surface
    glm::vec3 L(0.0f);           // otherwise: the reflected radiance itself

    for (const PointLightSource& light : lights_.points) {
        // Geometry from the true hit point; the shadow ray leaves from the offset origin.
        const glm::vec3 w = light.position - hit.position;
        const float d2 = glm::dot(w, w);
        if (!(d2 > 0.0f)) continue;
        const glm::vec3 l = w * (1.0f / std::sqrt(d2));
        // The geometric test decides the side (a shadow ray into the surface would self-hit);
        // the shading normal weights.
        if (glm::dot(hit.geometric, l) <= 0.0f) continue;
        const float cosSurface = glm::dot(hit.shading, l);
        if (cosSurface <= 0.0f) continue;
        const float lobe = light.angular(-l);  // cosine lobe or spot cone
        if (lobe <= 0.0f) continue;
        if (!unoccluded(origin, light.position, 1.0f, rays)) continue;  // a point: nothing to stop short of
        const glm::vec3 E = light.intensity * (lobe * cosSurface / d2);
        if (lambert) {
            irradiance += E;
            continue;
        }
        const bsdf::Lobes lobes = bsdf::evalLobes(mat, hit.albedo, hit.shading, hit.wo, l);
        L += E * (lobes.diffuse + lobes.glossy);  // a delta light: BSDF sampling never finds it
    }

    const int m = budget.grid;
    const float invM = 1.0f / static_cast<float>(m);
    const float invCount = invM * invM;
    const int count = m * m;
    ShadowBatch8 batch;
    for (std::size_t li = 0; li < lights_.areas.size(); ++li) {
        const AreaLightSampler& light = lights_.areas[li];
        LightView view = viewOf(light, hit.position);
        const bool bySolidAngle = view.solidAngle > 0.0f;
        float sum = 0.0f;  // sum of cos cos' / d^2 (by solid angle: cos) over the visible samples, in sample order
        glm::vec3 f(0.0f);  // the same weights times the BRDF
        for (int first = 0; first < count; first += ShadowBatch8::kWidth) {
            const int lanes = std::min(ShadowBatch8::kWidth, count - first);
            for (int i = 0; i < lanes; ++i) {
                const int j = first + i;
                const std::uint64_t dim = dims::areaLight(depth, static_cast<int>(li), j);
                const LightPoint q = light.sample(view, hit.position, sampler.jittered2D(dim, j % m, j / m, invM));
                batch.setSample(i, q.position, q.normal);
            }
            batch.padFrom(lanes);
            batch.prepare(lanes, hit.position, origin, hit.geometric, hit.shading, light.vertexScale(), bySolidAngle);
            sum += batch.trace(scene_, lanes, rays);
            if (lambert) continue;
            for (int i = 0; i < lanes; ++i) {
                if (!batch.visible(i)) continue;
                const glm::vec3 w = glm::vec3(batch.qx[i], batch.qy[i], batch.qz[i]) - hit.position;
                const float d2 = glm::dot(w, w), d = std::sqrt(d2);
                const glm::vec3 l = w / d;
                const bsdf::Lobes lobes = bsdf::evalLobes(mat, hit.albedo, hit.shading, hit.wo, l);
                float share = 1.0f;
                if (glossySamples > 0 && lobes.glossyPdf > 0.0f) {
                    const float cosLight = -glm::dot(glm::vec3(batch.nx[i], batch.ny[i], batch.nz[i]), l);
                    share = lightShare(static_cast<float>(count) / light.inversePdf(view, cosLight, d2), glossySamples,
                                       lobes.glossyPdf);
                }
                f += batch.weight[i] * (lobes.diffuse + share * lobes.glossy);
            }
        }
        // 1 / pdf, less the per-sample factors already in the weights.
        const float scale = (bySolidAngle ? view.solidAngle : light.area()) * invCount;
        if (lambert)
            irradiance += light.radiance() * (sum * scale);
        else
            L += light.radiance() * f * scale;
    }
    if (lambert) return hit.albedo * bsdf::kInvPi * irradiance;
    return L;
}

glm::vec3 DirectIntegrator::directManyLights(const SurfaceHit& hit, const Sampler& sampler, int depth,
                                             LightBudget budget, RayCounts& rays) const {
    if (shading_.lightSelection == LightSelection::Contribution && lights_.perHitSelectable())
        return directPerHitLights(hit, sampler, depth, budget, rays);
    // N = m x m stratified samples over [0,1)^2; u.x picks a light on the power CDF and, rescaled,
    // also places the point on it, so the pattern stays stratified over lights and their areas.
    const glm::vec3 origin = hit.position + hit.offset * hit.geometric;
    const int m = budget.grid;
    const float invM = 1.0f / static_cast<float>(m);
    glm::vec3 sum(0.0f);
    LastLightView last;
    PendingShadow pending[8];
    int queued = 0;
    for (int j = 0; j < m * m; ++j) {
        glm::vec2 u = sampler.jittered2D(dims::path(depth, dims::PathSlot::ManyLights, j), j % m, j / m, invM);
        const std::size_t l = lights_.select(u.x);
        if (prepareLightSample(hit, l, u, lights_.selectPdf[l], budget, last, pending[queued]) && ++queued == 8) {
            sum += traceLightSamples(origin, pending, queued, rays);
            queued = 0;
        }
    }
    if (queued > 0) sum += traceLightSamples(origin, pending, queued, rays);
    return sum * (invM * invM);
}

glm::vec3 DirectIntegrator::directPerHitLights(const SurfaceHit& hit, const Sampler& sampler, int depth,
                                               LightBudget budget, RayCounts& rays) const {
    // Per-hit CDF over each light's estimated contribution here (LightSet::contribution), in a
    // stack array: no allocation. Lights that cannot reach the hit get probability 0, and so
    // would have contributed 0: the estimator stays unbiased.
    const std::size_t n = lights_.count();
    float cdf[LightSet::kMaxPerHitLights];
    float total = 0.0f;
    std::size_t lastUsed = n;
    for (std::size_t l = 0; l < n; ++l) {
        const float w = lights_.contribution(l, hit.position, hit.shading);
        if (w > 0.0f) lastUsed = l;
        total += w;
        cdf[l] = total;
    }
    if (lastUsed == n || !(total > 0.0f)) return glm::vec3(0.0f);  // no light reaches this hit
    const float invTotal = 1.0f / total;
    // Pin the CDF's end at the last reachable light so rounding cannot select a zero-weight one.
    for (std::size_t l = 0; l < n; ++l) cdf[l] = l >= lastUsed ? 1.0f : cdf[l] * invTotal;

    // Sample j of N uses selection number (j + r.x) / N: 1D-stratified over the whole CDF, so each
    // light gets a share of samples close to its probability. The remainder places the point on
    // the light; y takes stratum (j % m) m + j / m, so runs of consecutive j (one light's
    // samples) spread over y as well. That fixed permutation alone would only ever visit N of the
    // N^2 cells (biased); a per-hit random shift of y (Cranley-Patterson) makes each sample's y
    // uniform and independent of its x again.
    const glm::vec3 origin = hit.position + hit.offset * hit.geometric;
    const int m = budget.grid;
    const int count = m * m;
    const float invCount = 1.0f / static_cast<float>(count);
    const float shiftY = sampler.get1D(dims::path(depth, dims::PathSlot::ManyLights, kShiftSample));
    glm::vec3 sum(0.0f);
    LastLightView last;
    PendingShadow pending[8];  // traced 8 at a time, in sample order
    int queued = 0;
    for (int j = 0; j < count; ++j) {
        const glm::vec2 r = sampler.get2D(dims::path(depth, dims::PathSlot::ManyLights, j));
        float y = (static_cast<float>((j % m) * m + j / m) + r.y) * invCount + shiftY;
        y -= y >= 1.0f ? 1.0f : 0.0f;
        glm::vec2 u{std::min((static_cast<float>(j) + r.x) * invCount, Sampler::kOneMinusUlp),
                    std::min(std::max(y, 0.0f), Sampler::kOneMinusUlp)};
        const std::size_t l = selectOnCdf(cdf, n, u.x);
        const float pick = (cdf[l] - (l == 0 ? 0.0f : cdf[l - 1]));
        if (!(pick > 0.0f)) continue;  // unreachable: zero-width intervals are never selected
        if (prepareLightSample(hit, l, u, pick, budget, last, pending[queued]) && ++queued == 8) {
            sum += traceLightSamples(origin, pending, queued, rays);
            queued = 0;
        }
    }
    if (queued > 0) sum += traceLightSamples(origin, pending, queued, rays);
    return sum * invCount;
}

bool DirectIntegrator::prepareLightSample(const SurfaceHit& hit, std::size_t l, glm::vec2 u, float pick,
                                          LightBudget budget, LastLightView& last, PendingShadow& out) const {
    // u: the point on an area light; pick: the light's selection probability.
    const ShadingMaterial& mat = *hit.material;
    const std::size_t nPoints = lights_.points.size();
    glm::vec3 target, Le;
    float geometry = 0.0f, tfar = 1.0f;  // 1 / pdf in solid angle (point: lobe / d^2)
    if (l < nPoints) {
        const PointLightSource& p = lights_.points[l];
        target = p.position;
        Le = p.intensity;
        const glm::vec3 w = target - hit.position;
        const float d2 = glm::dot(w, w);
        const float lobe = p.angular(-glm::normalize(w));
        if (!(d2 > 0.0f) || lobe <= 0.0f) return false;
        geometry = lobe / d2;
    } else {
        const AreaLightSampler& a = lights_.areas[l - nPoints];
        if (last.light != l) last = {l, viewOf(a, hit.position)};
        LightView& view = last.view;
        const LightPoint q = a.sample(view, hit.position, u);
        target = q.position;
        Le = a.radiance();
        const glm::vec3 w = target - hit.position;
        const float d2 = glm::dot(w, w);
        if (!(d2 > 0.0f)) return false;
        const float d = std::sqrt(d2);
        const float cosLight = -glm::dot(q.normal, w) / d;
        if (cosLight <= 0.0f) return false;
        geometry = a.inversePdf(view, cosLight, d2);
        tfar = 1.0f - rayOffset(target, a.vertexScale()) / d;
    }
    const glm::vec3 l3 = glm::normalize(target - hit.position);
    if (glm::dot(hit.geometric, l3) <= 0.0f) return false;
    const float cosSurface = glm::dot(hit.shading, l3);
    if (cosSurface <= 0.0f || !(tfar > 0.0f)) return false;
    const bsdf::Lobes lobes = bsdf::evalLobes(mat, hit.albedo, hit.shading, hit.wo, l3);
    // An area light's sample shares the glossy lobe with the glossy samples (MIS); all m x m
    // samples draw from the same mixture, density pick / geometry each.
    const float share = l < nPoints || !(lobes.glossyPdf > 0.0f)
                            ? 1.0f
                            : lightShare(static_cast<float>(budget.grid * budget.grid) * pick / geometry, budget.glossySamples,
                                         lobes.glossyPdf);
    out = {target, (lobes.diffuse + share * lobes.glossy) * Le * (geometry * cosSurface / pick), tfar};
    return true;
}

glm::vec3 DirectIntegrator::traceLightSamples(const glm::vec3& origin, const PendingShadow* samples, int count,
                                              RayCounts& rays) const {
    // The samples' shadow rays share the origin: one 8-wide packet traversal for up to 8 of them.
    alignas(32) int valid[8];
    RTCRay8 packet;
    for (int i = 0; i < 8; ++i) {
        const bool on = i < count;
        valid[i] = on ? -1 : 0;
        setShadowLane(packet, i, origin, on ? samples[i].target - origin : glm::vec3(0.0f, 0.0f, 1.0f),
                      on ? samples[i].tfar : 0.0f);
    }
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    rtcOccluded8(valid, scene_, &context, &packet);
    rays.shadow += static_cast<std::uint64_t>(count);
    glm::vec3 sum(0.0f);
    for (int i = 0; i < count; ++i)
        if (packet.tfar[i] >= 0.0f) sum += samples[i].contribution;  // Embree sets tfar to -inf on a hit
    return sum;
}

}  // namespace aamap
