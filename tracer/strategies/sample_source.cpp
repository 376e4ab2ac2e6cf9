#include "tracer/strategies/sample_source.h"

#include <algorithm>

#include <glm/vec3.hpp>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

namespace aamap {

glm::vec3 SampleSource::pixel(int x, int y, int k) const { return pixelHalves(x, y, k).mean; }

SampleSource::Halves SampleSource::pixelHalves(int x, int y, int k) const {
    glm::dvec3 sum(0.0), half[2] = {glm::dvec3(0.0), glm::dvec3(0.0)};
    int kept = 0, halfKept[2] = {0, 0};
    for (int sy = 0; sy < k; ++sy)
        for (int sx = 0; sx < k; ++sx) {
            const PrimarySample s = sample(x, y, sx, sy, k, false);
            if (!s.finite) continue;
            sum += glm::dvec3(s.radiance);
            ++kept;
            half[(sx + sy) & 1] += glm::dvec3(s.radiance);
            ++halfKept[(sx + sy) & 1];
        }
    return halvesOf(sum, kept, half, halfKept);
}

void SampleSource::samples(int x, int y, const int* strata, int count, int k, PrimarySample* out) const {
    for (int i = 0; i < count; ++i) out[i] = sample(x, y, strata[i] % k, strata[i] / k, k, false);
}

Scheduler::Scheduler(int width, int height, Progress progress)
    : width_(width),
      height_(height),
      tilesX_((width + kTileSize - 1) / kTileSize),
      tilesY_((height + kTileSize - 1) / kTileSize),
      tilesTotal_(tilesX_ * tilesY_),
      progress_(std::move(progress)) {}

void Scheduler::tiles(const std::function<void(int, int, int, int)>& fn) const {
    const int count = tileCount();
    // Grain 1: tiles are already coarse, and cost varies a lot between them.
    tbb::parallel_for(tbb::blocked_range<int>(0, count, 1), [&](const tbb::blocked_range<int>& r) {
        for (int t = r.begin(); t != r.end(); ++t) {
            const int x0 = (t % tilesX_) * kTileSize, y0 = (t / tilesX_) * kTileSize;
            const int x1 = std::min(x0 + kTileSize, width_), y1 = std::min(y0 + kTileSize, height_);
            fn(x0, y0, x1, y1);
            if (tileFinished_) tileFinished_(x0, y0, x1, y1);
            const int done = tilesDone_.fetch_add(1, std::memory_order_relaxed) + 1;
            if (progress_) progress_(std::min(done, tilesTotal_), tilesTotal_);
        }
    });
}

void Scheduler::range(int n, const std::function<void(int)>& fn) const {
    tbb::parallel_for(tbb::blocked_range<int>(0, n, 1), [&](const tbb::blocked_range<int>& r) {
        for (int i = r.begin(); i != r.end(); ++i) fn(i);
    });
}

}  // namespace aamap
