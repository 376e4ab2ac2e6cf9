#pragma once
// Shadow cube maps for the Snapshot's point lights (and the point samples of area lights).
//
// One pass, "shadow", writes one D32 2D-array resource with six layers per light (light i owns
// layers 6i..6i+5) in a single instanced draw: instance 6i+f goes to layer 6i+f through gl_Layer
// from the vertex shader. Why one pass and one resource rather than one per light:
//   * the G-buffer must bind every light's map, and a push-descriptor set holds at most
//     maxPushDescriptors (32 on lavapipe) descriptors, while the light buffer takes 256 lights;
//     one array image is one binding for any number of lights;
//   * the graph allows one initial writer per resource, so per-light passes could not share it;
//   * one draw and one rendering instance for all faces of all lights is the cheapest way to
//     rasterise them on lavapipe (no per-face or per-light begin/end, clear and draw overhead;
//     multiview is capped at 6 views there, so it would still need one rendering per light).
// The pass exists only when the scene has lights and shadows are on; each face stores near/ma
// (see glsl/shared/snapshot_interface.h).
#include <cstdint>
#include <span>
#include <string>

#include "engine/graph/render_graph.h"
#include "engine/vk/graph_executor.h"
#include "engine/vk/pipeline.h"
#include "passes/gbuffer.h"

namespace aamap::passes {

inline const std::string kShadowPass = "shadow";
inline const std::string kShadowCubes = "shadow.cubes";

class ShadowCubePass {
public:
    static constexpr graph::Format kFormat = graph::Format::D32Float;

    // Throws EnvironmentError when the device lacks shaderOutputLayer (Vulkan 1.2 feature).
    explicit ShadowCubePass(VulkanContext& context);

    // Declares `resource` (faceSize^2, 6 layers per light) and the pass "shadow" that renders the
    // cube maps of `geometry`'s lights (lightNames: one per light, for --explain) from its
    // vertices. Throws std::invalid_argument past the device's layer limits. `geometry` and this
    // object must outlive execution.
    graph::PassId add(graph::RenderGraph& graph, vk::GraphExecutor& executor, const std::string& resource,
                      const GBufferPass& geometry, std::span<const std::string> lightNames, std::uint32_t faceSize,
                      float nearPlane) const;

private:
    VulkanContext* context_;
    vk::Pipeline pipeline_;
    std::uint32_t maxLayers_ = 0;
};

}  // namespace aamap::passes
