#include "eval/strategy_settings.h"

#include <fmt/format.h>

#include "core/error.h"

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
    ShadingSettings s;
    s.areaLightSamples = c.shading.areaLightSamples;
    const std::string mode = r.shadingMode.empty() ? c.shading.mode : r.shadingMode;
    s.mode = mode == "path" ? ShadingMode::Path : mode == "cache" ? ShadingMode::Cache : ShadingMode::Direct;
    s.maxDepth = c.shading.maxDepth;
    s.russianRoulette = c.shading.russianRoulette;
    s.rouletteDepth = c.shading.rouletteDepth;
    s.maxSpecularDepth = c.shading.maxSpecularDepth;
    s.hideEmitters = c.shading.hideEmitters;
    s.lightSelection = c.shading.lightSelection == "power" ? LightSelection::Power : LightSelection::Contribution;
    parse(c.shading.lightSampling, s.lightSampling);  // the config reader checked the name
    s.textureFilter = c.shading.textureFilter == "none" ? TextureFilter::None : TextureFilter::Anisotropic;
    const ShadingConfig::Cache& ic = c.shading.cache;
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
