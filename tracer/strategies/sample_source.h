#pragma once
// What a sampling strategy renders with: a SampleSource that traces one stratum of one pixel, and
// a Scheduler that runs a phase in parallel. Strategies decide only from completed phases and every
// sample is a pure function of (pixel, k, stratum, seed), so images are bit-identical for any
// thread count. The tracer implements SampleSource with Embree; tests implement it with a
// synthetic radiance function.
#include <atomic>
#include <cstdint>
#include <functional>
#include <limits>

#include <glm/vec3.hpp>
#include <glm/ext/vector_double3.hpp>

#include "core/image.h"

namespace aamap {

constexpr std::uint32_t kNoShape = 0xffffffffu;  // a miss

struct PrimarySample {
    glm::vec3 radiance{0.0f};
    bool finite = true;  // false: radiance is NaN/Inf; the source counted it, the strategy drops it
    // Only filled when asked for (withHit): distance to the first hit along the unit ray (+inf on a
    // miss) and the shape (object) hit, for the depth and shape-id criteria.
    float depth = std::numeric_limits<float>::infinity();
    std::uint32_t shape = kNoShape;
};

class SampleSource {
public:
    virtual ~SampleSource() = default;
    virtual int width() const = 0;
    virtual int height() const = 0;
    // Stratum (sx, sy) of a k x k jittered grid over pixel (x, y), sample index sy * k + sx.
    // Thread-safe; counts the rays it traces. withHit may cost one extra probe ray.
    virtual PrimarySample sample(int x, int y, int sx, int sy, int k, bool withHit) const = 0;
    // Mean over all k x k strata, non-finite samples dropped (black if none is finite). Sources
    // override it for speed; the result must equal this default's.
    virtual glm::vec3 pixel(int x, int y, int k) const;
    // pixel(x, y, k), plus the mean of the strata with (sx + sy) even minus the mean of those with
    // it odd: two independent half estimates of the pixel, whose difference measures how far the
    // whole estimate is from converged (noise and antialiasing left). k >= 2. Sources override it
    // for speed; mean must equal pixel()'s bit for bit.
    struct Halves {
        glm::vec3 mean{0.0f}, difference{0.0f};
    };
    virtual Halves pixelHalves(int x, int y, int k) const;
    // out[i] = sample(x, y, strata[i] % k, strata[i] / k, k, false) for i < count, in that
    // order: a batch of strata of one pixel. Sources override it for speed (the tracer traces the
    // batch as packets); the result must equal this default's.
    virtual void samples(int x, int y, const int* strata, int count, int k, PrimarySample* out) const;
};

// Halves from the sums pixelHalves() gathers: the whole mean as pixel() forms it, and the
// difference of the two halves' means (0 when either half has no finite sample).
inline SampleSource::Halves halvesOf(const glm::dvec3& sum, int kept, const glm::dvec3 half[2], const int halfKept[2]) {
    SampleSource::Halves h;
    if (kept > 0) h.mean = glm::vec3(sum / static_cast<double>(kept));
    if (halfKept[0] > 0 && halfKept[1] > 0)
        h.difference = glm::vec3(half[0] / static_cast<double>(halfKept[0]) - half[1] / static_cast<double>(halfKept[1]));
    return h;
}

// Runs the phases of a strategy. Progress (tilesDone, tilesTotal) is reported per tile of the
// tiles() phases; tilesTotal = tile count x expectedTilePhases (what the strategy announced).
class Scheduler {
public:
    using Progress = std::function<void(int tilesDone, int tilesTotal)>;
    static constexpr int kTileSize = 16;

    Scheduler(int width, int height, Progress progress = {});
    int tileCount() const { return tilesX_ * tilesY_; }
    void expectTilePhases(int phases) { tilesTotal_ = tileCount() * phases; }
    // Called on the worker thread right after each tile of a tiles() phase, with its rectangle
    // (half-open): live previews read the tile's finished pixels there. It may throw to cancel.
    using TileFinished = std::function<void(int x0, int y0, int x1, int y1)>;
    void onTileFinished(TileFinished fn) { tileFinished_ = std::move(fn); }

    // fn(x0, y0, x1, y1) for every 16 x 16 tile (half-open), in parallel, grain one tile.
    void tiles(const std::function<void(int, int, int, int)>& fn) const;
    // fn(i) for i in [0, n), in parallel.
    void range(int n, const std::function<void(int)>& fn) const;

private:
    int width_, height_, tilesX_, tilesY_;
    int tilesTotal_;
    Progress progress_;
    TileFinished tileFinished_;
    mutable std::atomic<int> tilesDone_{0};
};

// What every strategy writes; allocated (black, zero rays, nothing traced) by the caller.
struct StrategyImages {
    ImageRGB image;
    Image<std::uint16_t> primaryRays;
    Image<std::uint8_t> traced;
    // Strategies that render every pixel with one k x k grid fill it with pixelHalves()'s
    // difference when the caller allocated it (TraceResult::halfDifference); else left empty.
    ImageRGB halfDifference;
    StrategyImages(int w, int h) : image(w, h, glm::vec3(0.0f)), primaryRays(w, h, 0), traced(w, h, 0) {}
};

}  // namespace aamap
