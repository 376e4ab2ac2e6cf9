#include "eval/strategy_settings.h"

#include <fmt/format.h>

#include "core/error.h"
#include "tracer/shading_params.h"

namespace aamap {

StrategySettings toStrategySettings(const RenderConfig& r, const ImageGrey* aamap) {
    const StrategyDescriptor* d = findStrategy(r.strategy);
    if (d == nullptr) throw InputError("config", fmt::format("strategy '{}' is not known to the tracer", r.strategy));
    StrategySettings s;
    s.name = r.strategy;
    s.strata = r.strata();
    s.params = r.params;  // checked by the config reader and again by the tracer, against one schema
    if (d->usesAamap) s.aamap = aamap;
    return s;
}

ShadingSettings toShadingSettings(const ExperimentConfig& c, const RenderConfig& r) {
    ShadingSettings s = c.shading;  // the config holds the tracer's own struct
    if (r.shadingMode) s.mode = *r.shadingMode;  // the reference's own
    s.cache.seed = c.seed;  // the cache's records, like every sample, follow the experiment's seed
    return s;
}

}  // namespace aamap
