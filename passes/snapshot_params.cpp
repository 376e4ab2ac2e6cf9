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

const std::vector<std::pair<std::string, SubpixelShading>>& shadingNames() {
    static const std::vector<std::pair<std::string, SubpixelShading>> names = {{"pixel", SubpixelShading::Pixel},
                                                                             {"sample", SubpixelShading::Sample}};
    return names;
}

// A choice's name, and the value of a name, from its list of names.
template <class E>
const char* nameIn(const std::vector<std::pair<std::string, E>>& names, E value) {
    for (const auto& n : names)
        if (n.second == value) return n.first.c_str();
    return "?";
}

template <class E>
bool parseIn(const std::vector<std::pair<std::string, E>>& names, const std::string& name, E& value) {
    for (const auto& n : names)
        if (n.first == name) {
            value = n.second;
            return true;
        }
    return false;
}

}  // namespace

const char* toString(SubpixelShading shading) { return nameIn(shadingNames(), shading); }
bool parse(const std::string& name, SubpixelShading& shading) { return parseIn(shadingNames(), name, shading); }
const char* toString(AamapSource source) { return nameIn(mapNames(), source); }
bool parse(const std::string& name, AamapSource& source) { return parseIn(mapNames(), name, source); }

}  // namespace passes

// The filter chain's defaults are the GLSL header's (its shaders' specialisation defaults), the
// subpixel map's k range its header's: one definition each, which the schema names.
namespace {

// The keys of the section that the passes take in their own structs: soft_shadows and
// shadow_texel_pixels (their defaults ShadowSettings' own) and the aamap filter chain's (their
// defaults glsl/shared/aamap_filter.h's).
const Schema<ShadowSettings>& shadowKeys() {
    using H = ShadowSettings;
    static const Schema<H> schema = [] {
        Schema<H> s;
        s.field(&H::softShadows, "soft_shadows", ShadowSettings{}.softShadows,
                   "each point sample of an area light casts the soft shadow of the patch of light it stands for (a "
                   "blocker search and a filter of the penumbra's width in its shadow map, "
                   "[architecture.md](architecture.md), \"Soft shadows of area-light samples\"); false: hard "
                   "shadows from every sample. Point and spot lights cast hard shadows either way. Only `false` "
                   "enters the cache keys")
            .field(&H::texelPixels, "shadow_texel_pixels", in(0.0, 64.0), ShadowSettings{}.texelPixels,
                   "shadow maps by need: each light's cube faces get the fewest texels (a multiple of 16, at least "
                   "32, at most the shadow resolution, 256) for which one texel spans at most this many render "
                   "pixels (the map's) at the receivers in view, divided by the light's share of the irradiance "
                   "there (a faint shadow's edge may move further), so a light near what it lights, far from the "
                   "eye or outshone gets fewer ([architecture.md](architecture.md), \"Samples and casters by "
                   "need\"); with a mirror in view every light gets the full resolution; 0: every light the full "
                   "resolution");
        return s;
    }();
    return schema;
}

const Schema<FilterParams>& filterKeys() {
    using F = FilterParams;
    static const Schema<F> schema = [] {
        Schema<F> s;
        s.field(&F::blurRadius, "blur_radius", in(0, 16), AAMAP_DEFAULT_BLUR_RADIUS,
                   "box blur radius after the 5x5 Laplacian, in snapshot pixels")
            .field(&F::flatRange, "flat_range", in(0.0, 1.0), AAMAP_DEFAULT_FLAT_RANGE,
                   "the Laplacian counts only where the grey spans at least this over a texel's 3x3 window (1/255: "
                   "one 8-bit code value); flat texels beside an edge, which one ray already renders, get 0 "
                   "([architecture.md](architecture.md), \"The aamap filter chain\"); 0: everywhere, the paper's "
                   "chain")
            .field(&F::noiseFloor, "noise_floor", in(0.0, 1.0), AAMAP_DEFAULT_NOISE_FLOOR,
                   "blurred edge responses below this are smooth shading: map = 0")
            .field(&F::gain, "gain", above(0.0, 1e6), AAMAP_DEFAULT_GAIN,
                   "map = clamp(gain * (blurred - noise_floor), 0, 1)");
        return s;
    }();
    return schema;
}

}  // namespace

const Schema<SnapshotSettings>& snapshotSchema() {
    using S = SnapshotSettings;
    static const Schema<S> schema = [] {
        Schema<S> s;
        s.field(&S::scale, "scale", in(1.0, 4.0), 1.5,
                "snapshot resolution / render resolution (the paper: 768 for 512; a device whose images are "
                "smaller gets the largest scale that fits, with a warning); not the subpixel map's, which "
                "rasterises geometry at `snapshot.subpixel` x the render resolution")
            .field(&S::areaLightSamples, "area_light_samples", in(1, 64), 5,
                   "at most this many point lights approximating each area light (the paper: 5)")
            .field(&S::areaLightSolidAngle, "area_light_solid_angle", in(0.0, 12.6), 0.04,
                   "an area light gets one point sample per this many steradians of its mean solid angle over the "
                   "visible region (at least 1, at most `area_light_samples`; 0: always `area_light_samples`); the "
                   "soft-shadow filter spreads each sample over its patch (docs/architecture.md, \"Samples and "
                   "casters by need\")")
            .field(&S::environmentLights, "environment_lights", in(0, 16), 1,
                   "the environment map's brightest regions shaded as this many shadowed directional lights; the "
                   "rest is an SH ambient term (0: all of it); no effect without a map (docs/architecture.md, "
                   "\"Lights at infinity in the Snapshot\")")
            .include(&S::shadows, shadowKeys())
            .include(&S::filter, filterKeys())
            .choice(&S::map, "map", passes::mapNames(),
                    "what the map is built from: the luminance Laplacian (the paper), G-buffer discontinuities "
                    "(depth, normal, object and material id, shadow-map visibility per light when shadows are on; "
                    "alpha cut-outs are holes), or their per-texel max, each followed by the same blur, dead zone "
                    "and reduction ([architecture.md](architecture.md), \"Geometric aamap\"); or `subpixel`: each "
                    "pixel's predicted one-ray display error from k x k geometry samples and the shading, against "
                    "`metrics.flip_threshold` ([architecture.md](architecture.md), \"Sub-pixel aamap\"; the blur, "
                    "dead zone and `scale` keys do not apply). Only non-default values enter the cache keys")
            .field(&S::subpixel, "subpixel", in(SUBPIXEL_MIN_K, SUBPIXEL_MAX_K), SUBPIXEL_DEFAULT_K,
                   "`map: subpixel`: samples per pixel side k; the Snapshot rasterises geometry (and with "
                   "`subpixel_shading: sample` colour) at k x the render resolution (a device whose images are "
                   "smaller gets the largest k that fits, with a warning). With `map: subpixel`, "
                   "`metrics.flip_threshold` enters the Snapshot's cache key too")
            .choice(&S::subpixelShading, "subpixel_shading", passes::shadingNames(),
                    "`map: subpixel`: `pixel` shades once per render pixel and shares that shade with the pixel's k x "
                    "k geometry samples (shading steps are read from the neighbouring pixels' shades), `sample` "
                    "shades every sample, at k^2 times the shading work ([architecture.md](architecture.md), "
                    "\"Sub-pixel aamap\")");
        return s;
    }();
    return schema;
}

SnapshotSettings::SnapshotSettings() { snapshotSchema().setDefaults(*this); }

const std::vector<ParamSpec>& snapshotParams() { return snapshotSchema().specs(); }

}  // namespace aamap
