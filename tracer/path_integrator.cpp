#include "tracer/path_integrator.h"

#include <algorithm>
#include <limits>
#include <cmath>

#include <glm/geometric.hpp>

#include "tracer/bsdf.h"
#include "tracer/ray_packet.h"
#include "tracer/shadow_packet.h"

namespace aamap {
namespace {

// How light arriving from direction wi reaches the vertex: the cosine at the surface (> 0), the
// shadow ray's origin (offset to wi's side) and the BSDF. Only a rough dielectric (the one Glass
// that samples lights) takes light from behind, through its interface; false where the surface
// cannot pass light from wi.
bool lightToward(const SurfaceHit& hit, const glm::vec3& wi, float diffusePick, float& cosSurface, glm::vec3& origin,
                 bsdf::Eval& e) {
    const ShadingMaterial& m = *hit.material;
    const float g = glm::dot(hit.geometric, wi), c = glm::dot(hit.shading, wi);
    if (m.kind == MaterialKind::Glass) {
        if (c * g <= 0.0f) return false;  // the shading and geometric normals disagree about the side
        cosSurface = std::abs(c);
        origin = hit.position + (g > 0.0f ? hit.offset : -hit.offset) * hit.geometric;
        e = bsdf::evalRoughDielectric(m, hit.shading, hit.wo, hit.front ? m.ior : 1.0f / m.ior, wi);
        return true;
    }
    if (g <= 0.0f || c <= 0.0f) return false;
    cosSurface = c;
    origin = hit.position + hit.offset * hit.geometric;
    e = bsdf::evalSmooth(m, hit.albedo, hit.shading, hit.wo, wi, c, diffusePick);
    return true;
}

// Traces the segments segmentOf(i) gives (nullptr: none) for the active lanes as one occlusion
// packet: valid[i] = -1 for those traced, and packet.tfar[i] < 0 where something blocks them.
template <class SegmentOf>
void traceShadows(RTCScene scene, RTCRay8& packet, int* valid, const int* lanes, int active, RayCounts& rays,
                  SegmentOf&& segmentOf) {
    int count = 0;
    for (int a = 0; a < active; ++a) {
        const int i = lanes[a];
        const ShadowSegment* segment = segmentOf(i);
        if (segment == nullptr) continue;
        valid[i] = -1;
        ++count;
        setShadowLane(packet, i, segment->origin, segment->dir, segment->tfar);
    }
    if (count == 0) return;
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    context.flags = RTC_INTERSECT_CONTEXT_FLAG_INCOHERENT;
    rtcOccluded8(valid, scene, &context, &packet);
    rays.shadow += static_cast<std::uint64_t>(count);
}

}  // namespace

// One light sample per vertex: Auto samples area lights by area (docs/tracer.md, "Lights").
PathIntegrator::PathIntegrator(const EmbreeScene& geometry, const LightSet& lights, const ShadingSettings& shading)
    : Integrator(geometry, lights, shading, "path", LightSampling::Area) {
    // The lanes sample area lights by area, or no finite light at all (lights at infinity alone,
    // sampled per lane afterwards); point lights and solid-angle sampling stay scalar.
    simd_ = lights_.points.empty() &&
            (lights_.areas.empty() ? lights_.selectCdf.empty() : !lights_.selectCdf.empty() && !bySolidAngle());
    if (simd_) simdLights_ = pathsimd::makeLightTable(lights_);
}

glm::vec3 PathIntegrator::nextEventInfinite(const SurfaceHit& hit, const Sampler& sampler, int depth, float diffusePick,
                                            RayCounts& rays, bool environment) const {
    glm::vec3 L(0.0f);
    float cosSurface = 0.0f;
    glm::vec3 origin;
    bsdf::Eval e;
    for (const DirectionalSource& d : lights_.directionals) {  // delta lights: no MIS
        if (!lightToward(hit, d.toLight, diffusePick, cosSurface, origin, e)) continue;
        if (!unoccludedToward(origin, d.toLight, rays)) continue;
        L += e.f * d.irradiance * cosSurface;
    }
    if (!environment || !lights_.environment || lights_.environment->constant()) return L;
    const EnvironmentSampler::Sample s = lights_.environment->sample(sampler.get2D(dims::path(depth, dims::PathSlot::EnvLight)));
    if (!(s.pdf > 0.0f)) return L;
    if (!lightToward(hit, s.direction, diffusePick, cosSurface, origin, e)) return L;
    if (!unoccludedToward(origin, s.direction, rays)) return L;
    return L + e.f * s.radiance * (cosSurface * powerHeuristic(s.pdf, e.pdf) / s.pdf);
}

glm::vec3 PathIntegrator::escapedPath(const glm::vec3& dir, bool specularBefore, float pdfBefore) const {
    if (!lights_.environment) return glm::vec3(0.0f);
    const EnvironmentSampler& env = *lights_.environment;
    // Only a map is light-sampled (nextEventInfinite); a constant sky comes from here alone.
    const float w = specularBefore || env.constant() ? 1.0f : powerHeuristic(pdfBefore, env.pdf(dir));
    return env.radiance(dir) * w;
}


bool PathIntegrator::prepareNextEventFinite(const SurfaceHit& hit, const Sampler& sampler, int depth, float diffusePick,
                                            glm::vec3& contribution, ShadowSegment& segment) const {
    if (lights_.selectCdf.empty()) return false;
    glm::vec2 u = sampler.get2D(dims::path(depth, dims::PathSlot::Light));
    const std::size_t l = lights_.select(u.x);
    const float pick = lights_.selectPdf[l];
    float cosSurface = 0.0f;
    glm::vec3 origin;
    bsdf::Eval e;
    const std::size_t nPoints = lights_.points.size();
    if (l < nPoints) {  // a delta light: BSDF sampling never finds it, so no MIS
        const PointLightSource& p = lights_.points[l];
        const glm::vec3 w = p.position - hit.position;
        const float d2 = glm::dot(w, w);
        if (!(d2 > 0.0f)) return false;
        const glm::vec3 wi = w * (1.0f / std::sqrt(d2));
        const float lobe = p.angular(-wi);
        if (lobe <= 0.0f || !lightToward(hit, wi, diffusePick, cosSurface, origin, e)) return false;
        segment = {origin, p.position - origin, 1.0f};  // a point: nothing to stop short of
        contribution = e.f * p.intensity * (lobe * cosSurface / (d2 * pick));
        return true;
    }
    const AreaLightSampler& a = lights_.areas[l - nPoints];
    LightView view = viewOf(a, hit.position);
    const LightPoint q = a.sample(view, hit.position, u);
    const glm::vec3 w = q.position - hit.position;
    const float d2 = glm::dot(w, w);
    if (!(d2 > 0.0f)) return false;
    const float invD = 1.0f / std::sqrt(d2);
    const glm::vec3 wi = w * invD;
    const float cosLight = -glm::dot(q.normal, wi);
    if (cosLight <= 0.0f || !lightToward(hit, wi, diffusePick, cosSurface, origin, e)) return false;
    const float tfar = 1.0f - rayOffset(q.position, a.vertexScale()) * invD;
    if (!(tfar > 0.0f)) return false;
    segment = {origin, q.position - origin, tfar};
    // The power heuristic over the light's pdf, pdfLight = pick / inv (solid angle), in one
    // division: w / pdfLight = pdfLight / (pdfLight^2 + pdfBsdf^2) = pick inv / (pick^2 + (pdfBsdf inv)^2).
    const float inv = a.inversePdf(view, cosLight, d2);
    const float bsdfInv = e.pdf * inv;
    const float denominator = pick * pick + bsdfInv * bsdfInv;
    if (!(denominator > 0.0f)) return false;
    contribution = e.f * a.radiance() * (cosSurface * (pick * inv / denominator));
    return true;
}

// A path between two of its vertices: what carries over from one bounce to the next.
struct PathIntegrator::PathState {
    SurfaceHit hit;              // the vertex to scatter at
    glm::vec3 L{0.0f};           // radiance gathered so far
    glm::vec3 beta{1.0f};        // throughput up to `hit`
    glm::vec3 before{0.0f};      // the vertex the last BSDF sample left from (where light sampling views the light)
    float pdfBefore = 0.0f;      // solid-angle pdf of that BSDF sample
    bool specularBefore = true;  // the camera "sampled" the primary direction: no MIS on it
    float etaScale = 1.0f;       // product of eta^2 over the refractions so far (beta * etaScale is unscaled)
    int depth = 0;
};

// What scattering at one vertex asks of the ray tracer: a shadow segment for next-event
// estimation and the ray the path goes on along. Either may be missing.
// Only the flags are reset per vertex: the vectors are written before they are read.
struct PathIntegrator::PathVertex {
    bool nextEvent;  // NEE was done: L += neeBeta * (finite where its segment is clear + infinite)
    bool shadow;     // finite has a segment to test
    bool infiniteLights;
    bool next;       // the path goes on from nextOrigin along unit nextDir
    bool envShadow;  // the SIMD lanes sampled the environment map: envContribution where
                     // envSegment (to infinity) is clear; infinite then holds the rest
    glm::vec3 neeBeta, finite, infinite;
    ShadowSegment segment;
    glm::vec3 nextOrigin, nextDir;
    glm::vec3 envContribution;
    ShadowSegment envSegment;
    void reset() { nextEvent = shadow = infiniteLights = next = envShadow = false; }
};

void PathIntegrator::addEmission(PathState& s) const {
    const SurfaceHit& hit = s.hit;
    const ShadingMaterial& m = *hit.material;
    if (m.emissive && hit.front && !(s.depth == 0 && shading_.hideEmitters)) {
        float w = 1.0f;
        const std::int32_t area = lights_.areaOfTriangle.empty() ? -1 : lights_.areaOfTriangle[hit.primitive];
        if (!s.specularBefore && area >= 0) {
            // What light sampling from the vertex before would have paid for this point:
            // P(light) times its solid-angle pdf there.
            const AreaLightSampler& a = lights_.areas[static_cast<std::size_t>(area)];
            const float cosLight = glm::dot(hit.geometric, hit.wo);
            const float pdfLight = lights_.selectPdf[lights_.points.size() + static_cast<std::size_t>(area)] /
                                   a.inversePdf(viewOf(a, s.before), cosLight, hit.distance * hit.distance);
            w = powerHeuristic(s.pdfBefore, pdfLight);
        }
        s.L += s.beta * m.ke * w;
    }
}

void PathIntegrator::scatterPathVertex(PathState& s, const Sampler& sampler, PathVertex& out, RayCounts& rays) const {
    const SurfaceHit& hit = s.hit;
    const ShadingMaterial& m = *hit.material;
    const int depth = s.depth;
    addEmission(s);
    if (depth + 1 >= shading_.maxDepth) return;  // one more segment would exceed maxDepth
    if (m.oneSided && !hit.front) return;         // a one-sided BSDF's back: black, the path ends

    const float lobeU = sampler.get1D(dims::path(depth, dims::PathSlot::Lobe));
    glm::vec3 dir;
    if (m.kind == MaterialKind::Glass && m.rough) {
        // Mitsuba's roughdielectric: lights sampled on both sides (through the interface too), and
        // a visible-normal reflection or refraction, MIS-weighted against them.
        out.nextEvent = true;
        out.neeBeta = s.beta;
        out.shadow = prepareNextEventFinite(hit, sampler, depth, 1.0f, out.finite, out.segment);
        out.infiniteLights = !lights_.directionals.empty() || lights_.environment.has_value();
        if (out.infiniteLights) out.infinite = nextEventInfinite(hit, sampler, depth, 1.0f, rays);
        const float eta = hit.front ? m.ior : 1.0f / m.ior;
        glm::vec3 weight;
        bool refracted = false;
        const glm::vec2 u = sampler.get2D(dims::path(depth, dims::PathSlot::Bsdf));
        if (!bsdf::sampleRoughDielectric(m, hit.shading, hit.wo, eta, lobeU, u, dir, weight, refracted)) return;
        if (refracted ? glm::dot(dir, hit.geometric) >= 0.0f : glm::dot(dir, hit.geometric) <= 0.0f) return;
        const float pdf = bsdf::pdfRoughDielectric(m, hit.shading, hit.wo, eta, dir);
        if (!(pdf > 0.0f)) return;
        s.beta *= weight;
        if (refracted) s.etaScale *= eta * eta;
        s.pdfBefore = pdf;
        s.specularBefore = false;
    } else if (m.kind == MaterialKind::Glass) {
        // One branch, chosen with the Fresnel probability: weight ks either way.
        const float cosI = std::min(glm::dot(hit.wo, hit.shading), 1.0f);
        if (!(cosI > 0.0f)) return;
        const float eta = hit.front ? m.ior : 1.0f / m.ior;
        float cosT = 0.0f;
        // A thin sheet reflects 2R / (1 + R) and lets the rest straight through.
        const float F = m.thin ? bsdf::thinDielectricReflectance(cosI, m.ior) : bsdf::fresnelDielectric(cosI, eta, cosT);
        if (m.thin && !(lobeU < F)) {
            dir = -hit.wo;
        } else if (lobeU < F) {
            dir = bsdf::reflect(hit.wo, hit.shading);
            if (glm::dot(dir, hit.geometric) <= 0.0f) return;
        } else {
            dir = bsdf::refract(hit.wo, hit.shading, eta, cosI, cosT);
            if (glm::dot(dir, hit.geometric) >= 0.0f) return;
            // Radiance crossing into a medium of relative index eta is L / eta^2 of the radiance
            // there (Mitsuba's dielectric does the same): a closed object's entry and exit cancel,
            // a single open interface (a pane as one sheet) keeps it.
            s.beta *= 1.0f / (eta * eta);
            s.etaScale *= eta * eta;
        }
        s.beta *= m.ks;
        s.specularBefore = true;
    } else {
        // Mirror (and the smooth Mitsuba models): the delta lobe with its probability, else the
        // non-delta part.
        const float cosO = std::clamp(glm::dot(hit.wo, hit.shading), 0.0f, 1.0f);
        const float specularPick = m.kind == MaterialKind::Mirror ? bsdf::deltaPick(m, cosO) : 0.0f;
        const float diffusePick = m.kind == MaterialKind::Mirror ? 1.0f - specularPick
                                  : m.glossy                      ? m.diffuseWeight
                                                                  : 1.0f;
        const bool nonDelta = (m.diffuse || m.glossy) && (m.kind != MaterialKind::Mirror || diffusePick > 0.0f);
        if (nonDelta) {
            // Next-event estimation of the non-delta lobes at every such vertex, whichever lobe the
            // path goes on with (light sampling does not depend on that choice), weighted by the
            // throughput before this vertex's scattering.
            out.nextEvent = true;
            out.neeBeta = s.beta;
            out.shadow = prepareNextEventFinite(hit, sampler, depth, diffusePick, out.finite, out.segment);
            out.infiniteLights = !lights_.directionals.empty() || lights_.environment.has_value();
            if (out.infiniteLights) out.infinite = nextEventInfinite(hit, sampler, depth, diffusePick, rays);
        }
        if (lobeU < specularPick) {
            dir = bsdf::reflect(hit.wo, hit.shading);
            if (glm::dot(dir, hit.geometric) <= 0.0f) return;
            s.beta *= bsdf::deltaReflectance(m, cosO) * (1.0f / specularPick);
            s.specularBefore = true;
        } else {
            if (!nonDelta) return;  // black
            const glm::vec2 u = sampler.get2D(dims::path(depth, dims::PathSlot::Bsdf));
            if (!bsdf::sampleSmooth(m, hit.shading, hit.wo, lobeU, u, dir)) return;
            const float cosI = glm::dot(hit.shading, dir);
            if (cosI <= 0.0f || glm::dot(hit.geometric, dir) <= 0.0f) return;
            const bsdf::Eval e = bsdf::evalSmooth(m, hit.albedo, hit.shading, hit.wo, dir, cosI, diffusePick);
            if (!(e.pdf > 0.0f)) return;
            s.beta *= e.f * (cosI / e.pdf);
            s.pdfBefore = e.pdf;
            s.specularBefore = false;
        }
    }
    if (shading_.russianRoulette && depth + 1 >= shading_.rouletteDepth) {
        // As Mitsuba: the throughput without the eta^2 factors, which cancel on leaving the medium.
        const float survive = std::min(bsdf::maxComponent(s.beta) * s.etaScale, 0.95f);
        if (!(sampler.get1D(dims::path(depth, dims::PathSlot::Roulette)) < survive)) return;
        s.beta *= 1.0f / survive;
    }
    out.next = true;
    out.nextOrigin = hit.originFor(dir);
    out.nextDir = dir;
    s.before = hit.position;
}

void PathIntegrator::finishSimdLane(PathState& s, const Sampler& sampler, const pathsimd::Lanes& lanes, int k,
                                    PathVertex& out, RayCounts& rays) const {
    const SurfaceHit& hit = s.hit;
    const ShadingMaterial& m = *hit.material;
    const int depth = s.depth;
    const bool onLanes = lanes.model[k] != pathsimd::kOther;  // the lanes shaded its BSDF too
    const float diffusePick = m.glossy ? m.diffuseWeight : 1.0f;
    const auto vec = [&](const float (&a)[3][pathsimd::kLanes]) { return glm::vec3(a[0][k], a[1][k], a[2][k]); };
    out.nextEvent = true;
    out.neeBeta = s.beta;
    if (onLanes) {
        out.shadow = lanes.shadow[k] != 0;
        out.finite = vec(lanes.contribution);
    } else if (lanes.lightOk[k] != 0) {
        // prepareNextEventFinite's BSDF and MIS weight on the lanes' light sample.
        const float cosSurface = lanes.cosSurface[k], inv = lanes.inv[k], pick = lanes.pick[k];
        const bsdf::Eval e =
            bsdf::evalSmooth(m, hit.albedo, hit.shading, hit.wo, vec(lanes.wi), cosSurface, diffusePick);
        const float bsdfInv = e.pdf * inv;
        const float denominator = pick * pick + bsdfInv * bsdfInv;
        out.shadow = denominator > 0.0f;
        out.finite = e.f * vec(lanes.radiance) * (cosSurface * (pick * inv / denominator));
    }
    if (out.shadow) out.segment = {vec(lanes.origin), vec(lanes.segment), lanes.tfar[k]};
    // The lanes sampled an environment map for this lane (Lambert and rough plastic lanes).
    const bool envOnLanes = onLanes && simdLights_.envWidth > 0;
    if (envOnLanes && lanes.envShadow[k] != 0) {
        out.envShadow = true;
        out.envContribution = vec(lanes.envContribution);
        out.envSegment = {vec(lanes.origin), vec(lanes.envDir), std::numeric_limits<float>::infinity()};
    }
    out.infiniteLights = !lights_.directionals.empty() || lights_.environment.has_value();
    if (out.infiniteLights) out.infinite = nextEventInfinite(hit, sampler, depth, diffusePick, rays, !envOnLanes);

    glm::vec3 dir;
    if (onLanes) {
        if (lanes.next[k] == 0) return;
        dir = vec(lanes.dir);
        s.beta = vec(lanes.beta);
        s.pdfBefore = lanes.pdf[k];
        s.specularBefore = false;
    } else {
        // scatterPathVertex's non-delta branch (no delta lobe here: m is not a Mirror).
        const glm::vec2 u(lanes.uBsdf[0][k], lanes.uBsdf[1][k]);
        if (!bsdf::sampleSmooth(m, hit.shading, hit.wo, lanes.uLobe[k], u, dir)) return;
        const float cosI = glm::dot(hit.shading, dir);
        if (cosI <= 0.0f || glm::dot(hit.geometric, dir) <= 0.0f) return;
        const bsdf::Eval e = bsdf::evalSmooth(m, hit.albedo, hit.shading, hit.wo, dir, cosI, diffusePick);
        if (!(e.pdf > 0.0f)) return;
        s.beta *= e.f * (cosI / e.pdf);
        s.pdfBefore = e.pdf;
        s.specularBefore = false;
        if (shading_.russianRoulette && depth + 1 >= shading_.rouletteDepth) {
            const float survive = std::min(bsdf::maxComponent(s.beta) * s.etaScale, 0.95f);
            if (!(lanes.uRoulette[k] < survive)) return;
            s.beta *= 1.0f / survive;
        }
    }
    out.next = true;
    out.nextOrigin = hit.originFor(dir);
    out.nextDir = dir;
    s.before = hit.position;
}

// The cone the next ray carries: the hit's, spread to the bounce's share of its lobe after a
// non-delta sample (ShadingSettings::bounceFootprint); a delta bounce keeps it, as a mirror keeps
// the camera pixel's footprint.
RayCone PathIntegrator::nextCone(const PathState& s) const {
    RayCone cone = s.hit.cone;
    if (s.specularBefore || shading_.textureFilter != TextureFilter::Anisotropic || !(shading_.bounceFootprint > 0.0f) ||
        !(s.pdfBefore > 0.0f))
        return cone;
    constexpr float kInvPi = 1.0f / 3.14159265358979f;
    const float lobe = std::min(2.0f * std::sqrt(kInvPi / s.pdfBefore), 3.14159265358979f);
    cone.spread = std::max(cone.spread, shading_.bounceFootprint * lobe);
    return cone;
}

void PathIntegrator::addNextEvent(PathState& s, const PathVertex& v, bool visible, bool envVisible) const {
    glm::vec3 nee = visible ? v.finite : glm::vec3(0.0f);
    if (v.infiniteLights) nee += v.infinite;
    if (envVisible) nee += v.envContribution;
    s.L += v.neeBeta * nee;
}

void PathIntegrator::endPath(PathState& s, const PathVertex& v) const {
    s.L += s.beta * escapedPath(v.nextDir, s.specularBefore, s.pdfBefore);
}

glm::vec3 PathIntegrator::tracePath(const SurfaceHit& first, const Sampler& sampler, RayCounts& rays) const {
    PathState s;
    s.hit = first;
    for (;;) {
        PathVertex v;
        v.reset();
        scatterPathVertex(s, sampler, v, rays);
        if (v.nextEvent)
            addNextEvent(s, v, v.shadow && !occluded(v.segment.origin, v.segment.dir, v.segment.tfar, rays), false);
        if (!v.next) break;
        if (!intersect(v.nextOrigin, v.nextDir, s.hit, rays.other, nextCone(s))) {
            endPath(s, v);
            break;
        }
        ++s.depth;
    }
    return s.L;
}

void PathIntegrator::primaryPacket(const RayPacket<kMaxPacket>& primaries, int count, const Sampler* samplers,
                                   const float* spreads, glm::vec3* out, RayCounts& rays) const {
    constexpr int W = kMaxPacket;
    PathState s[W];
    int lanes[W];  // the paths still going, in lane order
    int active = 0;
    for (int i = 0; i < count; ++i) {
        ++rays.primary;
        if (primaries.missed(i)) {
            out[i] = escapedCamera(primaries.dir[i]);
            continue;
        }
        fillHit(primaries, i, cameraCone(spreads[i]), s[i].hit);
        lanes[active++] = i;
    }
    // Lanes a packet does not trace keep finite data from their last use (Embree may load them).
    RTCRay8 shadow, envShadow;
    RayPacket<W> next;
    for (int i = 0; i < W; ++i) {
        setShadowLane(shadow, i, glm::vec3(0.0f), glm::vec3(0.0f, 0.0f, 1.0f), 0.0f);
        setShadowLane(envShadow, i, glm::vec3(0.0f), glm::vec3(0.0f, 0.0f, 1.0f), 0.0f);
        next.setIdle(i);
    }
    // Every path scatters, then their shadow segments go out as one packet and their next rays as
    // another: each lane does what tracePath does, in the same order (on the SIMD lanes only the
    // bounce's sine and cosine round differently).
    PathVertex v[W];
    pathsimd::Lanes simd{};  // zeroed once: lanes read fields their model does not set
    while (active > 0) {
        // The common vertices go to the SIMD lanes (after their emission, which is rare), the
        // others scatter one by one.
        int simdLane[W];
        int simdCount = 0;
        const int depth = s[lanes[0]].depth;  // lockstep: every live path is at the same depth
        for (int a = 0; a < active; ++a) {
            const int i = lanes[a];
            v[i].reset();
            const SurfaceHit& hit = s[i].hit;
            if (!simdVertex(*hit.material)) {
                scatterPathVertex(s[i], samplers[i], v[i], rays);
                continue;
            }
            addEmission(s[i]);
            if (depth + 1 >= shading_.maxDepth) continue;        // one more segment would exceed maxDepth
            if (hit.material->oneSided && !hit.front) continue;  // black, the path ends
            const int k = simdCount++;
            simdLane[k] = i;
            simd.key[k] = samplers[i].key();
            const ShadingMaterial& m = *hit.material;
            simd.model[k] = m.model == BsdfModel::Classic && !m.glossy ? pathsimd::kLambert
                            : m.model == BsdfModel::Plastic && m.rough && m.distribution == MicrofacetType::GGX
                                ? pathsimd::kRoughPlastic
                                : pathsimd::kOther;
            simd.material[k] = &m;
            for (int c = 0; c < 3; ++c) {
                simd.p[c][k] = hit.position[c];
                simd.g[c][k] = hit.geometric[c];
                simd.n[c][k] = hit.shading[c];
                simd.wo[c][k] = hit.wo[c];
                simd.albedo[c][k] = hit.albedo[c];
                simd.beta[c][k] = s[i].beta[c];
            }
            simd.offset[k] = hit.offset;
            simd.etaScale[k] = s[i].etaScale;
            if (simd.model[k] == pathsimd::kRoughPlastic) {
                // What depends on wo alone, from the scalar code's own functions.
                const float cosO = glm::dot(hit.shading, hit.wo);
                const microfacet::Distribution dist = bsdf::distributionOf(m);
                simd.alpha[0][k] = dist.alphaU;
                simd.alpha[1][k] = dist.alphaV;
                simd.ior[k] = m.ior;
                const glm::vec3 base = bsdf::plasticBase(m, hit.albedo);
                for (int c = 0; c < 3; ++c) {
                    simd.base[c][k] = base[c];
                    simd.tint[c][k] = m.specularTint[c];
                }
                simd.tO[k] = bsdf::coatingTransmittance(m, cosO);
                simd.pickSpecular[k] = bsdf::plasticSpecularPick(m, cosO);
            }
        }
        if (simdCount > 0) {
            // The vector loop runs over whole vectors: the spare lanes repeat lane 0.
            for (int k = simdCount; k < pathsimd::kLanes; ++k) {
                simd.key[k] = simd.key[0];
                simd.model[k] = simd.model[0];
                simd.material[k] = simd.material[0];
                for (int c = 0; c < 3; ++c) {
                    simd.p[c][k] = simd.p[c][0];
                    simd.g[c][k] = simd.g[c][0];
                    simd.n[c][k] = simd.n[c][0];
                    simd.wo[c][k] = simd.wo[c][0];
                    simd.albedo[c][k] = simd.albedo[c][0];
                    simd.beta[c][k] = simd.beta[c][0];
                    simd.base[c][k] = simd.base[c][0];
                    simd.tint[c][k] = simd.tint[c][0];
                }
                simd.alpha[0][k] = simd.alpha[0][0];
                simd.alpha[1][k] = simd.alpha[1][0];
                simd.ior[k] = simd.ior[0];
                simd.tO[k] = simd.tO[0];
                simd.pickSpecular[k] = simd.pickSpecular[0];
                simd.offset[k] = simd.offset[0];
                simd.etaScale[k] = simd.etaScale[0];
            }
            pathsimd::shade(simdLights_, simd, simdCount, depth,
                            shading_.russianRoulette && depth + 1 >= shading_.rouletteDepth);
            for (int k = 0; k < simdCount; ++k)
                finishSimdLane(s[simdLane[k]], samplers[simdLane[k]], simd, k, v[simdLane[k]], rays);
        }
        // The light samples' shadow segments as one packet, and the environment samples the lanes
        // took as another (to infinity, as unoccludedToward traces them one by one).
        alignas(32) int shadowValid[W] = {};
        alignas(32) int envValid[W] = {};
        traceShadows(scene_, shadow, shadowValid, lanes, active, rays,
                     [&](int i) { return v[i].shadow ? &v[i].segment : nullptr; });
        traceShadows(scene_, envShadow, envValid, lanes, active, rays,
                     [&](int i) { return v[i].envShadow ? &v[i].envSegment : nullptr; });
        alignas(32) int nextValid[W] = {};
        int going = 0;
        for (int a = 0; a < active; ++a) {
            const int i = lanes[a];
            if (v[i].nextEvent)
                addNextEvent(s[i], v[i], shadowValid[i] != 0 && shadow.tfar[i] >= 0.0f,
                             envValid[i] != 0 && envShadow.tfar[i] >= 0.0f);
            if (!v[i].next) continue;
            nextValid[i] = -1;
            next.set(i, v[i].nextOrigin, v[i].nextDir);
            lanes[going++] = i;
        }
        active = going;
        if (active == 0) break;
        next.trace(scene_, nextValid, false);
        rays.other += static_cast<std::uint64_t>(active);
        going = 0;
        for (int a = 0; a < active; ++a) {
            const int i = lanes[a];
            if (next.missed(i)) {
                endPath(s[i], v[i]);
                continue;
            }
            fillHit(next, i, nextCone(s[i]), s[i].hit);  // as in tracePath
            ++s[i].depth;
            lanes[going++] = i;
        }
        active = going;
    }
    for (int i = 0; i < count; ++i)
        if (!primaries.missed(i)) out[i] = s[i].L;
}

}  // namespace aamap
