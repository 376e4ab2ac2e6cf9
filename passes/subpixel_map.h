#pragma once
// The sub-pixel aamap (config snapshot.map: subpixel): the Snapshot rasterises geometry at k times
// the render resolution and colour either once per render pixel (shared shading) or at k times too,
// and one compute pass turns each render pixel's k x k samples into its predicted one-ray display
// error and the map value (rule: glsl/shared/subpixel_map.h).
// No Laplacian, blur or reduction: the pass writes the render-resolution aamap itself.
// GpuSubpixelMap runs the pass on host images (GPU-vs-CPU tests against passes/cpu_subpixel.h).
#include <memory>
#include <string>

#include "core/image.h"
#include "engine/vk/graph_executor.h"
#include "engine/vk/pipeline.h"
#include "glsl/shared/subpixel_map.h"
#include "passes/cpu_geometric.h"

namespace aamap::passes {

struct SubpixelSettings {
    int k = 2;              // samples per pixel side, [SUBPIXEL_MIN_K, SUBPIXEL_MAX_K]
    float exposure = 1.0f;  // the display transform's
    float tolerance = 0.0f; // tau, subpixelTolerance(FLIP threshold)
    bool shared = true;     // colour W x H, one shade per pixel (rule 2'); false: k W x k H
};

class SubpixelMapPass {
public:
    explicit SubpixelMapPass(VulkanContext& context);
    // Declares kSubpixelGeometry and two passes: "subpixel_geometry" reads `normalDepth` and `ids`
    // (k W x k H) and writes the geometry flags; "subpixel_map" reads them and `colour` (W x H when
    // settings.shared, else k W x k H) and writes `output` (r32f, W x H). Returns the latter.
    graph::PassId add(graph::RenderGraph& graph, vk::GraphExecutor& executor, const std::string& colour,
                      const std::string& normalDepth, const std::string& ids, const std::string& output,
                      const SubpixelSettings& settings) const;

private:
    VulkanContext* context_;
    mutable vk::Pipeline geometry_[SUBPIXEL_MAX_K + 1];      // by k, built when such a pass is kept
    mutable vk::Pipeline pipelines_[SUBPIXEL_MAX_K + 1][2];  // by k and shared, likewise
};

// The pass alone on host images: colour and geometry k W x k H, the map W x H.
class GpuSubpixelMap {
public:
    explicit GpuSubpixelMap(VulkanContext& context);
    ~GpuSubpixelMap();
    ImageGrey map(const ImageRGB& colour, const cpu::GeometryImages& geometry, const SubpixelSettings& settings);

private:
    SubpixelMapPass pass_;
    std::unique_ptr<vk::GraphExecutor> executor_;
};

}  // namespace aamap::passes
