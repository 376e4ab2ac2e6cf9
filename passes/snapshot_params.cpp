#include "passes/snapshot_params.h"

#include "glsl/shared/aamap_filter.h"
#include "glsl/shared/subpixel_map.h"

namespace aamap {

const std::vector<ParamSpec>& snapshotParams() {
    static const std::vector<ParamSpec> params = {
        realParam("scale", 1.0, 4.0, 1.5, "snapshot resolution / render resolution"),
        intParam("area_light_samples", 1, 64, 5, "point lights approximating each area light"),
        intParam("environment_lights", 0, 16, 1, "the environment map's brightest regions as shadowed directional lights"),
        boolParam("soft_shadows", true,
                  "area-light samples cast the soft shadow of the patch of light each stands for (PCSS)"),
        intParam("blur_radius", 0, 16, 1, "box blur radius after the Laplacian, in snapshot pixels"),
        realParam("flat_range", 0.0, 1.0, AAMAP_DEFAULT_FLAT_RANGE,
                  "the Laplacian counts only where the grey spans at least this over a texel's 3x3 window "
                  "(1/255: one 8-bit code value; 0: everywhere)"),
        realParam("noise_floor", 0.0, 1.0, 0.02, "blurred edge responses below this are smooth shading"),
        realParamAbove("gain", 0.0, 1e6, 1.0, "map = clamp(gain * (blurred - noise_floor), 0, 1)"),
        choiceParam("map", {"luminance", "geometric", "combined", "subpixel"},
                    "what the map is built from (subpixel: each pixel's predicted one-ray error from k x k samples)"),
        intParam("subpixel", SUBPIXEL_MIN_K, SUBPIXEL_MAX_K, SUBPIXEL_DEFAULT_K,
                 "map subpixel: samples per pixel side k (the raster runs at k x the render resolution)"),
    };
    return params;
}

}  // namespace aamap
