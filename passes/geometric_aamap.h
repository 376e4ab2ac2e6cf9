#pragma once
// The geometric aamap (beyond the paper): edges where the G-buffer is discontinuous -- depth,
// normal, object and material id, shadow occlusion mask (glsl/shared/geometric_edges.h; alpha
// cut-outs are uncovered texels) -- replace the luminance
// Laplacian (Geometric) or join it by a per-texel max (Combined); the luminance chain's blur,
// dead zone and reduction follow unchanged. addAamapChain() assembles the Snapshot's map chain
// for each source; GpuGeometricEdges runs the edge pass on host images (GPU-vs-CPU tests).
#include <memory>
#include <string>

#include "core/image.h"
#include "engine/vk/graph_executor.h"
#include "engine/vk/pipeline.h"
#include "passes/cpu_geometric.h"
#include "passes/filter_params.h"
#include "passes/geometry_buffer.h"
#include "passes/gpu_aamap.h"
#include "passes/snapshot_graph.h"
#include "passes/snapshot_params.h"
#include "passes/subpixel_map.h"

namespace aamap::passes {

// AamapSource, which edges the aamap is built from: passes/snapshot_params.h (config snapshot.map).

class GeometricEdgePass {
public:
    explicit GeometricEdgePass(VulkanContext& context);
    // Declares the pass "geometric_edges": reads the geometry images (and `laplacian` unless
    // empty: the combined variant), writes `output` (r32f, sized like the geometry images).
    graph::PassId add(graph::RenderGraph& graph, vk::GraphExecutor& executor, const std::string& normalDepth,
                      const std::string& ids, const std::string& laplacian, const std::string& output) const;

private:
    VulkanContext* context_;
    mutable vk::Pipeline geometric_, combined_;  // built when the pass is kept
};

struct MapChainInputs {
    std::string colour;  // the Snapshot's RGBA32F raster
    SnapshotView view;   // the geometry raster's camera, as the G-buffer's
    int width = 0, height = 0;  // render resolution
    FilterParams params;
    GBufferShadows shadows;  // the G-buffer's shadow maps (none: empty resource), for the occlusion mask
    bool greyFromGBuffer = false;  // kGrey is declared and the G-buffer writes it (GBufferGrey)
    SubpixelSettings subpixel;     // the subpixel map: `colour` is k x the render resolution unless shared
};

// Declares grey, laplacian, map and aamap (gpu_aamap.h) and the passes that make the aamap from
// `source`. The geometry raster and edge pass are declared in every mode, so that a luminance
// Snapshot culls them (CompiledGraph::explain says why) and builds nothing for them. The
// subpixel map declares the geometry raster (without the occlusion mask: shadows are in the
// colour) and the subpixel pass, which writes the aamap.
void addAamapChain(graph::RenderGraph& graph, vk::GraphExecutor& executor, const FilterChain& chain,
                   GeometryBufferPass& geometry, const GeometricEdgePass& edges, const SubpixelMapPass& subpixel,
                   AamapSource source, const MapChainInputs& in);

// The edge pass alone on host images.
class GpuGeometricEdges {
public:
    explicit GpuGeometricEdges(VulkanContext& context);
    ~GpuGeometricEdges();
    // laplacian: null for the geometric edges, else the combined max with it.
    ImageGrey edges(const cpu::GeometryImages& geometry, const ImageGrey* laplacian = nullptr);

private:
    GeometricEdgePass pass_;
    std::unique_ptr<vk::GraphExecutor> executor_;
};

}  // namespace aamap::passes
