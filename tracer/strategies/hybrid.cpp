#include "tracer/strategies/hybrid.h"

#include <algorithm>
#include <limits>
#include <vector>

#include <fmt/format.h>

#include "tracer/strategies/strategies.h"
#include "tracer/strategies/variance.h"

namespace aamap {

int hybridStartSamples(float a, int n, int k) {
    if (a == 0.0f || n == 1) return 1;  // NaN is flagged: unsure means look
    return std::min(std::max(k * k, 2), n * n);
}

bool hybridConverged(const glm::dvec3& meanAll, const glm::dvec3& meanHalf, int taken, int n, double threshold) {
    if (taken >= n * n) return true;
    if (taken < 2) return false;
    return varianceError(meanAll, meanHalf) < threshold;
}

namespace {

class HybridStrategy final : public SamplingStrategy {
public:
    HybridStrategy(int n, StrataMapping mapping, double threshold, int step, const ImageGrey& map)
        : n_(n), mapping_(mapping), threshold_(threshold), step_(step), map_(map), order_(varianceOrder(n)) {}
    int maxRaysPerPixel() const override { return n_ * n_; }
    std::string describe() const override {
        return fmt::format("hybrid n={} mapping={} noise-threshold={} sample-step={}", n_, toString(mapping_),
                           threshold_, step_);
    }

    void render(const SampleSource& source, const Scheduler& scheduler, StrategyImages& out) const override {
        scheduler.tiles([&](int x0, int y0, int x1, int y1) {
            for (int y = y0; y < y1; ++y)
                for (int x = x0; x < x1; ++x) {
                    const float a = map_.at(x, y);
                    const int start = hybridStartSamples(a, n_, stratification(a, n_, mapping_));
                    out.traced.at(x, y) = 1;
                    if (start == 1) {  // unflagged: one ray, as uniform n = 1
                        out.image.at(x, y) = source.pixel(x, y, 1);
                        out.primaryRays.at(x, y) = 1;
                        continue;
                    }
                    renderFlagged(source, x, y, start, out);
                }
        });
    }

private:
    void renderFlagged(const SampleSource& source, int x, int y, int start, StrategyImages& out) const {
        const int N = n_ * n_;
        glm::dvec3 all(0.0), half(0.0);
        int taken = 0, kept = 0, keptHalf = 0;
        auto take = [&](int count) {
            for (int c = 0; c < count && taken < N; ++c, ++taken) {
                const int q = order_[static_cast<std::size_t>(taken)];
                const PrimarySample s = source.sample(x, y, q % n_, q / n_, n_, false);
                if (!s.finite) continue;
                all += glm::dvec3(s.radiance);
                ++kept;
                if (taken % 2 == 1) {
                    half += glm::dvec3(s.radiance);
                    ++keptHalf;
                }
            }
        };
        take(start);
        for (;;) {
            const bool known = kept > 0 && keptHalf > 0;
            if (taken >= N) break;
            if (known && hybridConverged(all / static_cast<double>(kept), half / static_cast<double>(keptHalf), taken,
                                         n_, threshold_))
                break;
            take(step_);
        }
        out.image.at(x, y) = kept > 0 ? glm::vec3(all / static_cast<double>(kept)) : glm::vec3(0.0f);
        out.primaryRays.at(x, y) = static_cast<std::uint16_t>(taken);
    }

    int n_;
    StrataMapping mapping_;
    double threshold_;
    int step_;
    const ImageGrey& map_;
    std::vector<int> order_;
};

}  // namespace

StrategyDescriptor hybridStrategy() {
    StrategyDescriptor d;
    d.name = "hybrid";
    d.doc = "the aamap says where to look (1 ray elsewhere), sample contrast where to stop (beyond the paper)";
    d.params = {mappingParam(),
                realParam("noise_threshold", 0, std::numeric_limits<double>::infinity(), 0.01,
                          "flagged pixels stop adding samples once their error is below it"),
                intParam("sample_step", 1, 1024, 4, "samples added per round to a flagged pixel")};
    d.usesAamap = true;
    d.create = [](const StrategyParams& p, const StrategyInputs& in) {
        return std::make_unique<HybridStrategy>(in.strata, mappingOf(p), p.real("noise_threshold"),
                                                p.integer("sample_step"), *in.aamap);
    };
    return d;
}

}  // namespace aamap
