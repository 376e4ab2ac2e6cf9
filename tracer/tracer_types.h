#pragma once
// The tracer's vocabulary: the plain settings, count and result types shared by the public entry
// (tracer/tracer.h) and the tracer's internal headers. Internal code includes this header, not
// tracer.h, so that it does not depend on the Tracer class it is part of.
#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>

#include "core/image.h"
#include "tracer/irradiance_cache.h"
#include "tracer/pixel_filter.h"

namespace aamap {

// How a hit is shaded (docs/tracer.md). Direct: emission + direct light + mirror/glass recursion,
// no indirect diffuse. Path: unbiased path tracing (NEE + MIS + Russian roulette), the ground
// truth. Cache: Direct plus indirect diffuse from the irradiance cache.
enum class ShadingMode { Direct, Path, Cache };
const char* toString(ShadingMode mode);  // shading.mode's name (tracer/shading_params.cpp declares them)

// Direct/Cache with more than LightSet::kFewLights lights: how each shadow sample picks its light.
// Power: the global power CDF (the pre-existing behaviour, kept for comparison). Contribution: a
// per-hit CDF over each light's estimated unoccluded contribution there (docs/tracer.md).
enum class LightSelection { Power, Contribution };

// Where an area light's samples go (ShadingSettings::lightSampling). SolidAngle: uniform over the
// solid angle the light subtends at the receiver, for lights of few triangles in whose near field
// the receiver is (else by area); Area: uniform over the light's area; Auto: SolidAngle in Direct
// and Cache modes, whose many samples per hit make the light the noise, Area in Path mode, where
// one light sample per vertex is a small part of a path's noise. docs/tracer.md, "Light sampling".
enum class LightSampling { Auto, SolidAngle, Area };
// shading.light_sampling's names (auto, solid_angle, area); false for an unknown name.
// Declared with the config section (tracer/shading_params.h).
bool parse(const std::string& name, LightSampling& sampling);

// How a textured albedo is looked up (ShadingSettings::textureFilter).
enum class TextureFilter { Anisotropic, None };

// The `shading` config section binds these fields (tracer/shading_params.cpp); each initializer is
// the key's default.
struct ShadingSettings {
    int areaLightSamples = 16;  // stratified shadow-ray samples per area light per hit (rounded to a square)
    ShadingMode mode = ShadingMode::Direct;
    // Path: longest path in segments, as Mitsuba's max_depth (1: emitters only, 2: direct light).
    int maxDepth = 5;
    bool russianRoulette = true;  // Path: from segment `rouletteDepth` on, paths die by throughput
    int rouletteDepth = 5;        // Mitsuba's rr_depth default
    // Direct/Cache: mirror and glass bounces followed per primary ray (glass splits into both).
    int maxSpecularDepth = 8;
    // Direct/Cache: glossy lobes up to this roughness (GGX alpha) reflect the scene through BSDF
    // samples (shading.glossy_reflection_alpha).
    float glossyReflectionAlpha = 0.2f;
    // Camera rays see no emitter, as Mitsuba's hide_emitters: a camera ray's hit adds no emission
    // (the surface still reflects) and a camera ray that escapes is black. Paths that bounce first
    // (a mirror's reflection of the light) see emitters as always.
    bool hideEmitters = false;
    // Cache: the irradiance cache (-ab -ad -as -aa -ar; bounces 0 = no cache, shades as Direct).
    IrradianceCacheSettings cache;
    LightSelection lightSelection = LightSelection::Contribution;  // many lights only (see above)
    LightSampling lightSampling = LightSampling::Auto;
    // Textured albedo: filtered over each ray's footprint (a ray cone, docs/tracer.md "Texture
    // filtering"), or the plain bilinear texel at the hit point (None).
    TextureFilter textureFilter = TextureFilter::Anisotropic;
    // Path mode: after a non-delta BSDF sample of pdf p, the path's ray cone spreads at least this
    // fraction of the sampled lobe's width, 2 sqrt(1 / (pi p)) radians (the full angle of a cone
    // of solid angle 1 / p): textures seen in indirect light are filtered over a share of the
    // lobe the bounce integrates over, not over a camera pixel. 0: the camera's spread throughout.
    float bounceFootprint = 0.25f;
    bool operator==(const ShadingSettings&) const = default;
};

// The footprint a ray carries for texture filtering: its width `width` at the origin, growing by
// `spread` per unit distance. Camera rays start at width 0 with the angle their share of the
// pixel subtends; a zero cone filters nothing.
struct RayCone {
    float width = 0.0f;
    float spread = 0.0f;
    float at(float distance) const { return width + spread * distance; }
};

struct RayCounts {
    std::uint64_t primary = 0;
    std::uint64_t shadow = 0;
    std::uint64_t other = 0;
    std::uint64_t total() const { return primary + shadow + other; }
};

// Cache mode: the irradiance cache built for one render (docs/irradiance-cache.md, "Wiring").
struct CacheStats {
    bool built = false;                 // false: no cache (other modes, or bounces 0)
    int gridWidth = 0, gridHeight = 0;  // the candidate grid of camera rays
    std::size_t candidates = 0;         // its first hits offered to the pre-pass
    std::size_t records = 0;            // records after the pre-pass (all levels)
    std::size_t probed = 0;             // points the probe render found uncovered, offered as candidates too
    double prepassSeconds = 0.0;        // candidates + pre-pass + probe; part of TraceResult::seconds
    RayCounts prepassRays;              // candidate camera rays (primary) and pre-pass rays; NOT in TraceResult::rays
    RayCounts probeRays;                // the probe render's own rays; NOT in TraceResult::rays
    std::uint64_t misses = 0;           // lookups during the render that no record covered
    std::uint64_t missRays = 0;         // their hemisphere rays (counted in TraceResult::rays.other)
};

// A finished tile, [x0, x1) x [y0, y1), of the render in progress (TraceSettings::onTileFinished).
struct TileUpdate {
    int x0, y0, x1, y1;
    const ImageRGB& image;
    const Image<std::uint16_t>& primaryRays;
};

struct TraceSettings {
    int width = 512, height = 512;
    std::uint64_t seed = 1;
    int threads = 0;  // 0: all hardware threads
    ShadingSettings shading;
    // Where a pixel's primary rays land (tracer/pixel_filter.h): the pixel itself by default.
    PixelFilterSettings filter;
    // Called from worker threads as tiles finish (for progress bars); may be empty.
    std::function<void(int tilesDone, int tilesTotal)> onTileDone;
    // Live previews (the viewer): called from a worker thread as each tile of a tile phase
    // finishes. Only the tile's own pixels may be read (other tiles are in flight); they are final
    // for that phase (multi-phase strategies fill untraced pixels after the last tile). Reading
    // never changes the result. Throwing from it cancels the render: render() rethrows.
    std::function<void(const TileUpdate&)> onTileFinished;
};

struct TraceResult {
    ImageRGB image;                    // linear radiance, finite everywhere
    Image<std::uint16_t> primaryRays;  // primary rays traced per pixel
    Image<std::uint8_t> traced;        // 1: estimated from rays at this pixel, 0: interpolated
    // Strategies that split their samples (StrategyDescriptor::splitsHalves, n >= 2): the
    // difference of two independent half images (SampleSource::pixelHalves); else empty.
    ImageRGB halfDifference;
    std::string strategy;              // the strategy with its resolved parameters, one line
    RayCounts rays;
    std::uint64_t nonFiniteSamples = 0;  // NaN/Inf samples dropped (counted, never written)
    double seconds = 0.0;
    CacheStats cache;
};

}  // namespace aamap
