#pragma once
// The tracer's config keys, declared once: the `shading` section, its `shading.cache` subsection
// and the pixel filter's keys of `image`, each key bound to the field of the tracer's own settings
// struct that holds it (core/schema.h), a choice to the tracer's enum. The config reader, --set,
// --help, the cache keys and docs/config.md's rows are generated from these schemas.
#include <string>
#include <vector>

#include "core/params.h"
#include "core/schema.h"
#include "tracer/tracer_types.h"

namespace aamap {

// The longest path shading.max_depth allows (a scene file's unlimited depth becomes this).
inline constexpr int kMaxPathDepth = 1024;

// The `shading` section binds ShadingSettings (tracer/tracer_types.h) itself, `shading.cache` its
// IrradianceCacheSettings, and the pixel filter keys of `image` PixelFilterSettings: the config
// fills the structs the tracer takes, and each default is the struct's own initializer, which
// the schema reads (the structs stay plain aggregates for code that builds them directly).
const Schema<ShadingSettings>& shadingSchema();
const Schema<IrradianceCacheSettings>& shadingCacheSchema();
const Schema<PixelFilterSettings>& pixelFilterSchema();
const std::vector<ParamSpec>& shadingParams();       // shadingSchema().specs()
const std::vector<ParamSpec>& shadingCacheParams();  // shadingCacheSchema().specs()

// shading.mode's names (direct, path, cache), as the schema declares them; false for an unknown name.
bool parse(const std::string& name, ShadingMode& mode);
// shading.light_sampling's names (auto, solid_angle, area); false for an unknown name.
bool parse(const std::string& name, LightSampling& sampling);

}  // namespace aamap
