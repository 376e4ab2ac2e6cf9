#pragma once
// Sampling strategies: which pixels get how many primary rays, and how untraced pixels are filled.
// A strategy drives rendering through a SampleSource (trace stratum (sx, sy) of a k x k grid over
// pixel p) and a Scheduler (parallel phases); multi-pass strategies trace, look at the completed
// phase, then trace more. One interface for all; each strategy's own file in tracer/strategies/
// declares it (StrategyDescriptor: name, doc line, parameters, needs, factory), and
// strategyRegistry() lists them (docs/tracer.md, "Sampling strategies", has each one's rule).
#include <deque>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "core/image.h"
#include "tracer/strategies/sample_source.h"
#include "tracer/strategy_params.h"

namespace aamap {

class BlockSums;  // tracer/block_sums.h

// The baseline of speedups (the registry's first, "uniform"): one name for every comparison.
const std::string& baselineStrategyName();

// Which sampling strategy a render uses, by name (strategyRegistry()), with its parameters
// (checked against the strategy's schema; missing ones take their defaults).
struct StrategySettings {
    std::string name = baselineStrategyName();
    int strata = 1;  // n: at most n x n rays per pixel (per sub-pixel for supersample)
    StrategyParams params;
    // Strategies that use the aamap: pixel p's map value. Must match the render resolution. Not owned.
    const ImageGrey* aamap = nullptr;
    // Strategies that need block sums: those of `aamap` computed elsewhere (the Snapshot's GPU
    // pass); null: the strategy builds them on the CPU. Must be of the same map. Not owned.
    const BlockSums* blockSums = nullptr;
    // The display exposure (image.exposure): strategies that judge image differences as the PNGs
    // and the error metrics show them (exposure, clamp, sRGB). Finite and > 0.
    float exposure = 1.0f;
};

class SamplingStrategy {
public:
    virtual ~SamplingStrategy() = default;

    // Bound on primaryRays per pixel (validated to fit 16 bits).
    virtual int maxRaysPerPixel() const = 0;
    // How many Scheduler::tiles() phases render() runs (at most), for progress reports.
    virtual int tilePhases() const { return 1; }
    // One line: the name and the resolved parameters (recorded in TraceResult::strategy).
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

// What a strategy is built from besides its parameters, checked by makeStrategy first.
struct StrategyInputs {
    int width = 0, height = 0;  // the render's size
    int strata = 1;             // n, in [1, kMaxStrata]
    const ImageGrey* aamap = nullptr;      // usesAamap: present, of the render's size (not owned)
    const BlockSums* blockSums = nullptr;  // needsBlockSums: null or of the render's size (not owned)
    float exposure = 1.0f;                 // StrategySettings::exposure, checked
};

// One sampling strategy, as the config, the runner, the viewer and the documentation see it.
struct StrategyDescriptor {
    std::string name;  // renders[].strategy, StrategySettings::name
    std::string doc;   // one line
    std::vector<ParamSpec> params;  // in documentation order
    bool usesAamap = false;       // reads StrategyInputs::aamap (the Snapshot, so the GPU unless cached)
    bool needsBlockSums = false;  // plans from the map's block sums: the Snapshot's GPU pass builds them
    bool marksTraced = false;     // may leave pixels untraced (interpolated): the traced mask is an output
    // One k x k grid in every pixel: it also returns two independent half images' difference
    // (TraceResult::halfDifference), from which a reference's own convergence is estimated.
    bool splitsHalves = false;
    // params: resolved (every parameter present, typed, in range). May keep pointers to inputs.
    std::function<std::unique_ptr<SamplingStrategy>(const StrategyParams& params, const StrategyInputs& inputs)> create;

    const ParamSpec* param(const std::string& key) const;  // null when it has no such parameter
};

// Every strategy, in documentation order; the first ("uniform") is the baseline of speedups.
const std::deque<StrategyDescriptor>& strategyRegistry();
const StrategyDescriptor* findStrategy(const std::string& name);  // null for an unknown name
std::vector<std::string> strategyNames();
// Adds (or replaces) a strategy at run time: for tests and for custom RenderBackends. Not
// thread-safe; call before parsing configs.
void registerStrategy(StrategyDescriptor descriptor);
void unregisterStrategy(const std::string& name);  // tests: invalidates pointers into the registry

// `given` checked against the schema (throws std::invalid_argument naming the strategy and the
// parameter): every parameter of `strategy` in schema order, typed, defaults for the missing ones.
StrategyParams resolveParams(const StrategyDescriptor& strategy, const StrategyParams& given);

// Validates the settings against the render size (throws std::invalid_argument) and builds the
// strategy. The returned object may keep a pointer to settings.aamap and settings.blockSums.
std::unique_ptr<SamplingStrategy> makeStrategy(const StrategySettings& settings, int width, int height);

// Map value a in [0,1] -> strata per axis k in [1, n]. Paper: k = 1 + round(a (n - 1)) (paper section 4).
// LinearRays: k = round(sqrt(1 + a (n^2 - 1))), rays per pixel linear in a. Names "paper", "linear-rays".
enum class StrataMapping { Paper, LinearRays };
const char* toString(StrataMapping mapping);
bool parse(const std::string& name, StrataMapping& mapping);
// The `mapping` parameter the aamap-driven strategies share, and its value in resolved params.
ParamSpec mappingParam();
StrataMapping mappingOf(const StrategyParams& params);

// Paper mapping: k = 1 + round(a * (n - 1)) clamped to [1, n]; NaN counts as 1 (sample fully when unsure).
int aamapStratification(float a, int n);
// k for map value a under `mapping` (same clamping and NaN rule).
int stratification(float a, int n, StrataMapping mapping);

// The largest n a pixel can take: k^2 rays must fit TraceResult::primaryRays (16 bits).
constexpr int kMaxStrata = 255;

}  // namespace aamap
