#pragma once
// Sampling strategies: which pixels get how many primary rays, and how untraced pixels are filled.
// A strategy drives rendering through a SampleSource (trace stratum (sx, sy) of a k x k grid over
// pixel p) and a Scheduler (parallel phases); multi-pass strategies trace, look at the completed
// phase, then trace more. One interface for all (StrategyKind in tracer.h):
// - uniform: n x n strata everywhere (the full solution of the paper).
// - aamap: k(p) x k(p) strata, k from the map value (StrataMapping; paper section 4).
// - aamap-subsample: the paper's adaptive subsampling on a grid of spacing s, with per-pixel
//   modulation on the traced pixels ("Space 8", "Space 16"); strategies/subsample.h.
// - rpict: Radiance's -ps/-pt adaptive undersampling, one ray per pixel at most; strategies/rpict.h.
// - supersample: f x f sub-pixels of n x n strata, then a pfilt-like box/Gaussian filter.
// - variance: Cycles-style two half-buffer error estimate and stop rule; strategies/variance.h.
// - shape-id: pbrt-v2 AdaptiveSampler, shape-id method; strategies/shape_id.h.
// - hybrid: the aamap picks the pixels that get more than one ray, each pixel's sample contrast
//   (Cycles' half-buffer error) decides when it stops; strategies/hybrid.h.
#include <memory>
#include <string>

#include "core/image.h"
#include "tracer/strategies/sample_source.h"
#include "tracer/tracer.h"

namespace aamap {

class SamplingStrategy {
public:
    virtual ~SamplingStrategy() = default;

    virtual StrategyKind kind() const = 0;
    // Bound on primaryRays per pixel (validated to fit 16 bits).
    virtual int maxRaysPerPixel() const = 0;
    // How many Scheduler::tiles() phases render() runs (at most), for progress reports.
    virtual int tilePhases() const { return 1; }
    // One line: the kind and the resolved parameters (recorded in TraceResult::strategy).
    virtual std::string describe() const = 0;
    // Writes every pixel of out.image, plus out.primaryRays (rays traced at each pixel) and
    // out.traced. Call inside the task arena that should run it.
    virtual void render(const SampleSource& source, const Scheduler& scheduler, StrategyImages& out) const = 0;
};

// Strategies that fix every pixel's stratification up front (uniform, aamap): one tile phase.
class PerPixelStrategy : public SamplingStrategy {
public:
    // k for pixel (x, y): k x k jittered primary rays, k >= 1. Called concurrently: thread-safe.
    virtual int stratificationFor(int x, int y) const = 0;
    void render(const SampleSource& source, const Scheduler& scheduler, StrategyImages& out) const override;
};

// Validates the settings against the render size (throws std::invalid_argument) and builds the
// strategy. The returned object may keep a pointer to settings.aamap.
std::unique_ptr<SamplingStrategy> makeStrategy(const StrategySettings& settings, int width, int height);

// Paper mapping: k = 1 + round(a * (n - 1)) clamped to [1, n]; NaN counts as 1 (sample fully when unsure).
int aamapStratification(float a, int n);
// k for map value a under `mapping` (same clamping and NaN rule).
int stratification(float a, int n, StrataMapping mapping);

// The largest n a pixel can take: k^2 rays must fit TraceResult::primaryRays (16 bits).
constexpr int kMaxStrata = 255;

}  // namespace aamap
