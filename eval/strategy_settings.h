#pragma once
// A render's config as the tracer's StrategySettings and ShadingSettings.
#include "core/image.h"
#include "eval/config.h"
#include "tracer/strategy.h"
#include "tracer/tracer_types.h"

namespace aamap {

// aamap: the Snapshot's map, required by strategies that use it (not owned).
StrategySettings toStrategySettings(const RenderConfig& render, const ImageGrey* aamap);
ShadingSettings toShadingSettings(const ExperimentConfig& config, const RenderConfig& render);

}  // namespace aamap
