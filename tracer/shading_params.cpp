#include "tracer/shading_params.h"

#include "tracer/tracer_types.h"

namespace aamap {

const std::vector<ParamSpec>& shadingParams() {
    static const std::vector<ParamSpec> params = {
        intParam("area_light_samples", 1, 4096, 16, "shadow rays per area light per hit"),
        choiceParam("mode", {"direct", "path", "cache"}, "direct light, path tracing or an irradiance cache"),
        intParam("max_depth", 1, kMaxPathDepth, 5,
                 "path: longest path in segments; unset: a Mitsuba scene file's integrator decides"),
        boolParam("russian_roulette", true, "path"),
        intParam("roulette_depth", 1, kMaxPathDepth, 5,
                 "path: roulette from this segment on; unset: a Mitsuba scene file's integrator decides"),
        boolParam("hide_emitters", false,
                  "camera rays see no emitter: area lights add no emission and the environment is black where "
                  "seen directly (reflections keep both); unset: a Mitsuba scene file's integrator decides"),
        intParam("max_specular_depth", 0, 1024, 8, "direct/cache: mirror and glass bounces"),
        choiceParam("light_selection", {"contribution", "power"}, "which light a shadow ray goes to"),
        choiceParam("light_sampling", {"auto", "solid_angle", "area"},
                    "an area light's samples uniform over the solid angle it subtends (near lights of up to 8 "
                    "triangles) or over its area; auto: by solid angle in direct and cache modes, by area in path"),
        choiceParam("texture_filter", {"anisotropic", "none"},
                    "textures filtered over each ray's footprint, or the bilinear texel at the hit"),
    };
    return params;
}

bool parse(const std::string& name, LightSampling& sampling) {
    if (name == "auto") sampling = LightSampling::Auto;
    else if (name == "solid_angle") sampling = LightSampling::SolidAngle;
    else if (name == "area") sampling = LightSampling::Area;
    else return false;
    return true;
}

const std::vector<ParamSpec>& shadingCacheParams() {
    static const std::vector<ParamSpec> params = {
        intParam("bounces", 0, 16, 1, "diffuse bounces through the cache"),
        intParam("divisions", 4, 1 << 16, 512, "hemisphere samples of a record"),
        intParam("supersamples", 0, 1 << 16, 128, "extra samples to the cells with the largest differences"),
        realParamAbove("accuracy", 0.0, 1.0, 0.2, "a record is used where its error is below this"),
        intParam("resolution", 0, 1 << 16, 64, "minimum record radius = scene size / resolution"),
        intParam("grid_step", 1, 64, 4, "the pre-pass takes one camera ray per grid_step x grid_step pixels"),
    };
    return params;
}

}  // namespace aamap
