#include "tracer/shading_params.h"

namespace aamap {

namespace {

const std::vector<std::pair<std::string, ShadingMode>>& modeNames() {
    static const std::vector<std::pair<std::string, ShadingMode>> names = {
        {"direct", ShadingMode::Direct}, {"path", ShadingMode::Path}, {"cache", ShadingMode::Cache}};
    return names;
}

const std::vector<std::pair<std::string, PixelFilterType>>& filterNames() {
    static const std::vector<std::pair<std::string, PixelFilterType>> names = {
        {"box", PixelFilterType::Box}, {"tent", PixelFilterType::Tent}, {"gaussian", PixelFilterType::Gaussian}};
    return names;
}

const std::vector<std::pair<std::string, PixelFilterMode>>& filterModeNames() {
    static const std::vector<std::pair<std::string, PixelFilterMode>> names = {
        {"convolution", PixelFilterMode::Convolution}, {"importance", PixelFilterMode::Importance}};
    return names;
}

template <class E>
const char* nameOf(const std::vector<std::pair<std::string, E>>& names, E value) {
    for (const auto& n : names)
        if (n.second == value) return n.first.c_str();
    return "?";
}

const std::vector<std::pair<std::string, LightSampling>>& samplingNames() {
    static const std::vector<std::pair<std::string, LightSampling>> names = {
        {"auto", LightSampling::Auto}, {"solid_angle", LightSampling::SolidAngle}, {"area", LightSampling::Area}};
    return names;
}

template <class E>
bool parseName(const std::vector<std::pair<std::string, E>>& names, const std::string& name, E& value) {
    for (const auto& n : names)
        if (n.first == name) {
            value = n.second;
            return true;
        }
    return false;
}

}  // namespace

// Each default is the struct's initializer (D), so the tracer's settings have one.
const Schema<ShadingSettings>& shadingSchema() {
    using S = ShadingSettings;
    static const Schema<S> schema = [] {
        const S D{};
        Schema<S> s;
        s.field(&S::areaLightSamples, "area_light_samples", in(1, 4096), D.areaLightSamples,
                "shadow rays per area light per hit (rounded to a square)")
            .choice(&S::mode, "mode", modeNames(),
                    "`direct`: emission, direct light, mirror/glass; `path`: unbiased path tracing (the ground "
                    "truth); `cache`: direct plus an irradiance cache")
            .field(&S::maxDepth, "max_depth", in(1, kMaxPathDepth), D.maxDepth,
                   "`path`: longest path in segments; unset, a Mitsuba scene's integrator decides ([Mitsuba "
                   "scenes](#mitsuba-scenes))")
            .field(&S::russianRoulette, "russian_roulette", D.russianRoulette,
                   "`path`")
            .field(&S::rouletteDepth, "roulette_depth", in(1, kMaxPathDepth), D.rouletteDepth,
                   "`path`: roulette from this segment on; unset, a Mitsuba scene's integrator decides")
            .field(&S::hideEmitters, "hide_emitters", D.hideEmitters,
                   "the tracer's camera rays see no emitter (the Snapshot still shows them): area lights add no "
                   "emission and the environment is black where seen directly (reflections keep both); unset, a "
                   "Mitsuba scene's integrator decides")
            .field(&S::maxSpecularDepth, "max_specular_depth", in(0, 1024), D.maxSpecularDepth,
                   "`direct`/`cache`: mirror and glass bounces")
            .field(&S::glossyReflectionAlpha, "glossy_reflection_alpha", in(0.0, 1.0), D.glossyReflectionAlpha,
                   "`direct`/`cache`: glossy lobes up to this roughness (GGX alpha; a Phong exponent n counts as "
                   "sqrt(2 / (n + 2))) reflect the scene through BSDF samples; rougher ones are light-sampled only, "
                   "their reflection of the scene a blur left out like diffuse interreflection")
            .choice(&S::lightSelection, "light_selection",
                    {{"contribution", LightSelection::Contribution}, {"power", LightSelection::Power}},
                    "with more than 8 lights, which light each shadow ray goes to: `contribution` picks per hit by "
                    "each light's estimated unoccluded contribution there, `power` by global power (docs/tracer.md)")
            .choice(&S::lightSampling, "light_sampling", samplingNames(),
                    "where an area light's shadow samples go: `solid_angle` samples a light of up to 8 triangles "
                    "uniformly over the solid angle it subtends wherever a receiver is in its near field (area "
                    "sampling's density there varies more than 4-fold over the light), and by area elsewhere; "
                    "`area` always by area; `auto` is `solid_angle` in `direct` and `cache` modes and `area` in "
                    "`path` (docs/tracer.md, \"Light sampling\")")
            .choice(&S::textureFilter, "texture_filter",
                    {{"anisotropic", TextureFilter::Anisotropic}, {"none", TextureFilter::None}},
                    "textured albedo filtered over each ray's footprint (ray cones, an anisotropic mip-map lookup: "
                    "one ray per pixel on a minified texture shows its pixel average), or the bilinear texel at the "
                    "hit point (docs/tracer.md, \"Texture filtering\")")
            .field(&S::bounceFootprint, "bounce_footprint", in(0.0, 1.0), D.bounceFootprint,
                   "`path`: after a non-delta bounce of pdf p, the ray cone spreads at least this fraction of "
                   "the lobe's width 2 sqrt(1 / (pi p)) radians, so textures in indirect light are filtered over a "
                   "share of what the bounce integrates (coarser mip levels, the same mean); 0 keeps the camera "
                   "pixel's spread (docs/tracer.md, \"Texture filtering\")");
        return s;
    }();
    return schema;
}

const Schema<IrradianceCacheSettings>& shadingCacheSchema() {
    using C = IrradianceCacheSettings;
    static const Schema<C> schema = [] {
        const C D{};
        Schema<C> s;
        s.field(&C::bounces, "bounces", in(0, 16), D.bounces,
                "`cache`: diffuse bounces through the irradiance cache (Radiance `-ab`); each level's records "
                "gather from the next; 0 shades as `direct`; B bounces render the light transport of `path` with "
                "`max_depth` B + 2")
            .field(&C::divisions, "divisions", in(4, 1 << 16), D.divisions,
                   "`cache`: hemisphere samples of a record (`-ad`)")
            .field(&C::supersamples, "supersamples", in(0, 1 << 16), D.supersamples,
                   "`cache`: extra hemisphere samples to the cells with the largest differences (`-as`)")
            .field(&C::accuracy, "accuracy", above(0.0, 1.0), D.accuracy,
                   "`cache`: a record is used where its error is below this (`-aa`); smaller: more records, "
                   "smoother and slower")
            .field(&C::resolution, "resolution", in(0, 1 << 16), D.resolution,
                   "`cache`: minimum record radius = scene size / resolution (`-ar`; 0: no minimum)")
            .field(&C::gridStep, "grid_step", in(1, 64), D.gridStep,
                   "`cache`: the pre-pass seeds records from one camera ray per grid_step x grid_step pixels (at "
                   "least a 32 x 32 grid)");
        return s;
    }();
    return schema;
}

const Schema<PixelFilterSettings>& pixelFilterSchema() {
    using P = PixelFilterSettings;
    static const Schema<P> schema = [] {
        const P D{};
        Schema<P> s;
        s.choice(&P::type, "filter", filterNames(),
                 "pixel reconstruction filter of every traced image (renders, reference, the map-quality 1-ray "
                 "image), for every strategy, applied as `image.filter_mode` says. Box of radius 0.5 is the pixel "
                 "itself; Mitsuba 3's default is `gaussian` with stddev 0.5. The Snapshot is not filtered "
                 "(docs/tracer.md, \"Pixel filters\")")
            .field(&P::radius, "filter_radius", in(0.0, 8.0), D.radius,
                   "half-width in pixels; 0: the filter's own (box 0.5, tent 1, gaussian 4 x stddev as Mitsuba)")
            .field(&P::stddev, "filter_stddev", above(0.0, 4.0), D.stddev,
                   "gaussian only (an error with another filter): the standard deviation in pixels; the Gaussian "
                   "minus its value at the radius, clamped at 0, as pbrt and Mitsuba")
            .choice(&P::mode, "filter_mode", filterModeNames(),
                    "how the filter applies. `convolution`: the strategy renders box pixels, then the image is "
                    "convolved with the filter's mass over each pixel cell, so neighbours share samples as a "
                    "splatting film (Mitsuba's) does: less noise for the same rays (uniform 64 in path mode: 0.60 % "
                    "pixels above FLIP 0.1 against 1.33 %, docs/results.md). `importance`: film positions drawn "
                    "from the filter (pbrt-v4), each pixel the mean of its own samples. Both are the same image for "
                    "the box of radius 0.5 (docs/tracer.md, \"Pixel filters\")");
        return s;
    }();
    return schema;
}

const std::vector<ParamSpec>& shadingParams() { return shadingSchema().specs(); }
const std::vector<ParamSpec>& shadingCacheParams() { return shadingCacheSchema().specs(); }

bool parse(const std::string& name, ShadingMode& mode) { return parseName(modeNames(), name, mode); }
bool parse(const std::string& name, LightSampling& sampling) { return parseName(samplingNames(), name, sampling); }

const char* toString(ShadingMode mode) { return nameOf(modeNames(), mode); }
const char* toString(PixelFilterType type) { return nameOf(filterNames(), type); }
const char* toString(PixelFilterMode mode) { return nameOf(filterModeNames(), mode); }
bool parse(const std::string& name, PixelFilterType& type) { return parseName(filterNames(), name, type); }
bool parse(const std::string& name, PixelFilterMode& mode) { return parseName(filterModeNames(), name, mode); }

}  // namespace aamap
