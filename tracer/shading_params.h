#pragma once
// The `shading` config section and its `shading.cache` subsection, declared once: each key bound
// to the ShadingConfig field that holds it (core/schema.h), a choice to the tracer's enum
// (tracer/tracer_types.h). The structs' defaults, the config reader, --set, --help, the cache
// keys and docs/config.md's rows are generated from shadingSchema() and shadingCacheSchema().
#include <string>
#include <vector>

#include "core/params.h"
#include "core/schema.h"
#include "tracer/tracer_types.h"

namespace aamap {

// The longest path shading.max_depth allows (a scene file's unlimited depth becomes this).
inline constexpr int kMaxPathDepth = 1024;

// The integrator's settings as the config holds them (tracer/tracer_types.h ShadingSettings is
// what the tracer takes: toShadingSettings, eval/strategy_settings.h). Every default is the schema's.
struct ShadingConfig {
    ShadingConfig();  // shadingSchema()'s defaults

    int areaLightSamples;
    ShadingMode mode;
    int maxDepth;           // path: longest path in segments
    bool russianRoulette;   // path
    int rouletteDepth;      // path: roulette from this segment on
    bool hideEmitters;      // camera rays see no emitter (Mitsuba's hide_emitters)
    int maxSpecularDepth;   // direct/cache: mirror and glass bounces
    double glossyReflectionAlpha;  // direct/cache: lobes up to this roughness reflect the scene
    LightSelection lightSelection;
    LightSampling lightSampling;
    TextureFilter textureFilter;
    // Written in the config (or --set): else a scene file's own integrator decides
    // (withSceneRenderSettings in eval/experiment.h).
    bool maxDepthGiven = false, rouletteDepthGiven = false, hideEmittersGiven = false;
    // cache: the irradiance cache (docs/irradiance-cache.md); Radiance's -ab -ad -as -aa -ar.
    struct Cache {
        Cache();  // shadingCacheSchema()'s defaults
        int bounces;       // diffuse bounces through the cache; 0: shades as direct
        int divisions;     // hemisphere samples of a record
        int supersamples;  // extra samples to the cells with the largest differences
        double accuracy;   // a record is used where its error is below this
        int resolution;    // minimum record radius = scene size / resolution (0: none)
        int gridStep;      // the pre-pass takes one camera ray per grid_step x grid_step pixels
        bool operator==(const Cache&) const = default;
    } cache;
};

const Schema<ShadingConfig>& shadingSchema();
const Schema<ShadingConfig::Cache>& shadingCacheSchema();
const std::vector<ParamSpec>& shadingParams();       // shadingSchema().specs()
const std::vector<ParamSpec>& shadingCacheParams();  // shadingCacheSchema().specs()

// shading.mode's names (direct, path, cache), as the schema declares them; false for an unknown name.
bool parse(const std::string& name, ShadingMode& mode);
// shading.light_sampling's names (auto, solid_angle, area); false for an unknown name.
bool parse(const std::string& name, LightSampling& sampling);

}  // namespace aamap
