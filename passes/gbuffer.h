#pragma once
// The Snapshot raster: the scene's mesh with Lambert shading from point lights (and cosine-lobe
// point samples of area lights) plus emission, into linear colour and depth. Holds the scene's
// GPU state (vertices, materials, lights) so that several views reuse it.
#include <span>
#include <string>

#include "engine/graph/render_graph.h"
#include "engine/vk/graph_executor.h"
#include "engine/vk/pipeline.h"
#include "engine/vk/resources.h"
#include "scene/camera.h"
#include "scene/scene.h"

namespace aamap::passes {

class GBufferPass {
public:
    static constexpr graph::Format kColourFormat = graph::Format::RGBA32Float;
    static constexpr graph::Format kDepthFormat = graph::Format::D32Float;

    GBufferPass(VulkanContext& context, const Scene& scene);  // uploads the mesh with its materials
    // Uploads the light list; throws std::invalid_argument past GBUFFER_MAX_LIGHTS (256).
    void setLights(std::span<const PointLight> lights);

    // Declares the pass "gbuffer" (writes `colour` and `depth`) and registers its recording for
    // the camera with the given clip planes. This object must outlive execution.
    graph::PassId add(graph::RenderGraph& graph, vk::GraphExecutor& executor, const std::string& colour,
                      const std::string& depth, const PinholeCamera& camera, float nearPlane, float farPlane) const;

    std::uint32_t vertexCount() const { return vertexCount_; }
    std::uint32_t lightCount() const { return lightCount_; }

private:
    VulkanContext* context_;
    vk::Pipeline pipeline_;
    vk::Buffer vertices_, lights_;
    std::uint32_t vertexCount_ = 0;
    std::uint32_t lightCount_ = 0;
};

}  // namespace aamap::passes
