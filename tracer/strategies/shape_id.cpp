#include "tracer/strategies/shape_id.h"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "tracer/strategies/strategies.h"

namespace aamap {

bool shapesDiffer(const std::vector<std::uint32_t>& shapes) {
    return std::any_of(shapes.begin(), shapes.end(), [&](std::uint32_t s) { return s != shapes.front(); });
}

int shapeIdMinStrata(int minSamples, int n) {
    int m = static_cast<int>(std::sqrt(static_cast<double>(std::max(1, minSamples))));
    while ((m + 1) * (m + 1) <= minSamples) ++m;  // exact floor despite sqrt rounding
    while (m * m > minSamples) --m;
    return std::clamp(m, 1, n);
}

namespace {

class ShapeIdStrategy final : public SamplingStrategy {
public:
    ShapeIdStrategy(int n, int minSamples) : n_(n), m_(shapeIdMinStrata(minSamples, n)) {}
    int maxRaysPerPixel() const override { return m_ < n_ ? m_ * m_ + n_ * n_ : n_ * n_; }
    std::string describe() const override { return fmt::format("shape-id n={} min-samples={}", n_, m_ * m_); }

    void render(const SampleSource& source, const Scheduler& scheduler, StrategyImages& out) const override {
        scheduler.tiles([&](int x0, int y0, int x1, int y1) {
            std::vector<std::uint32_t> shapes;
            for (int y = y0; y < y1; ++y)
                for (int x = x0; x < x1; ++x) {
                    out.traced.at(x, y) = 1;
                    if (m_ >= n_) {  // the first samples are already the most there can be
                        out.image.at(x, y) = source.pixel(x, y, n_);
                        out.primaryRays.at(x, y) = static_cast<std::uint16_t>(n_ * n_);
                        continue;
                    }
                    shapes.clear();
                    glm::dvec3 sum(0.0);
                    int kept = 0;
                    for (int sy = 0; sy < m_; ++sy)
                        for (int sx = 0; sx < m_; ++sx) {
                            const PrimarySample s = source.sample(x, y, sx, sy, m_, true);
                            shapes.push_back(s.shape);
                            if (!s.finite) continue;
                            sum += glm::dvec3(s.radiance);
                            ++kept;
                        }
                    if (shapesDiffer(shapes)) {
                        out.image.at(x, y) = source.pixel(x, y, n_);
                        out.primaryRays.at(x, y) = static_cast<std::uint16_t>(m_ * m_ + n_ * n_);
                    } else {
                        out.image.at(x, y) = kept > 0 ? glm::vec3(sum / static_cast<double>(kept)) : glm::vec3(0.0f);
                        out.primaryRays.at(x, y) = static_cast<std::uint16_t>(m_ * m_);
                    }
                }
        });
    }

private:
    int n_, m_;
};

}  // namespace

StrategyDescriptor shapeIdStrategy() {
    StrategyDescriptor d;
    d.name = "shape-id";
    d.doc = "n x n more samples where the first ones hit different shapes (pbrt-v2)";
    d.params = {intParam("min_samples", 1, 1024, 4, "first samples per pixel (rounded down to a square)")};
    d.create = [](const StrategyParams& p, const StrategyInputs& in) {
        return std::make_unique<ShapeIdStrategy>(in.strata, p.integer("min_samples"));
    };
    return d;
}

}  // namespace aamap
