#include "tracer/strategy.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <fmt/format.h>

#include "tracer/block_sums.h"
#include "tracer/strategies/strategies.h"

namespace aamap {

const char* toString(StrategyKind kind) {
    switch (kind) {
        case StrategyKind::Uniform: return "uniform";
        case StrategyKind::Aamap: return "aamap";
        case StrategyKind::AamapSubsample: return "aamap-subsample";
        case StrategyKind::RpictAdaptive: return "rpict";
        case StrategyKind::SupersampleFilter: return "supersample";
        case StrategyKind::VarianceAdaptive: return "variance";
        case StrategyKind::ShapeIdAdaptive: return "shape-id";
        case StrategyKind::Hybrid: return "hybrid";
    }
    return "unknown";
}

const char* toString(StrataMapping mapping) {
    return mapping == StrataMapping::LinearRays ? "linear-rays" : "paper";
}

const char* toString(DownFilter filter) { return filter == DownFilter::Gaussian ? "gaussian" : "box"; }

namespace {
template <class Enum, int N>
bool parseEnum(const std::string& name, Enum& out, const Enum (&all)[N]) {
    for (Enum e : all)
        if (name == toString(e)) {
            out = e;
            return true;
        }
    return false;
}
}  // namespace

bool parse(const std::string& name, StrategyKind& kind) {
    using K = StrategyKind;
    const K all[] = {K::Uniform,           K::Aamap,           K::AamapSubsample, K::RpictAdaptive,
                     K::SupersampleFilter, K::VarianceAdaptive, K::ShapeIdAdaptive, K::Hybrid};
    return parseEnum(name, kind, all);
}

bool parse(const std::string& name, StrataMapping& mapping) {
    const StrataMapping all[] = {StrataMapping::Paper, StrataMapping::LinearRays};
    return parseEnum(name, mapping, all);
}

bool parse(const std::string& name, DownFilter& filter) {
    const DownFilter all[] = {DownFilter::Box, DownFilter::Gaussian};
    return parseEnum(name, filter, all);
}

int aamapStratification(float a, int n) { return stratification(a, n, StrataMapping::Paper); }

int stratification(float a, int n, StrataMapping mapping) {
    if (std::isnan(a)) return n;
    const float c = std::clamp(a, 0.0f, 1.0f);
    int k = 1;
    if (mapping == StrataMapping::Paper) {
        k = 1 + static_cast<int>(std::lround(c * static_cast<float>(n - 1)));
    } else {
        // Rays k^2 ~ 1 + a (n^2 - 1): linear in a. Double: n^2 reaches 65025.
        const double rays = 1.0 + static_cast<double>(c) * (static_cast<double>(n) * n - 1.0);
        k = static_cast<int>(std::lround(std::sqrt(rays)));
    }
    return std::clamp(k, 1, n);
}

void PerPixelStrategy::render(const SampleSource& source, const Scheduler& scheduler, StrategyImages& out) const {
    scheduler.tiles([&](int x0, int y0, int x1, int y1) {
        for (int y = y0; y < y1; ++y)
            for (int x = x0; x < x1; ++x) {
                const int k = stratificationFor(x, y);
                out.image.at(x, y) = source.pixel(x, y, k);
                out.primaryRays.at(x, y) = static_cast<std::uint16_t>(k * k);
                out.traced.at(x, y) = 1;
            }
    });
}

namespace {

class UniformStrategy final : public PerPixelStrategy {
public:
    explicit UniformStrategy(int n) : n_(n) {}
    StrategyKind kind() const override { return StrategyKind::Uniform; }
    int maxRaysPerPixel() const override { return n_ * n_; }
    std::string describe() const override { return fmt::format("uniform n={}", n_); }
    int stratificationFor(int, int) const override { return n_; }

private:
    int n_;
};

class AamapStrategy final : public PerPixelStrategy {
public:
    AamapStrategy(int n, StrataMapping mapping, const ImageGrey& map) : n_(n), mapping_(mapping), map_(map) {}
    StrategyKind kind() const override { return StrategyKind::Aamap; }
    int maxRaysPerPixel() const override { return n_ * n_; }
    std::string describe() const override { return fmt::format("aamap n={} mapping={}", n_, toString(mapping_)); }
    int stratificationFor(int x, int y) const override { return stratification(map_.at(x, y), n_, mapping_); }

private:
    int n_;
    StrataMapping mapping_;
    const ImageGrey& map_;
};

const ImageGrey& requireMap(const StrategySettings& s, int width, int height) {
    if (s.aamap == nullptr)
        throw std::invalid_argument(fmt::format("{} strategy needs an aamap image", toString(s.kind)));
    const ImageGrey& map = *s.aamap;
    if (map.width() != width || map.height() != height)
        throw std::invalid_argument(
            fmt::format("aamap is {}x{} but the render is {}x{}", map.width(), map.height(), width, height));
    return map;
}

void require(bool ok, const std::string& message) {
    if (!ok) throw std::invalid_argument(message);
}

}  // namespace

std::unique_ptr<SamplingStrategy> makeStrategy(const StrategySettings& s, int width, int height) {
    const int n = s.strata;
    require(n >= 1 && n <= kMaxStrata, fmt::format("strata must be in [1, {}], got {}", kMaxStrata, n));
    std::unique_ptr<SamplingStrategy> strategy;
    switch (s.kind) {
        case StrategyKind::Uniform: strategy = std::make_unique<UniformStrategy>(n); break;
        case StrategyKind::Aamap:
            strategy = std::make_unique<AamapStrategy>(n, s.mapping, requireMap(s, width, height));
            break;
        case StrategyKind::AamapSubsample:
            require(s.spacing >= 1 && s.spacing <= 64, fmt::format("spacing must be in [1, 64], got {}", s.spacing));
            require(s.threshold >= 0.0, fmt::format("threshold must be >= 0, got {}", s.threshold));
            require(s.blockSums == nullptr || (s.blockSums->width() == width && s.blockSums->height() == height),
                    "block sums do not match the render size");
            strategy = makeSubsampleStrategy(n, s.mapping, s.spacing, s.threshold, requireMap(s, width, height),
                                             s.blockSums);
            break;
        case StrategyKind::RpictAdaptive:
            require(s.spacing >= 1 && s.spacing <= 64, fmt::format("spacing must be in [1, 64], got {}", s.spacing));
            require(s.threshold >= 0.0, fmt::format("threshold must be >= 0, got {}", s.threshold));
            strategy = makeRpictStrategy(s.spacing, s.threshold);
            break;
        case StrategyKind::SupersampleFilter:
            require(s.supersample >= 1 && s.supersample <= 4,
                    fmt::format("supersample factor must be in [1, 4], got {}", s.supersample));
            require(std::isfinite(s.filterRadius) && s.filterRadius > 0.0,
                    fmt::format("filter radius must be > 0, got {}", s.filterRadius));
            strategy = makeSupersampleStrategy(n, s.supersample, s.filter, s.filterRadius);
            break;
        case StrategyKind::VarianceAdaptive:
            require(s.noiseThreshold >= 0.0, fmt::format("noise threshold must be >= 0, got {}", s.noiseThreshold));
            require(s.minSamples >= 1, fmt::format("min samples must be >= 1, got {}", s.minSamples));
            require(s.sampleStep >= 1, fmt::format("sample step must be >= 1, got {}", s.sampleStep));
            strategy = makeVarianceStrategy(n, s.noiseThreshold, s.minSamples, s.sampleStep);
            break;
        case StrategyKind::ShapeIdAdaptive:
            require(s.minSamples >= 1, fmt::format("min samples must be >= 1, got {}", s.minSamples));
            strategy = makeShapeIdStrategy(n, s.minSamples);
            break;
        case StrategyKind::Hybrid:
            require(s.noiseThreshold >= 0.0, fmt::format("noise threshold must be >= 0, got {}", s.noiseThreshold));
            require(s.sampleStep >= 1, fmt::format("sample step must be >= 1, got {}", s.sampleStep));
            strategy = makeHybridStrategy(n, s.mapping, s.noiseThreshold, s.sampleStep, requireMap(s, width, height));
            break;
    }
    require(strategy != nullptr, "unknown sampling strategy");
    require(strategy->maxRaysPerPixel() <= 65535,
            fmt::format("{}: up to {} rays per pixel do not fit the 16-bit ray map", strategy->describe(),
                        strategy->maxRaysPerPixel()));
    return strategy;
}

}  // namespace aamap
