#pragma once
// The Snapshot: rasterise the scene on Vulkan through the render graph, build the aamap on the
// GPU, read it back. This is the integration-facing API; the passes live beside it.
#include <memory>
#include <string>
#include <vector>

#include "core/image.h"
#include "passes/block_sums.h"
#include "passes/filter_params.h"
#include "passes/geometric_aamap.h"
#include "passes/snapshot_params.h"
#include "scene/scene.h"

namespace aamap {

class VulkanContext;  // engine/vk/context.h

// Shadow cube maps, one per point light and per area-light sample (config: snapshot.shadows.*).
struct ShadowSettings {
    bool enabled = true;     // no lights: no shadow pass either way
    int resolution = 256;    // texels per cube-face side
    float depthBias = 0.5f;  // constant bias, in shadow-map texels at the receiver
    float slopeBias = 1.0f;  // times tan(incidence angle), in texels (slope-scaled bias)
    int pcf = 1;             // percentage-closer filter kernel side in texels; 1 = one tap
    // Area-light samples filter their lookups over the penumbra of the patch of the light each
    // stands for (PCSS): smooth penumbrae. Point and spot lights keep the pcf lookup either way.
    bool softShadows = true;
    bool operator==(const ShadowSettings&) const = default;
};

// What one Snapshot run takes: the config's `snapshot` section (passes/snapshot_params.h, every
// value and default there) as the passes read it, and the run's own choices beside it.
struct SnapshotSettings {
    SnapshotSettings() : SnapshotSettings(SnapshotConfig()) {}
    // The config section's values; exposure, flipThreshold and the run's choices keep their defaults.
    explicit SnapshotSettings(const SnapshotConfig& config);

    float scale;           // snapshot resolution / render resolution (768 for 512); not the subpixel map's
    int areaLightSamples;  // at most this many point samples per area light (the paper used 5)
    // One sample per this many steradians of an area light's mean solid angle over the visible
    // region (passes/view_budget.h); 0: every area light gets areaLightSamples.
    float areaLightSolidAngle;
    // The environment map's brightest regions shaded as this many shadowed directional lights
    // (0..16; 0: the whole map goes to the SH ambient term). passes/environment_lighting.h.
    int environmentLights;
    FilterParams filter;
    bool keepDebugImages = true;  // also read back snapshot colour and laplacian
    // Also build and read back the aamap's block-sum tables (passes/block_sums.h) for adaptive
    // subsampling; false leaves the block-sum passes culled.
    bool blockSums = false;
    // Edges the aamap is built from: the luminance Laplacian (the paper), G-buffer
    // discontinuities, or their max (passes/geometric_aamap.h).
    passes::AamapSource map;
    // The subpixel map: k x k samples per render pixel (the raster runs at k x the render
    // resolution; `scale` does not apply), and the FLIP threshold its predicted error is held
    // against (glsl/shared/subpixel_map.h).
    int subpixel;
    float flipThreshold = 0.1f;
    ShadowSettings shadows;
    bool operator==(const SnapshotSettings&) const = default;
};

struct PassTiming {
    std::string pass;
    double gpuMilliseconds = 0.0;  // from timestamp queries
};

struct SnapshotResult {
    ImageRGB snapshot;     // linear colour at snapshot resolution (if keepDebugImages)
    ImageGrey laplacian;   // |L| at snapshot resolution (if keepDebugImages; not for the geometric and subpixel maps)
    ImageGrey edges;       // geometric/combined map: the edge image the blur read (if keepDebugImages)
    ImageGrey aamap;       // render resolution, values in [0,1]
    passes::BlockSumTables blockSums;  // of the aamap, if SnapshotSettings::blockSums (else empty)
    std::vector<PassTiming> passTimes;
    double totalSeconds = 0.0;     // CPU wall time: graph build, upload, execute, readback
    double readbackSeconds = 0.0;  // CPU wall time of the readback alone
    std::string deviceName;
    std::string explain;  // the compiled graph, CompiledGraph::explain(), and each kept pass's purpose
    std::string dot;      // the compiled graph as Graphviz DOT (CompiledGraph::toDot())
    int shadowCubeMaps = 0;  // cube maps rendered: one per shadowed point light / area-light sample
                             // (and per directional light: its orthographic map takes a cube's layers)
    std::vector<int> areaLightSamples;  // the point samples each area light got, in the scene's order
};

// What of the scene the Snapshot cannot show the way the tracer will, one sentence each (curved
// mirror triangles, glass refracting): the aamap is blind there, so a run says so up front.
std::vector<std::string> snapshotLimitations(const Scene& scene);

// Builds the graph for what the scene needs and runs it. Holds per-scene GPU state (vertex
// buffers, pipelines) so that rendering several views or sizes reuses it.
class SnapshotRenderer {
public:
    SnapshotRenderer(VulkanContext& context, const Scene& scene);
    ~SnapshotRenderer();
    SnapshotRenderer(const SnapshotRenderer&) = delete;
    SnapshotRenderer& operator=(const SnapshotRenderer&) = delete;

    SnapshotResult render(const View& view, int width, int height, const SnapshotSettings& settings);

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

}  // namespace aamap
