#include "tracer/strategies/variance.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <vector>

#include <fmt/format.h>

#include "tracer/sampler.h"
#include "tracer/strategies/strategies.h"

namespace aamap {

double varianceError(const glm::dvec3& all, const glm::dvec3& half) {
    const double difference = std::abs(all.x - half.x) + std::abs(all.y - half.y) + std::abs(all.z - half.z);
    const double normalise = std::sqrt(std::max(0.0, all.x + all.y + all.z));
    return difference / (1e-4 + normalise);  // Cycles' epsilon: black pixels converge
}

std::vector<int> varianceOrder(int n) {
    std::vector<int> order(static_cast<std::size_t>(n) * n);
    std::iota(order.begin(), order.end(), 0);
    // Fisher-Yates driven by the counter-based hash: the same order on every run and machine.
    for (std::size_t i = order.size(); i > 1; --i) {
        const std::uint64_t j = mix64(0x5eed0000ull + i) % i;
        std::swap(order[i - 1], order[j]);
    }
    return order;
}

Image<std::uint8_t> dilate3x3(const Image<std::uint8_t>& active) {
    const int W = active.width(), H = active.height();
    Image<std::uint8_t> rows(W, H, 0), out(W, H, 0);
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x)
            rows.at(x, y) = active.at(x, y) || (x > 0 && active.at(x - 1, y)) || (x + 1 < W && active.at(x + 1, y));
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x)
            out.at(x, y) = rows.at(x, y) || (y > 0 && rows.at(x, y - 1)) || (y + 1 < H && rows.at(x, y + 1));
    return out;
}

namespace {

struct PixelState {
    glm::dvec3 all{0.0}, half{0.0};  // sums of the finite samples; half: odd sample positions
    int taken = 0, kept = 0, keptHalf = 0;
};

class VarianceStrategy final : public SamplingStrategy {
public:
    VarianceStrategy(int n, double threshold, int minSamples, int step)
        : n_(n), threshold_(threshold), min_(std::min(std::max(minSamples, 2), n * n)), step_(step),
          order_(varianceOrder(n)) {}
    int maxRaysPerPixel() const override { return n_ * n_; }
    int tilePhases() const override { return 1 + (n_ * n_ - min_ + step_ - 1) / step_; }
    std::string describe() const override {
        return fmt::format("variance n={} noise-threshold={} min-samples={} sample-step={}", n_, threshold_, min_,
                           step_);
    }

    void render(const SampleSource& source, const Scheduler& scheduler, StrategyImages& out) const override {
        const int W = source.width(), H = source.height(), N = n_ * n_;
        std::vector<PixelState> state(static_cast<std::size_t>(W) * H);
        auto at = [&](int x, int y) -> PixelState& { return state[static_cast<std::size_t>(y) * W + x]; };
        Image<std::uint8_t> active(W, H, 1);
        int budget = min_;  // samples this round
        for (;;) {
            scheduler.tiles([&](int x0, int y0, int x1, int y1) {
                for (int y = y0; y < y1; ++y)
                    for (int x = x0; x < x1; ++x)
                        if (active.at(x, y)) take(source, x, y, at(x, y), std::min(budget, N - at(x, y).taken));
            });
            // Decide from the completed round only.
            Image<std::uint8_t> unconverged(W, H, 0);
            scheduler.range(H, [&](int y) {
                for (int x = 0; x < W; ++x) unconverged.at(x, y) = !converged(at(x, y), N);
            });
            active = dilate3x3(unconverged);
            bool any = false;
            for (int y = 0; y < H; ++y)
                for (int x = 0; x < W; ++x) {
                    active.at(x, y) = active.at(x, y) && at(x, y).taken < N;
                    any = any || active.at(x, y);
                }
            if (!any) break;
            budget = step_;
        }
        for (int y = 0; y < H; ++y)
            for (int x = 0; x < W; ++x) {
                const PixelState& p = at(x, y);
                out.image.at(x, y) = p.kept > 0 ? glm::vec3(p.all / static_cast<double>(p.kept)) : glm::vec3(0.0f);
                out.primaryRays.at(x, y) = static_cast<std::uint16_t>(p.taken);
                out.traced.at(x, y) = 1;
            }
    }

private:
    // The next `count` samples of the pixel in order_, in batches the source can trace together.
    void take(const SampleSource& source, int x, int y, PixelState& p, int count) const {
        constexpr int kBatch = 64;
        PrimarySample batch[kBatch];
        for (int from = 0; from < count; from += kBatch) {
            const int n = std::min(kBatch, count - from);
            source.samples(x, y, order_.data() + p.taken, n, n_, batch);
            for (int c = 0; c < n; ++c, ++p.taken) {
                const PrimarySample& s = batch[c];
                if (!s.finite) continue;
                p.all += glm::dvec3(s.radiance);
                ++p.kept;
                if (p.taken % 2 == 1) {
                    p.half += glm::dvec3(s.radiance);
                    ++p.keptHalf;
                }
            }
        }
    }

    bool converged(const PixelState& p, int N) const {
        if (p.taken >= N) return true;
        if (p.kept == 0 || p.keptHalf == 0) return false;
        return varianceError(p.all / static_cast<double>(p.kept), p.half / static_cast<double>(p.keptHalf)) <
               threshold_;
    }

    int n_;
    double threshold_;
    int min_, step_;
    std::vector<int> order_;
};

}  // namespace

StrategyDescriptor varianceStrategy() {
    StrategyDescriptor d;
    d.name = "variance";
    d.doc = "variance-driven adaptive sampling (Cycles)";
    d.params = {realParam("noise_threshold", 0, std::numeric_limits<double>::infinity(), 0.01,
                          "pixels whose error estimate is at least this get more samples"),
                intParam("min_samples", 1, 1024, 4,
                         "first round of samples per pixel (1 runs as 2: the error estimate needs two)"),
                intParam("sample_step", 1, 1024, 4, "samples added per round")};
    d.create = [](const StrategyParams& p, const StrategyInputs& in) {
        return std::make_unique<VarianceStrategy>(in.strata, p.real("noise_threshold"), p.integer("min_samples"),
                                                  p.integer("sample_step"));
    };
    return d;
}

}  // namespace aamap
