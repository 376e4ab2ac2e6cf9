#include "eval/strategy_settings.h"

#include <fmt/format.h>

#include "core/error.h"

namespace aamap {

StrategySettings toStrategySettings(const RenderConfig& r, const ImageGrey* aamap) {
    StrategySettings s;
    s.strata = r.strata();
    // One case per strategyTable() entry (eval/strategies.cpp); tracer/strategy.cpp's names.
    if (!parse(r.strategy, s.kind))
        throw InputError("config", fmt::format("strategy '{}' is not known to the tracer", r.strategy));
    const auto has = [&](const char* key) {
        for (const auto& [k, v] : r.params)
            if (k == key) return true;
        return false;
    };
    const auto integer = [&](const char* key) { return static_cast<int>(r.param(key)); };
    if (has("mapping")) s.mapping = integer("mapping") == 1 ? StrataMapping::LinearRays : StrataMapping::Paper;
    switch (s.kind) {
        case StrategyKind::Uniform: break;
        case StrategyKind::Aamap: s.aamap = aamap; break;
        case StrategyKind::AamapSubsample:
            s.aamap = aamap;
            s.spacing = integer("spacing");
            s.threshold = r.param("threshold");
            break;
        case StrategyKind::RpictAdaptive:
            s.spacing = integer("spacing");
            s.threshold = r.param("threshold");
            break;
        case StrategyKind::SupersampleFilter:
            s.supersample = integer("supersample");
            s.filter = integer("filter") == 1 ? DownFilter::Gaussian : DownFilter::Box;
            s.filterRadius = r.param("filter_radius");
            break;
        case StrategyKind::VarianceAdaptive:
            s.noiseThreshold = r.param("noise_threshold");
            s.minSamples = integer("min_samples");
            s.sampleStep = integer("sample_step");
            break;
        case StrategyKind::ShapeIdAdaptive: s.minSamples = integer("min_samples"); break;
        case StrategyKind::Hybrid:
            s.aamap = aamap;
            s.noiseThreshold = r.param("noise_threshold");
            s.sampleStep = integer("sample_step");
            break;
    }
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
    s.lightSelection = c.shading.lightSelection == "power" ? LightSelection::Power : LightSelection::Contribution;
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
