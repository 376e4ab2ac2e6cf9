#include "tracer/strategies/subsample.h"

#include <cmath>
#include <limits>
#include <optional>

#include <fmt/format.h>

#include "core/image_io.h"
#include "tracer/strategies/strategies.h"

namespace aamap {

std::vector<int> gridLines(int size, int spacing) {
    std::vector<int> lines;
    for (int i = 0; i < size; i += spacing) lines.push_back(i);
    if (lines.back() != size - 1) lines.push_back(size - 1);
    return lines;
}

bool hasInnerPixels(const Block& b) { return b.x1 - b.x0 > 1 || b.y1 - b.y0 > 1; }

std::vector<Block> splitBlock(const Block& b) {
    const int xm = (b.x0 + b.x1) / 2, ym = (b.y0 + b.y1) / 2;
    const bool splitX = b.x1 - b.x0 > 1, splitY = b.y1 - b.y0 > 1;
    const int xs[3] = {b.x0, splitX ? xm : b.x1, b.x1};
    const int ys[3] = {b.y0, splitY ? ym : b.y1, b.y1};
    std::vector<Block> parts;
    for (int j = 0; j < (splitY ? 2 : 1); ++j)
        for (int i = 0; i < (splitX ? 2 : 1); ++i)
            parts.push_back({xs[i], ys[j], splitX ? xs[i + 1] : b.x1, splitY ? ys[j + 1] : b.y1});
    return parts;
}

namespace {

struct Planner {
    const BlockSums& sums;
    double threshold;
    SubsamplePlan& plan;

    void refine(const Block& b) {
        plan.traced.at(b.x0, b.y0) = plan.traced.at(b.x1, b.y0) = 1;
        plan.traced.at(b.x0, b.y1) = plan.traced.at(b.x1, b.y1) = 1;
        if (!hasInnerPixels(b)) return;  // every pixel is a corner
        if (!(sums.sum(b.x0, b.y0, b.x1, b.y1) > threshold)) {
            plan.interpolated.push_back(b);
            return;
        }
        for (const Block& part : splitBlock(b)) refine(part);
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

namespace {
glm::vec3 bilinear(const ImageRGB& image, const Block& b, int x, int y) {
    const float u = b.x1 > b.x0 ? static_cast<float>(x - b.x0) / static_cast<float>(b.x1 - b.x0) : 0.0f;
    const float v = b.y1 > b.y0 ? static_cast<float>(y - b.y0) / static_cast<float>(b.y1 - b.y0) : 0.0f;
    const glm::vec3 top = (1.0f - u) * image.at(b.x0, b.y0) + u * image.at(b.x1, b.y0);
    const glm::vec3 bottom = (1.0f - u) * image.at(b.x0, b.y1) + u * image.at(b.x1, b.y1);
    return (1.0f - v) * top + v * bottom;
}
}  // namespace

float predictedInterpolationError(const ImageRGB& image, const Block& block, float exposure) {
    float worst = 0.0f;
    for (const Block& part : splitBlock(block))
        for (const auto& [x, y] : {std::pair{part.x0, part.y0}, std::pair{part.x1, part.y0},
                                   std::pair{part.x0, part.y1}, std::pair{part.x1, part.y1}}) {
            const glm::vec3 predicted = bilinear(image, block, x, y), traced = image.at(x, y);
            float squared = 0.0f;
            for (int c = 0; c < 3; ++c) {
                const float d = displayEncode(predicted[c], exposure) - displayEncode(traced[c], exposure);
                squared += d * d;
            }
            worst = std::max(worst, 255.0f * std::sqrt(squared / 3.0f));  // the block's own corners: 0
        }
    return worst;
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
    SubsampleStrategy(int n, StrataMapping mapping, int spacing, double threshold, double gradientTolerance,
                      float exposure, const ImageGrey& map, const BlockSums* sums)
        : n_(n), mapping_(mapping), spacing_(spacing), threshold_(threshold), gradientTolerance_(gradientTolerance),
          exposure_(exposure), map_(map), sums_(sums) {}
    int maxRaysPerPixel() const override { return n_ * n_; }
    // The planned pixels, then one phase per gradient round: blocks of at most `spacing` pixels
    // a side halve each round, so ceil(log2(spacing)) rounds reach single pixels.
    int tilePhases() const override {
        return 1 + (refinesGradients() ? static_cast<int>(std::ceil(std::log2(static_cast<double>(spacing_)))) : 0);
    }
    std::string describe() const override {
        return fmt::format("aamap-subsample n={} mapping={} spacing={} threshold={} gradient-tolerance={} "
                           "exposure={} block-sums={}",
                           n_, toString(mapping_), spacing_, threshold_, gradientTolerance_, exposure_,
                           sums_ != nullptr ? "given" : "cpu");
    }

    void render(const SampleSource& source, const Scheduler& scheduler, StrategyImages& out) const override {
        std::optional<BlockSums> cpuSums;  // the fallback when no GPU tables were given
        if (sums_ == nullptr) cpuSums.emplace(map_);
        SubsamplePlan plan = planSubsampling(sums_ != nullptr ? *sums_ : *cpuSums, spacing_, threshold_);
        traceNewlyMarked(source, scheduler, plan.traced, out);
        if (refinesGradients()) refineGradients(source, scheduler, plan, out);
        out.traced = plan.traced;
        fillPlan(out.image, plan);
    }

private:
    // No display difference exceeds 255 code values: a tolerance that high could never split, so
    // no probe is traced and the map alone decides (the paper's Space 8/16; a config's way to it).
    bool refinesGradients() const { return gradientTolerance_ < kGradientToleranceOff; }

    // Traces every pixel marked in `traced` that has no ray yet (k >= 1: a traced pixel has rays).
    // One parallel phase: each pixel is written by its own tile only.
    void traceNewlyMarked(const SampleSource& source, const Scheduler& scheduler, const Image<std::uint8_t>& traced,
                          StrategyImages& out) const {
        scheduler.tiles([&](int x0, int y0, int x1, int y1) {
            for (int y = y0; y < y1; ++y)
                for (int x = x0; x < x1; ++x) {
                    if (!traced.at(x, y) || out.primaryRays.at(x, y) != 0) continue;
                    const int k = stratification(map_.at(x, y), n_, mapping_);
                    out.image.at(x, y) = source.pixel(x, y, k);
                    out.primaryRays.at(x, y) = static_cast<std::uint16_t>(k * k);
                }
        });
    }

    // Rounds over the blocks the plan would interpolate: trace the corners their split adds, then
    // (from the completed round only, so for any thread count) keep testing the quarters of a
    // block whose predicted error exceeds the tolerance, and interpolate those of the others.
    // A predicted error rather than a contrast test between corners: a linear ramp of any slope
    // interpolates exactly and costs nothing, while a curved falloff between equal corners (a
    // hot spot centred in the block) is caught. Every probe becomes a corner, so none is wasted.
    void refineGradients(const SampleSource& source, const Scheduler& scheduler, SubsamplePlan& plan,
                         StrategyImages& out) const {
        std::vector<Block> candidates = std::move(plan.interpolated);
        plan.interpolated.clear();
        while (!candidates.empty()) {
            for (const Block& b : candidates)
                for (const Block& part : splitBlock(b)) {
                    plan.traced.at(part.x0, part.y0) = plan.traced.at(part.x1, part.y0) = 1;
                    plan.traced.at(part.x0, part.y1) = plan.traced.at(part.x1, part.y1) = 1;
                }
            traceNewlyMarked(source, scheduler, plan.traced, out);
            std::vector<std::uint8_t> steep(candidates.size(), 0);
            scheduler.range(static_cast<int>(candidates.size()), [&](int i) {
                const float error = predictedInterpolationError(out.image, candidates[static_cast<std::size_t>(i)],
                                                                exposure_);
                steep[static_cast<std::size_t>(i)] = error > gradientTolerance_ ? 1 : 0;
            });
            std::vector<Block> next;
            for (std::size_t i = 0; i < candidates.size(); ++i)
                for (const Block& part : splitBlock(candidates[i]))
                    if (hasInnerPixels(part)) (steep[i] ? next : plan.interpolated).push_back(part);
            candidates = std::move(next);
        }
    }

    int n_;
    StrataMapping mapping_;
    int spacing_;
    double threshold_;
    double gradientTolerance_;  // >= kGradientToleranceOff: no gradient rounds
    float exposure_;
    const ImageGrey& map_;
    const BlockSums* sums_;
};

}  // namespace

StrategyDescriptor subsampleStrategy() {
    StrategyDescriptor d;
    d.name = kSubsampleStrategyName;
    d.doc = "adaptive subsampling guided by the aamap (paper section 4) and by traced gradients, then k x k rays "
            "in traced pixels";
    d.params = {intParam(kSubsampleSpacing, 1, 64, 8, "grid spacing s in pixels (the paper's Space 8 / Space 16)"),
                // Infinity: never split (only the grid is traced); the config takes finite values.
                realParam(kSubsampleThreshold, 0, std::numeric_limits<double>::infinity(), 0,
                          "blocks whose aamap sum exceeds it are split, the rest interpolated"),
                realParam("gradient_tolerance", 0, std::numeric_limits<double>::infinity(), kDefaultGradientTolerance,
                          "a block to interpolate is split further while its centre and edge midpoints, traced, "
                          "differ from the bilinear prediction of its corners by more than this many 8-bit "
                          "display code values (RMS over R, G, B; 2: the display MSE error threshold; 255 or "
                          "more: the map alone decides, as the paper)"),
                mappingParam()};
    d.usesAamap = true;
    d.needsBlockSums = true;
    d.marksTraced = true;
    d.create = [](const StrategyParams& p, const StrategyInputs& in) {
        return std::make_unique<SubsampleStrategy>(in.strata, mappingOf(p), p.integer("spacing"), p.real("threshold"),
                                                   p.real("gradient_tolerance"), in.exposure, *in.aamap,
                                                   in.blockSums);
    };
    return d;
}

}  // namespace aamap
