#include "tracer/strategies/subsample.h"

#include <limits>
#include <optional>

#include <fmt/format.h>

#include "tracer/strategies/strategies.h"

namespace aamap {

std::vector<int> gridLines(int size, int spacing) {
    std::vector<int> lines;
    for (int i = 0; i < size; i += spacing) lines.push_back(i);
    if (lines.back() != size - 1) lines.push_back(size - 1);
    return lines;
}

namespace {

struct Planner {
    const BlockSums& sums;
    double threshold;
    SubsamplePlan& plan;

    void refine(const Block& b) {
        plan.traced.at(b.x0, b.y0) = plan.traced.at(b.x1, b.y0) = 1;
        plan.traced.at(b.x0, b.y1) = plan.traced.at(b.x1, b.y1) = 1;
        if (b.x1 - b.x0 <= 1 && b.y1 - b.y0 <= 1) return;  // every pixel is a corner
        if (!(sums.sum(b.x0, b.y0, b.x1, b.y1) > threshold)) {
            plan.interpolated.push_back(b);
            return;
        }
        // Split into four (two where one side has no pixel between its corners).
        const int xm = (b.x0 + b.x1) / 2, ym = (b.y0 + b.y1) / 2;
        const bool splitX = b.x1 - b.x0 > 1, splitY = b.y1 - b.y0 > 1;
        const int xs[3] = {b.x0, splitX ? xm : b.x1, b.x1};
        const int ys[3] = {b.y0, splitY ? ym : b.y1, b.y1};
        for (int j = 0; j < (splitY ? 2 : 1); ++j)
            for (int i = 0; i < (splitX ? 2 : 1); ++i)
                refine({xs[i], ys[j], splitX ? xs[i + 1] : b.x1, splitY ? ys[j + 1] : b.y1});
    }
};

}  // namespace

SubsamplePlan planSubsampling(const BlockSums& sums, int spacing, double threshold) {
    SubsamplePlan plan{Image<std::uint8_t>(sums.width(), sums.height(), 0), {}};
    const std::vector<int> xs = gridLines(sums.width(), spacing);
    const std::vector<int> ys = gridLines(sums.height(), spacing);
    Planner planner{sums, threshold, plan};
    // One grid line (a 1-pixel-wide image) makes degenerate blocks x0 == x1.
    for (std::size_t j = 0; j < std::max<std::size_t>(1, ys.size() - 1); ++j)
        for (std::size_t i = 0; i < std::max<std::size_t>(1, xs.size() - 1); ++i)
            planner.refine({xs[i], ys[j], xs[std::min(i + 1, xs.size() - 1)], ys[std::min(j + 1, ys.size() - 1)]});
    return plan;
}

void interpolateBlock(ImageRGB& image, const Block& b) {
    const glm::vec3 c00 = image.at(b.x0, b.y0), c10 = image.at(b.x1, b.y0);
    const glm::vec3 c01 = image.at(b.x0, b.y1), c11 = image.at(b.x1, b.y1);
    for (int y = b.y0 + 1; y < b.y1; ++y) {
        const float v = static_cast<float>(y - b.y0) / static_cast<float>(b.y1 - b.y0);
        for (int x = b.x0 + 1; x < b.x1; ++x) {
            const float u = static_cast<float>(x - b.x0) / static_cast<float>(b.x1 - b.x0);
            image.at(x, y) = (1.0f - v) * ((1.0f - u) * c00 + u * c10) + v * ((1.0f - u) * c01 + u * c11);
        }
    }
}

namespace {
// Linear between consecutive traced pixels on a line; at(i) is the i-th pixel of the line.
template <class At, class IsTraced>
void interpolateLine(int from, int to, At at, IsTraced isTraced) {
    int last = from;
    for (int i = from + 1; i <= to; ++i) {
        if (!isTraced(i)) continue;
        const glm::vec3 a = at(last), b = at(i);
        for (int m = last + 1; m < i; ++m) {
            const float w = static_cast<float>(m - last) / static_cast<float>(i - last);
            at(m) = (1.0f - w) * a + w * b;
        }
        last = i;
    }
}
}  // namespace

void interpolateRow(ImageRGB& image, const Image<std::uint8_t>& traced, int y, int from, int to) {
    interpolateLine(
        from, to, [&](int x) -> glm::vec3& { return image.at(x, y); }, [&](int x) { return traced.at(x, y) != 0; });
}

void interpolateColumn(ImageRGB& image, const Image<std::uint8_t>& traced, int x, int from, int to) {
    interpolateLine(
        from, to, [&](int y) -> glm::vec3& { return image.at(x, y); }, [&](int y) { return traced.at(x, y) != 0; });
}

void fillPlan(ImageRGB& image, const SubsamplePlan& plan) {
    // Sequential: it is a few operations per pixel, and shared borders are written by two blocks
    // (with the same values: they depend only on the traced pixels of the line).
    for (const Block& b : plan.interpolated) {
        interpolateRow(image, plan.traced, b.y0, b.x0, b.x1);
        interpolateRow(image, plan.traced, b.y1, b.x0, b.x1);
        interpolateColumn(image, plan.traced, b.x0, b.y0, b.y1);
        interpolateColumn(image, plan.traced, b.x1, b.y0, b.y1);
        interpolateBlock(image, b);
    }
}

namespace {

class SubsampleStrategy final : public SamplingStrategy {
public:
    SubsampleStrategy(int n, StrataMapping mapping, int spacing, double threshold, const ImageGrey& map,
                      const BlockSums* sums)
        : n_(n), mapping_(mapping), spacing_(spacing), threshold_(threshold), map_(map), sums_(sums) {}
    int maxRaysPerPixel() const override { return n_ * n_; }
    std::string describe() const override {
        return fmt::format("aamap-subsample n={} mapping={} spacing={} threshold={} block-sums={}", n_,
                           toString(mapping_), spacing_, threshold_, sums_ != nullptr ? "given" : "cpu");
    }

    void render(const SampleSource& source, const Scheduler& scheduler, StrategyImages& out) const override {
        std::optional<BlockSums> cpuSums;  // the fallback when no GPU tables were given
        if (sums_ == nullptr) cpuSums.emplace(map_);
        const SubsamplePlan plan = planSubsampling(sums_ != nullptr ? *sums_ : *cpuSums, spacing_, threshold_);
        scheduler.tiles([&](int x0, int y0, int x1, int y1) {
            for (int y = y0; y < y1; ++y)
                for (int x = x0; x < x1; ++x) {
                    if (!plan.traced.at(x, y)) continue;
                    const int k = stratification(map_.at(x, y), n_, mapping_);
                    out.image.at(x, y) = source.pixel(x, y, k);
                    out.primaryRays.at(x, y) = static_cast<std::uint16_t>(k * k);
                }
        });
        out.traced = plan.traced;
        fillPlan(out.image, plan);
    }

private:
    int n_;
    StrataMapping mapping_;
    int spacing_;
    double threshold_;
    const ImageGrey& map_;
    const BlockSums* sums_;
};

}  // namespace

StrategyDescriptor subsampleStrategy() {
    StrategyDescriptor d;
    d.name = "aamap-subsample";
    d.doc = "adaptive subsampling guided by the aamap, then k x k rays in traced pixels (paper section 4)";
    d.params = {intParam("spacing", 1, 64, 8, "grid spacing s in pixels (the paper's Space 8 / Space 16)"),
                // Infinity: never split (only the grid is traced); the config takes finite values.
                realParam("threshold", 0, std::numeric_limits<double>::infinity(), 0,
                          "blocks whose aamap sum exceeds it are split, the rest interpolated"),
                mappingParam()};
    d.usesAamap = true;
    d.needsBlockSums = true;
    d.marksTraced = true;
    d.create = [](const StrategyParams& p, const StrategyInputs& in) {
        return std::make_unique<SubsampleStrategy>(in.strata, mappingOf(p), p.integer("spacing"), p.real("threshold"),
                                                   *in.aamap, in.blockSums);
    };
    return d;
}

}  // namespace aamap
