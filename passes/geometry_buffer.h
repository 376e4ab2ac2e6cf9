#pragma once
// The geometric aamap's raster: per snapshot texel the world normal (turned towards the camera),
// the view depth, the object and material ids and the shadow occlusion mask (layout:
// glsl/shared/geometric_edges.h). No shading. It draws the scene's vertex buffer (passes/scene_gpu.h),
// so it sees exactly the G-buffer's triangles, with the G-buffer's alpha test on the texture atlas
// (cut-outs are holes here too) and, when the Snapshot has shadow cube maps, the G-buffer's
// shadow lookup per light. The ids of the drawn triangles (the G-buffer's vertices carry none)
// are a small storage buffer, uploaded on first use, so a Snapshot that only asks for the
// luminance map never pays for it.
#include <cstdint>
#include <string>
#include <vector>

#include "engine/graph/render_graph.h"
#include "engine/vk/graph_executor.h"
#include "engine/vk/pipeline.h"
#include "engine/vk/resources.h"
#include "passes/gbuffer.h"
#include "passes/view_budget.h"
#include "passes/scene_gpu.h"
#include "scene/scene.h"
#include "passes/snapshot_graph.h"

namespace aamap::passes {

class GeometryBufferPass {
public:
    static constexpr graph::Format kFormat = graph::Format::RGBA32Float;

    // `sceneGpu` was built from `scene` and must outlive this pass (its vertices, lights and atlas
    // are drawn and bound here). Lists the drawn triangles' ids; no upload yet.
    GeometryBufferPass(VulkanContext& context, const Scene& scene, const SceneGpu& sceneGpu);
    ~GeometryBufferPass();

    // Declares kGeometryNormalDepth, kGeometryIds and kGeometryDepth of `size` and the
    // pass "geometry_buffer", which also reads shadows.resource when that is not empty (the same
    // GBufferShadows the G-buffer got). Must outlive execution. Nothing is uploaded or built
    // unless the graph keeps the pass (the executor's prepare step).
    void add(graph::RenderGraph& graph, vk::GraphExecutor& executor, const graph::Size& size,
             const SnapshotView& view, const GBufferShadows& shadows = {});
    bool prepared() const { return static_cast<bool>(ids_) || triangleCount_ == 0; }

private:
    void prepare();  // uploads the triangle ids once, builds the pipeline the last add() chose
                     // (variant and lighting constants)

    VulkanContext* context_;
    const SceneGpu* scene_;
    vk::Pipeline pipelines_[2];  // unshadowed, shadowed: built on first use
    std::vector<std::uint32_t> builtConstants_[2];  // the lighting constants each was built with
    bool shadowed_ = false;                         // of the last add()
    std::vector<std::uint32_t> constants_;          // of the last add(): SceneGpu::lightingConstants
    std::vector<glm::uvec2> pendingIds_;  // (object, material) per drawn triangle until prepare()
    vk::Buffer ids_;
    std::uint32_t triangleCount_ = 0;
    // The triangles in the last add()'s view frustum (passes/view_budget.h), as an index list in
    // mesh order (ties resolve as in the unculled draw; gl_VertexIndex still names the triangle).
    vk::Buffer viewIndices_;
    std::uint32_t viewIndexCount_ = 0;
    ViewFrustum viewFrustum_;
    bool viewValid_ = false;
};

}  // namespace aamap::passes
