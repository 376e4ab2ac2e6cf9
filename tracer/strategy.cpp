#include "tracer/strategy.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <fmt/format.h>

namespace aamap {

const char* toString(StrategyKind kind) {
    switch (kind) {
        case StrategyKind::Uniform: return "uniform";
        case StrategyKind::Aamap: return "aamap";
    }
    return "unknown";
}

void SamplingStrategy::fill(ImageRGB&, const Image<std::uint16_t>&) const {}

int aamapStratification(float a, int n) {
    if (std::isnan(a)) return n;
    const float clamped = std::clamp(a, 0.0f, 1.0f);
    const int k = 1 + static_cast<int>(std::lround(clamped * static_cast<float>(n - 1)));
    return std::clamp(k, 1, n);
}

namespace {

class UniformStrategy final : public SamplingStrategy {
public:
    explicit UniformStrategy(int n) : n_(n) {}
    StrategyKind kind() const override { return StrategyKind::Uniform; }
    int maxStratification() const override { return n_; }
    int stratificationFor(int, int) const override { return n_; }

private:
    int n_;
};

class AamapStrategy final : public SamplingStrategy {
public:
    AamapStrategy(int n, const ImageGrey& map) : n_(n), map_(map) {}
    StrategyKind kind() const override { return StrategyKind::Aamap; }
    int maxStratification() const override { return n_; }
    int stratificationFor(int x, int y) const override { return aamapStratification(map_.at(x, y), n_); }

private:
    int n_;
    const ImageGrey& map_;
};

}  // namespace

std::unique_ptr<SamplingStrategy> makeStrategy(const StrategySettings& settings, int width, int height) {
    const int n = settings.strata;
    if (n < 1 || n > kMaxStrata)
        throw std::invalid_argument(fmt::format("strata must be in [1, {}], got {}", kMaxStrata, n));
    switch (settings.kind) {
        case StrategyKind::Uniform: return std::make_unique<UniformStrategy>(n);
        case StrategyKind::Aamap: {
            if (settings.aamap == nullptr) throw std::invalid_argument("aamap strategy needs an aamap image");
            const ImageGrey& map = *settings.aamap;
            if (map.width() != width || map.height() != height)
                throw std::invalid_argument(fmt::format("aamap is {}x{} but the render is {}x{}", map.width(),
                                                        map.height(), width, height));
            return std::make_unique<AamapStrategy>(n, map);
        }
    }
    throw std::invalid_argument("unknown sampling strategy");
}

}  // namespace aamap
