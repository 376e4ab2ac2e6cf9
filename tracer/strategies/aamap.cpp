// aamap: k(p) x k(p) strata, k from the map value under `mapping` (paper section 4).
#include <fmt/format.h>

#include "tracer/strategies/strategies.h"

namespace aamap {
namespace {

class AamapStrategy final : public PerPixelStrategy {
public:
    AamapStrategy(int n, StrataMapping mapping, const ImageGrey& map) : n_(n), mapping_(mapping), map_(map) {}
    int maxRaysPerPixel() const override { return n_ * n_; }
    std::string describe() const override { return fmt::format("aamap n={} mapping={}", n_, toString(mapping_)); }
    int stratificationFor(int x, int y) const override { return stratification(map_.at(x, y), n_, mapping_); }

private:
    int n_;
    StrataMapping mapping_;
    const ImageGrey& map_;
};

}  // namespace

StrategyDescriptor aamapStrategy() {
    StrategyDescriptor d;
    d.name = "aamap";
    d.doc = "k x k rays, k from the aamap (the paper's non-adaptive selective render)";
    d.params = {mappingParam()};
    d.usesAamap = true;
    d.create = [](const StrategyParams& p, const StrategyInputs& in) {
        return std::make_unique<AamapStrategy>(in.strata, mappingOf(p), *in.aamap);
    };
    return d;
}

}  // namespace aamap
