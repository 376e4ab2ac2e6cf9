// uniform: n x n jittered strata in every pixel.
#include <fmt/format.h>

#include "tracer/strategies/strategies.h"

namespace aamap {
namespace {

class UniformStrategy final : public PerPixelStrategy {
public:
    explicit UniformStrategy(int n) : n_(n) {}
    int maxRaysPerPixel() const override { return n_ * n_; }
    std::string describe() const override { return fmt::format("uniform n={}", n_); }
    int stratificationFor(int, int) const override { return n_; }

private:
    int n_;
};

}  // namespace

StrategyDescriptor uniformStrategy() {
    StrategyDescriptor d;
    d.name = "uniform";
    d.doc = "n x n jittered rays in every pixel (the paper's standard render)";
    d.splitsHalves = true;
    d.create = [](const StrategyParams&, const StrategyInputs& in) {
        return std::make_unique<UniformStrategy>(in.strata);
    };
    return d;
}

}  // namespace aamap
