#pragma once
// The `shading` config section and its `shading.cache` subsection, declared once: the
// integrator's settings (tracer/integrator.h, tracer/irradiance_cache.h). The config reader,
// --set, --help and docs/config.md are generated from these lists.
#include <vector>

#include "core/params.h"

namespace aamap {

// The longest path shading.max_depth allows (a scene file's unlimited depth becomes this).
inline constexpr int kMaxPathDepth = 1024;

const std::vector<ParamSpec>& shadingParams();
const std::vector<ParamSpec>& shadingCacheParams();

}  // namespace aamap
