#pragma once
// The `snapshot` config section, declared once: each key bound to the SnapshotSettings field that
// holds it (core/schema.h), with its range, default and doc. The struct's defaults, the config
// reader, --set, the CLI options of `aamap snapshot`, --help, the cache keys and docs/config.md's
// key table are generated from snapshotSchema(). No Vulkan: the config reader links only this.
#include <string>
#include <vector>

#include "core/params.h"
#include "core/schema.h"
#include "passes/filter_params.h"

namespace aamap {
namespace passes {

// Which edges the aamap is built from (config snapshot.map; passes/geometric_aamap.h).
// Subpixel: the predicted one-ray error from k x k samples per pixel (passes/subpixel_map.h).
enum class AamapSource { Luminance, Geometric, Combined, Subpixel };
const char* toString(AamapSource source);  // the config's name: "luminance", "geometric", ...
bool parse(const std::string& name, AamapSource& source);  // false for an unknown name

// Where the subpixel map's colour comes from (config snapshot.subpixel_shading): Pixel shades
// once per render pixel and shares that shade with the pixel's k x k geometry samples; Sample
// shades every sample (the raster at k x the render resolution). glsl/shared/subpixel_map.h.
enum class SubpixelShading { Pixel, Sample };
const char* toString(SubpixelShading shading);  // "pixel", "sample"
bool parse(const std::string& name, SubpixelShading& shading);  // false for an unknown name

}  // namespace passes

// Shadow cube maps, one per point light and per area-light sample.
struct ShadowSettings {
    bool enabled = true;     // no lights: no shadow pass either way
    int resolution = 256;    // texels per cube-face side at most (each light's by need, texelPixels)
    // Each light's faces get the fewest texels for which one spans at most this many render
    // pixels (the map's) at the receivers in view, for a shadow edge of full contrast (passes/view_budget.h
    // shadowFaceSizes); 0: every light at `resolution`. The config key snapshot.shadow_texel_pixels.
    float texelPixels = 1.0f;
    float depthBias = 0.5f;  // constant bias, in shadow-map texels at the receiver
    float slopeBias = 1.0f;  // times tan(incidence angle), in texels (slope-scaled bias)
    int pcf = 1;             // percentage-closer filter kernel side in texels; 1 = one tap
    // Area-light samples filter their lookups over the penumbra of the patch of the light each
    // stands for (PCSS): smooth penumbrae. Point and spot lights keep the pcf lookup either way.
    // The config key snapshot.soft_shadows.
    bool softShadows = true;
    bool operator==(const ShadowSettings&) const = default;
};

// What one Snapshot run takes. The `snapshot` config section binds its fields (snapshotSchema(),
// which declares each key's default, the filter's from glsl/shared/aamap_filter.h): the config
// holds this struct, and the passes read it. The run's own choices (exposure, the FLIP
// threshold, read-backs) sit beside the keys.
struct SnapshotSettings {
    SnapshotSettings();  // snapshotSchema()'s defaults

    float scale;           // snapshot resolution / render resolution (768 for 512); not the subpixel map's
    int areaLightSamples;  // at most this many point samples per area light (the paper used 5)
    // One sample per this many steradians of an area light's mean solid angle over the visible
    // region (passes/view_budget.h); 0: every area light gets areaLightSamples.
    float areaLightSolidAngle;
    // The environment map's brightest regions shaded as this many shadowed directional lights
    // (0..16; 0: the whole map goes to the SH ambient term). passes/environment_lighting.h.
    int environmentLights;
    FilterParams filter;  // blur_radius, flat_range, noise_floor, gain; exposure from image.exposure
    bool keepDebugImages = true;  // also read back snapshot colour and laplacian
    // Also build and read back the aamap's block-sum tables (passes/block_sums.h) for adaptive
    // subsampling; false leaves the block-sum passes culled.
    bool blockSums = false;
    // Edges the aamap is built from: the luminance Laplacian (the paper), G-buffer
    // discontinuities, or their max (passes/geometric_aamap.h), or the subpixel prediction.
    passes::AamapSource map;
    // The subpixel map: k x k geometry samples per render pixel (that raster runs at k x the
    // render resolution; `scale` does not apply), and the FLIP threshold its predicted error is held
    // against (glsl/shared/subpixel_map.h; metrics.flip_threshold).
    int subpixel;
    passes::SubpixelShading subpixelShading;  // one shade per pixel, or one per sample
    float flipThreshold = 0.1f;
    ShadowSettings shadows;  // soft_shadows, shadow_texel_pixels
    bool operator==(const SnapshotSettings&) const = default;
};

const Schema<SnapshotSettings>& snapshotSchema();
const std::vector<ParamSpec>& snapshotParams();  // snapshotSchema().specs()

}  // namespace aamap
