#pragma once
// The `snapshot` config section, declared once: each key bound to the SnapshotConfig field that
// holds it (core/schema.h), with its range, default and doc. The structs' defaults, the config
// reader, --set, the CLI options of `aamap snapshot`, --help, the cache keys and docs/config.md's
// rows are generated from snapshotSchema(). No Vulkan: the config reader links only this.
#include <string>
#include <vector>

#include "core/params.h"
#include "core/schema.h"

namespace aamap {
namespace passes {

// Which edges the aamap is built from (config snapshot.map; passes/geometric_aamap.h).
// Subpixel: the predicted one-ray error from k x k samples per pixel (passes/subpixel_map.h).
enum class AamapSource { Luminance, Geometric, Combined, Subpixel };
const char* toString(AamapSource source);  // the config's name: "luminance", "geometric", ...
bool parse(const std::string& name, AamapSource& source);  // false for an unknown name

}  // namespace passes

// The Snapshot's settings as the config holds them (doubles: the canonical form prints the numbers
// written). Every field's default is its schema default: no second copy here.
struct SnapshotConfig {
    SnapshotConfig();  // snapshotSchema()'s defaults

    double scale;           // snapshot resolution / render resolution
    int areaLightSamples;   // at most this many point lights approximating each area light
    // Steradians of an area light's mean solid angle over the visible region per point sample
    // (passes/view_budget.h); 0: every area light gets areaLightSamples.
    double areaLightSolidAngle;
    // The environment map's brightest regions as this many shadowed directional lights (0: all of
    // it in the SH ambient term); no effect without an environment map.
    int environmentLights;
    // Area-light samples' shadows filtered over the penumbra of their patch of the light
    // (passes/snapshot.h ShadowSettings); false: hard shadows from every sample.
    bool softShadows;
    int blurRadius;         // the aamap filter chain (glsl/shared/aamap_filter.h)
    double flatRange;
    double noiseFloor;
    double gain;
    passes::AamapSource map;  // what the map is built from (passes/geometric_aamap.h)
    int subpixel;             // the subpixel map's samples per pixel side (passes/subpixel_map.h)

    bool operator==(const SnapshotConfig&) const = default;
};

const Schema<SnapshotConfig>& snapshotSchema();
const std::vector<ParamSpec>& snapshotParams();  // snapshotSchema().specs()

}  // namespace aamap
