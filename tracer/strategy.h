#pragma once
// Sampling strategies: which pixels get how many primary rays. The tracer asks a strategy for each
// pixel's stratification k (k x k jittered rays); k = 0 means "do not trace this pixel", and the
// strategy's fill() then supplies it after every traced pixel is final. That covers the strategies
// that decide up front from the aamap (uniform, aamap-modulated, aamap + adaptive subsampling with
// interpolation). Strategies that decide from traced values (rpict-style contrast, variance-driven)
// will add refinement passes on top of this interface.
#include <memory>

#include "core/image.h"
#include "tracer/tracer.h"

namespace aamap {

class SamplingStrategy {
public:
    virtual ~SamplingStrategy() = default;

    virtual StrategyKind kind() const = 0;
    // Largest k the strategy may return (bounds the ray count per pixel).
    virtual int maxStratification() const = 0;
    // k for pixel (x, y): k x k jittered primary rays, 0 = not traced (fill() provides it).
    // Called concurrently from worker threads: must be const and thread-safe.
    virtual int stratificationFor(int x, int y) const = 0;
    // Completes the image once every traced pixel holds its estimate: fills the pixels whose
    // primaryRays count is 0 (for example by interpolating between traced ones). Default: nothing.
    virtual void fill(ImageRGB& image, const Image<std::uint16_t>& primaryRays) const;
};

// Validates the settings against the render size (throws std::invalid_argument) and builds the
// strategy. The returned object may keep a pointer to settings.aamap.
std::unique_ptr<SamplingStrategy> makeStrategy(const StrategySettings& settings, int width, int height);

// k = 1 + round(a * (n - 1)) clamped to [1, n]; NaN counts as 1 (sample fully when unsure).
int aamapStratification(float a, int n);

// The largest n a pixel can take: k^2 rays must fit TraceResult::primaryRays (16 bits).
constexpr int kMaxStrata = 255;

}  // namespace aamap
