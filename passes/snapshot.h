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
    // Texels per side of each shadowed light's cube faces (point lights, area-light samples, then
    // directional lights; passes/view_budget.h shadowFaceSizes); empty without the shadow pass.
    std::vector<int> shadowFaceSizes;
    int subpixel = 0;  // the subpixel map's k as run (below the asked k where the device's images are smaller)
    std::vector<std::string> warnings;  // what the Snapshot changed from its settings, and why
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
