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

// The shadow cube maps the G-buffer samples (see passes/shadow_cube.h); empty resource: none.
struct GBufferShadows {
    std::string resource;  // D32 2D array, layers 6i..6i+5 for light i
    float nearPlane = 0.0f;
    std::uint32_t faceSize = 0;
    float depthBias = 0.0f, slopeBias = 0.0f;  // in shadow-map texels at the receiver
    std::uint32_t pcf = 1;
};

class GBufferPass {
public:
    static constexpr graph::Format kColourFormat = graph::Format::RGBA32Float;
    static constexpr graph::Format kDepthFormat = graph::Format::D32Float;

    GBufferPass(VulkanContext& context, const Scene& scene);  // uploads the mesh with its materials
    // Uploads the light list; throws std::invalid_argument past GBUFFER_MAX_LIGHTS (256).
    void setLights(std::span<const PointLight> lights);

    // Declares the pass "gbuffer" (writes `colour` and `depth`, reads the shadow maps if any) and
    // registers its recording for the camera with the given clip planes. This object must outlive
    // execution.
    graph::PassId add(graph::RenderGraph& graph, vk::GraphExecutor& executor, const std::string& colour,
                      const std::string& depth, const PinholeCamera& camera, float nearPlane, float farPlane,
                      const GBufferShadows& shadows = {});

    std::uint32_t vertexCount() const { return vertexCount_; }
    std::uint32_t lightCount() const { return lightCount_; }
    // For the shadow pass, which draws the same vertices from the same lights.
    const vk::Buffer& vertexBuffer() const { return vertices_; }
    const vk::Buffer& lightBuffer() const { return lights_; }
    static constexpr std::uint32_t kVertexStride = 48;

private:
    VulkanContext* context_;
    vk::Pipeline pipeline_;
    vk::Pipeline shadowedPipeline_;  // built on first use: scenes without lights never need it
    vk::Buffer vertices_, lights_;
    std::uint32_t vertexCount_ = 0;
    std::uint32_t lightCount_ = 0;
};

}  // namespace aamap::passes
