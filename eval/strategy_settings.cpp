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
    const ShadingConfig& h = c.shading;
    ShadingSettings s;
    s.areaLightSamples = h.areaLightSamples;
    s.mode = h.mode;
    if (!r.shadingMode.empty()) parse(r.shadingMode, s.mode);  // the reference's own; the config reader checked it
    s.maxDepth = h.maxDepth;
    s.russianRoulette = h.russianRoulette;
    s.rouletteDepth = h.rouletteDepth;
    s.maxSpecularDepth = h.maxSpecularDepth;
    s.glossyReflectionAlpha = static_cast<float>(h.glossyReflectionAlpha);
    s.hideEmitters = h.hideEmitters;
    s.lightSelection = h.lightSelection;
    s.lightSampling = h.lightSampling;
    s.textureFilter = h.textureFilter;
    const ShadingConfig::Cache& ic = h.cache;
    s.cache.bounces = ic.bounces;
    s.cache.divisions = ic.divisions;
    s.cache.supersamples = ic.supersamples;
    s.cache.accuracy = static_cast<float>(ic.accuracy);
    s.cache.resolution = ic.resolution;
    s.cacheGridStep = ic.gridStep;
    s.cache.seed = c.seed;  // the cache's records, like every sample, follow the experiment's seed
    return s;
}

}  // namespace aamap
