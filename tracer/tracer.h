#pragma once
// The high-fidelity renderer: Embree BVH, TBB tiles, deterministic per-(pixel, sample, seed)
// random numbers. Integration-facing API; no Vulkan here.
// This header is the public entry: the Tracer class. The types its API takes and returns
// (TraceSettings, ShadingSettings, TraceResult, RayCounts, ...) live in tracer/tracer_types.h,
// which the tracer's internal headers include instead of this one.
#include <memory>

#include "core/pixel_facts.h"
#include "scene/scene.h"
#include "tracer/strategy.h"
#include "tracer/tracer_types.h"

namespace aamap {

class Tracer {
public:
    explicit Tracer(const Scene& scene);  // builds the BVH
    ~Tracer();
    Tracer(const Tracer&) = delete;
    Tracer& operator=(const Tracer&) = delete;

    double bvhBuildSeconds() const;
    TraceResult render(const View& view, const TraceSettings& settings, const StrategySettings& strategy) const;
    // What each pixel's sub-rays see (core/pixel_facts.h), for explaining the map's misses.
    // threads 0: all hardware threads; the result does not depend on it.
    PixelFacts pixelFacts(const View& view, int width, int height, int threads = 0) const;

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

}  // namespace aamap
