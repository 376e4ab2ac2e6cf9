#pragma once
// The high-fidelity renderer: Embree BVH, TBB tiles, deterministic per-(pixel, sample, seed)
// random numbers. Integration-facing API; no Vulkan here.
#include <cstdint>
#include <functional>
#include <memory>
#include <string>

#include "core/image.h"
#include "scene/scene.h"

namespace aamap {

struct ShadingSettings {
    int areaLightSamples = 16;  // stratified shadow-ray samples per area light per hit (rounded to a square)
};

struct RayCounts {
    std::uint64_t primary = 0;
    std::uint64_t shadow = 0;
    std::uint64_t other = 0;
    std::uint64_t total() const { return primary + shadow + other; }
};

enum class StrategyKind { Uniform, Aamap };
const char* toString(StrategyKind kind);

struct StrategySettings {
    StrategyKind kind = StrategyKind::Uniform;
    int strata = 1;  // n: at most n x n rays per pixel
    // Aamap only: pixel p gets k x k rays, k = 1 + round(aamap(p) * (n - 1)). Must match the
    // render resolution. Not owned.
    const ImageGrey* aamap = nullptr;
};

struct TraceSettings {
    int width = 512, height = 512;
    std::uint64_t seed = 1;
    int threads = 0;  // 0: all hardware threads
    ShadingSettings shading;
    // Called from worker threads as tiles finish (for progress bars); may be empty.
    std::function<void(int tilesDone, int tilesTotal)> onTileDone;
};

struct TraceResult {
    ImageRGB image;                    // linear radiance, finite everywhere
    Image<std::uint16_t> primaryRays;  // primary rays traced per pixel
    RayCounts rays;
    std::uint64_t nonFiniteSamples = 0;  // NaN/Inf samples dropped (counted, never written)
    double seconds = 0.0;
};

class Tracer {
public:
    explicit Tracer(const Scene& scene);  // builds the BVH
    ~Tracer();
    Tracer(const Tracer&) = delete;
    Tracer& operator=(const Tracer&) = delete;

    double bvhBuildSeconds() const;
    TraceResult render(const View& view, const TraceSettings& settings, const StrategySettings& strategy) const;

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

}  // namespace aamap
