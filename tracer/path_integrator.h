#pragma once
// Path mode: unbiased path tracing, the ground truth for shading. Next-event estimation at every
// non-delta vertex (one light sample, light picked on the power CDF, plus every directional light
// and one environment-map sample), MIS with the power heuristic between light and BSDF sampling,
// Russian roulette by throughput. Rays that leave the scene bring back the environment. Depth
// counts path segments as Mitsuba's max_depth does.
//
// A path advances vertex by vertex: scatterPathVertex shades one vertex and says which shadow
// segment and which next ray it needs; the caller traces them. tracePath traces them one at a
// time; primaryPacket advances up to 8 paths in lockstep, shades their common vertices on SIMD
// lanes (tracer/path_simd.h) and traces their shadow segments and their next rays as 8-wide
// Embree packets (docs/tracer.md, "Path mode in lockstep").
#include "tracer/integrator.h"
#include "tracer/path_simd.h"

namespace aamap {

class PathIntegrator final : public Integrator {
public:
    PathIntegrator(const EmbreeScene& geometry, const LightSet& lights, const ShadingSettings& shading);

    // 8 wide for any 2-8 primary rays: the lanes' paths go on in lockstep, so a wider packet is
    // not wasted on its primary rays alone.
    int packetWidth(int samples) const override { return samples == 1 ? 1 : kMaxPacket; }
    // The lanes' paths advanced together, their shadow and bounce rays traced as packets too; each
    // lane's radiance (and ray count) is the one primaryFromHit gives it, up to the rounding of the
    // SIMD lanes' sine and cosine.
    void primaryPacket(const RayPacket<kMaxPacket>& primaries, int count, const Sampler* samplers,
                       const float* spreads, glm::vec3* out, RayCounts& rays) const override;
    using Integrator::primaryPacket;  // 4 wide: lane by lane (the tracer never asks for it)
    // Whether primaryPacket shades the common vertices on SIMD lanes (tracer/path_simd.h): every
    // light an area light, sampled by area.
    bool simdLanes() const { return simd_; }

protected:
    glm::vec3 shadeCamera(const SurfaceHit& hit, const Sampler& sampler, RayCounts& rays) const override {
        return tracePath(hit, sampler, rays);
    }

private:
    // The whole path from a primary hit.
    glm::vec3 tracePath(const SurfaceHit& first, const Sampler& sampler, RayCounts& rays) const;
    // PathState: one path between two vertices; PathVertex: what scattering at a vertex asks the
    // ray tracer for.
    struct PathState;
    struct PathVertex;
    // Shades s.hit: adds its emission, prepares next-event estimation and samples the next
    // direction (out says which rays to trace). Rays for lights at infinity are traced here.
    void scatterPathVertex(PathState& s, const Sampler& sampler, PathVertex& out, RayCounts& rays) const;
    // Adds what an emitter at s.hit sends back along the path, MIS-weighted.
    void addEmission(PathState& s) const;
    // Whether primaryPacket shades a vertex with this material with the SIMD lanes
    // (tracer/path_simd.h): the non-delta lobes of a smooth material, lights sampled by area.
    bool simdVertex(const ShadingMaterial& m) const {
        return simd_ && m.kind == MaterialKind::Diffuse && m.model != BsdfModel::Blend && (m.diffuse || m.glossy);
    }
    // scatterPathVertex for lane k of the SIMD lanes: their light sample and, Lambert lanes, their
    // bounce; the other materials' BSDF, bounce and roulette are scalar, on the lanes' numbers.
    void finishSimdLane(PathState& s, const Sampler& sampler, const pathsimd::Lanes& lanes, int k, PathVertex& out,
                        RayCounts& rays) const;
    // Adds the vertex's next-event estimate; visible: its shadow segment was clear.
    RayCone nextCone(const PathState& s) const;
    // envVisible: the lanes' environment sample (PathVertex::envShadow) escaped.
    void addNextEvent(PathState& s, const PathVertex& v, bool visible, bool envVisible) const;
    // Ends a path whose next ray left the scene: what the environment sends back along it.
    void endPath(PathState& s, const PathVertex& v) const;
    // One point or area light from the power CDF, MIS-weighted against BSDF sampling, before its
    // shadow ray: false if it adds nothing whatever the visibility; else what it adds when the
    // segment is clear.
    bool prepareNextEventFinite(const SurfaceHit& hit, const Sampler& sampler, int depth, float diffusePick,
                                glm::vec3& contribution, ShadowSegment& segment) const;
    // Every directional light and one environment-map sample (a constant environment is left to
    // BSDF sampling; environment false: the SIMD lanes took that sample), their shadow rays traced here.
    glm::vec3 nextEventInfinite(const SurfaceHit& hit, const Sampler& sampler, int depth, float diffusePick,
                                RayCounts& rays, bool environment = true) const;
    // What a BSDF-sampled ray that left the scene brings back, MIS-weighted against the
    // environment's light samples (pdfBefore: the BSDF sample's solid-angle pdf).
    glm::vec3 escapedPath(const glm::vec3& dir, bool specularBefore, float pdfBefore) const;

    // The SIMD lanes run where every light is an area light sampled by area.
    bool simd_ = false;
    pathsimd::LightTable simdLights_;
};

}  // namespace aamap
