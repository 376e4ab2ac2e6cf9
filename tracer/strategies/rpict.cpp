#include "tracer/strategies/rpict.h"

#include <cmath>
#include <limits>
#include <vector>

#include <fmt/format.h>

#include "tracer/strategies/strategies.h"
#include "tracer/strategies/subsample.h"

namespace aamap {
namespace {

bool bigDiff(double a, double b, double t) {
    if (std::isnan(a) || std::isnan(b)) return true;
    if (a == b) return false;  // equal infinities too
    return a - b > t * b || b - a > t * a;
}

}  // namespace

bool rpictDiffers(const glm::vec3& a, float depthA, const glm::vec3& b, float depthB, double t) {
    for (int c = 0; c < 3; ++c)
        if (bigDiff(a[c], b[c], t)) return true;
    return bigDiff(depthA, depthB, t);
}

namespace {

class RpictStrategy final : public SamplingStrategy {
public:
    RpictStrategy(int spacing, double threshold) : spacing_(spacing), threshold_(threshold) {}
    int maxRaysPerPixel() const override { return 1; }
    std::string describe() const override {
        return fmt::format("rpict spacing={} threshold={}", spacing_, threshold_);
    }

    void render(const SampleSource& source, const Scheduler& scheduler, StrategyImages& out) const override {
        const int W = source.width(), H = source.height();
        std::vector<float> depth(static_cast<std::size_t>(W) * H, 0.0f);
        const Ctx ctx{source, out, depth, W, threshold_};
        const std::vector<int> xs = gridLines(W, spacing_), ys = gridLines(H, spacing_);
        std::vector<std::uint8_t> gridColumn(static_cast<std::size_t>(W), 0);
        for (int x : xs) gridColumn[static_cast<std::size_t>(x)] = 1;
        std::vector<std::uint8_t> gridRow(static_cast<std::size_t>(H), 0);
        for (int y : ys) gridRow[static_cast<std::size_t>(y)] = 1;

        scheduler.tiles([&](int x0, int y0, int x1, int y1) {  // phase 1: the grid
            for (int y = y0; y < y1; ++y)
                for (int x = x0; x < x1; ++x)
                    if (gridRow[static_cast<std::size_t>(y)] && gridColumn[static_cast<std::size_t>(x)]) ctx.trace(x, y);
        });
        // Phase 2: along the traced rows. Phase 3: along every column, between traced rows.
        scheduler.range(static_cast<int>(ys.size()), [&](int j) {
            for (std::size_t i = 0; i + 1 < xs.size(); ++i) ctx.fill(xs[i], ys[j], xs[i + 1], ys[j], 1, 0);
        });
        scheduler.range(W, [&](int x) {
            for (std::size_t j = 0; j + 1 < ys.size(); ++j) ctx.fill(x, ys[j], x, ys[j + 1], 0, 1);
        });
    }

private:
    struct Ctx {
        const SampleSource& source;
        StrategyImages& out;
        std::vector<float>& depth;
        int width;
        double t;

        float& z(int x, int y) const { return depth[static_cast<std::size_t>(y) * width + x]; }

        void trace(int x, int y) const {
            const PrimarySample s = source.sample(x, y, 0, 0, 1, true);
            out.image.at(x, y) = s.finite ? s.radiance : glm::vec3(0.0f);
            z(x, y) = s.depth;
            out.primaryRays.at(x, y) = 1;
            out.traced.at(x, y) = 1;
        }

        // Pixels strictly between (ax, ay) and (bx, by), a step (dx, dy) apart; both ends known.
        void fill(int ax, int ay, int bx, int by, int dx, int dy) const {
            const int len = (bx - ax) * dx + (by - ay) * dy;
            if (len <= 1) return;
            const glm::vec3 ca = out.image.at(ax, ay), cb = out.image.at(bx, by);
            const float za = z(ax, ay), zb = z(bx, by);
            if (rpictDiffers(ca, za, cb, zb, t)) {
                const int mx = ax + dx * (len / 2), my = ay + dy * (len / 2);
                trace(mx, my);
                fill(ax, ay, mx, my, dx, dy);
                fill(mx, my, bx, by, dx, dy);
                return;
            }
            for (int i = 1; i < len; ++i) {
                const float w = static_cast<float>(i) / static_cast<float>(len);
                const int x = ax + dx * i, y = ay + dy * i;
                out.image.at(x, y) = (1.0f - w) * ca + w * cb;
                z(x, y) = za == zb ? za : (1.0f - w) * za + w * zb;  // inf * 0 would be NaN
            }
        }
    };

    int spacing_;
    double threshold_;
};

}  // namespace

StrategyDescriptor rpictStrategy() {
    StrategyDescriptor d;
    d.name = "rpict";
    d.doc = "Radiance rpict-style adaptive subsampling by image contrast, one ray per pixel at most (no aamap)";
    d.params = {intParam("spacing", 1, 64, 4, "-ps: initial sample spacing in pixels"),
                realParam("threshold", 0, std::numeric_limits<double>::infinity(), 0.05,
                          "-pt: relative colour/depth difference that forces a split")};
    d.marksTraced = true;
    d.create = [](const StrategyParams& p, const StrategyInputs&) {
        return std::make_unique<RpictStrategy>(p.integer("spacing"), p.real("threshold"));
    };
    return d;
}

}  // namespace aamap
