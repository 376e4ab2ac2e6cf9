#include "tracer/shading_params.h"

namespace aamap {

namespace {

const std::vector<std::pair<std::string, ShadingMode>>& modeNames() {
    static const std::vector<std::pair<std::string, ShadingMode>> names = {
        {"direct", ShadingMode::Direct}, {"path", ShadingMode::Path}, {"cache", ShadingMode::Cache}};
    return names;
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

const Schema<ShadingConfig>& shadingSchema() {
    using S = ShadingConfig;
    static const Schema<S> schema = [] {
        Schema<S> s;
        s.field(&S::areaLightSamples, "area_light_samples", in(1, 4096), 16, "shadow rays per area light per hit")
            .choice(&S::mode, "mode", modeNames(), "direct light, path tracing or an irradiance cache")
            .field(&S::maxDepth, "max_depth", in(1, kMaxPathDepth), 5,
                   "path: longest path in segments; unset: a Mitsuba scene file's integrator decides")
            .field(&S::russianRoulette, "russian_roulette", true, "path")
            .field(&S::rouletteDepth, "roulette_depth", in(1, kMaxPathDepth), 5,
                   "path: roulette from this segment on; unset: a Mitsuba scene file's integrator decides")
            .field(&S::hideEmitters, "hide_emitters", false,
                   "camera rays see no emitter: area lights add no emission and the environment is black where "
                   "seen directly (reflections keep both); unset: a Mitsuba scene file's integrator decides")
            .field(&S::maxSpecularDepth, "max_specular_depth", in(0, 1024), 8, "direct/cache: mirror and glass bounces")
            .field(&S::glossyReflectionAlpha, "glossy_reflection_alpha", in(0.0, 1.0), 0.2,
                   "direct/cache: glossy lobes up to this roughness (GGX alpha; a Phong exponent n counts as "
                   "sqrt(2 / (n + 2))) reflect the scene through BSDF samples; rougher ones are light-sampled only, "
                   "their reflection of the scene a blur left out like diffuse interreflection")
            .choice(&S::lightSelection, "light_selection",
                    {{"contribution", LightSelection::Contribution}, {"power", LightSelection::Power}},
                    "which light a shadow ray goes to")
            .choice(&S::lightSampling, "light_sampling", samplingNames(),
                    "an area light's samples uniform over the solid angle it subtends (near lights of up to 8 "
                    "triangles) or over its area; auto: by solid angle in direct and cache modes, by area in path")
            .choice(&S::textureFilter, "texture_filter",
                    {{"anisotropic", TextureFilter::Anisotropic}, {"none", TextureFilter::None}},
                    "textures filtered over each ray's footprint, or the bilinear texel at the hit");
        return s;
    }();
    return schema;
}

const Schema<ShadingConfig::Cache>& shadingCacheSchema() {
    using C = ShadingConfig::Cache;
    static const Schema<C> schema = [] {
        Schema<C> s;
        s.field(&C::bounces, "bounces", in(0, 16), 1, "diffuse bounces through the cache")
            .field(&C::divisions, "divisions", in(4, 1 << 16), 512, "hemisphere samples of a record")
            .field(&C::supersamples, "supersamples", in(0, 1 << 16), 128,
                   "extra samples to the cells with the largest differences")
            .field(&C::accuracy, "accuracy", above(0.0, 1.0), 0.2, "a record is used where its error is below this")
            .field(&C::resolution, "resolution", in(0, 1 << 16), 64, "minimum record radius = scene size / resolution")
            .field(&C::gridStep, "grid_step", in(1, 64), 4,
                   "the pre-pass takes one camera ray per grid_step x grid_step pixels");
        return s;
    }();
    return schema;
}

ShadingConfig::ShadingConfig() { shadingSchema().setDefaults(*this); }
ShadingConfig::Cache::Cache() { shadingCacheSchema().setDefaults(*this); }

const std::vector<ParamSpec>& shadingParams() { return shadingSchema().specs(); }
const std::vector<ParamSpec>& shadingCacheParams() { return shadingCacheSchema().specs(); }

bool parse(const std::string& name, ShadingMode& mode) { return parseName(modeNames(), name, mode); }
bool parse(const std::string& name, LightSampling& sampling) { return parseName(samplingNames(), name, sampling); }

const char* toString(ShadingMode mode) {
    for (const auto& n : modeNames())
        if (n.second == mode) return n.first.c_str();
    return "?";
}

}  // namespace aamap
