#include "passes/snapshot_params.h"

#include "glsl/shared/aamap_filter.h"
#include "glsl/shared/subpixel_map.h"

namespace aamap {

namespace passes {

namespace {

// snapshot.map's names, declared once: the schema's choice and toString/parse read this list.
const std::vector<std::pair<std::string, AamapSource>>& mapNames() {
    static const std::vector<std::pair<std::string, AamapSource>> names = {
        {"luminance", AamapSource::Luminance},
        {"geometric", AamapSource::Geometric},
        {"combined", AamapSource::Combined},
        {"subpixel", AamapSource::Subpixel}};
    return names;
}

}  // namespace

const char* toString(AamapSource source) {
    for (const auto& n : mapNames())
        if (n.second == source) return n.first.c_str();
    return "?";
}

bool parse(const std::string& name, AamapSource& source) {
    for (const auto& n : mapNames())
        if (n.first == name) {
            source = n.second;
            return true;
        }
    return false;
}

}  // namespace passes

// The filter chain's defaults are the GLSL header's (its shaders' specialisation defaults), the
// subpixel map's k range its header's: one definition each, which the schema names.
const Schema<SnapshotConfig>& snapshotSchema() {
    using S = SnapshotConfig;
    static const Schema<S> schema = [] {
        Schema<S> s;
        s.field(&S::scale, "scale", in(1.0, 4.0), 1.5, "snapshot resolution / render resolution")
            .field(&S::areaLightSamples, "area_light_samples", in(1, 64), 5,
                   "at most this many point lights approximating each area light")
            .field(&S::areaLightSolidAngle, "area_light_solid_angle", in(0.0, 12.6), 0.04,
                   "an area light gets one point sample per this many steradians of its mean solid angle over "
                   "the visible region (at least 1, at most area_light_samples; 0: always area_light_samples)")
            .field(&S::environmentLights, "environment_lights", in(0, 16), 1,
                   "the environment map's brightest regions as shadowed directional lights")
            .field(&S::softShadows, "soft_shadows", true,
                   "area-light samples cast the soft shadow of the patch of light each stands for (PCSS)")
            .field(&S::blurRadius, "blur_radius", in(0, 16), AAMAP_DEFAULT_BLUR_RADIUS,
                   "box blur radius after the Laplacian, in snapshot pixels")
            .field(&S::flatRange, "flat_range", in(0.0, 1.0), AAMAP_DEFAULT_FLAT_RANGE,
                   "the Laplacian counts only where the grey spans at least this over a texel's 3x3 window "
                   "(1/255: one 8-bit code value; 0: everywhere)")
            .field(&S::noiseFloor, "noise_floor", in(0.0, 1.0), AAMAP_DEFAULT_NOISE_FLOOR,
                   "blurred edge responses below this are smooth shading")
            .field(&S::gain, "gain", above(0.0, 1e6), AAMAP_DEFAULT_GAIN,
                   "map = clamp(gain * (blurred - noise_floor), 0, 1)")
            .choice(&S::map, "map", passes::mapNames(),
                    "what the map is built from (subpixel: each pixel's predicted one-ray error from k x k samples)")
            .field(&S::subpixel, "subpixel", in(SUBPIXEL_MIN_K, SUBPIXEL_MAX_K), SUBPIXEL_DEFAULT_K,
                   "map subpixel: samples per pixel side k (the raster runs at k x the render resolution)");
        return s;
    }();
    return schema;
}

SnapshotConfig::SnapshotConfig() { snapshotSchema().setDefaults(*this); }

const std::vector<ParamSpec>& snapshotParams() { return snapshotSchema().specs(); }

}  // namespace aamap
