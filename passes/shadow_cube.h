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
//   * one rendering instance for all faces of all lights is the cheapest way to rasterise them
//     on lavapipe (no per-face or per-light begin/end and clear; multiview is capped at 6 views
//     there, so it would still need one rendering per light).
// Face sizes by need: light i's faces fill the top-left SceneGpu::shadowFaceSizes()[i]^2 texels
// of its layers (passes/view_budget.h shadowFaceSizes; the viewport changes per light), so a light
// that needs few texels rasterises few fragments; the array is as large as the largest face.
// Per-face culling: each face draws only the triangles that can reach its 90-degree pyramid, from
// an index list built on the CPU once per light set (one indexed draw per face, firstInstance =
// its layer). A triangle lies in one or two faces of most lights, so large scenes shade about a
// quarter of the vertices an instanced draw of every triangle to every face would (the
// conference room: 331k triangles x 36 faces).
// Shared positions: the scene's vertices (passes/scene_gpu.h) are unindexed (three per triangle, each with its
// triangle's normal and material), but the depth raster needs only positions. Unless the scene
// has alpha masks, the pass draws the distinct positions (12-byte stride,
// SceneGpu::positionBuffer) through the face lists remapped onto them, so lavapipe's vertex
// cache (per batch of indices) shades a shared corner once rather than once per triangle: the
// vertex stage, single-threaded there, is what limits this pass on large scenes.
// The pass exists only when the scene has lights and shadows are on; each face stores near/ma
// (see glsl/shared/snapshot_interface.h). A scene with alpha-masked textures gets the masked
// variant (shadow_cube.masked.*), which binds the scene's atlas and discards cut-out texels.
#include <cstdint>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include <glm/vec3.hpp>

#include "engine/graph/render_graph.h"
#include "engine/vk/graph_executor.h"
#include "engine/vk/pipeline.h"
#include "passes/scene_gpu.h"
#include "passes/snapshot_graph.h"
#include "passes/view_budget.h"

namespace aamap::passes {

class ShadowCubePass {
public:
    static constexpr graph::Format kFormat = graph::Format::D32Float;

    // Throws EnvironmentError when the device lacks shaderOutputLayer (Vulkan 1.2 feature).
    explicit ShadowCubePass(VulkanContext& context);

    // Declares `resource` (faceSize^2, 6 layers per light; each light's faces at its
    // SceneGpu::shadowFaceSizes(), at most faceSize) and the pass "shadow" that renders the
    // cube maps of `scene`'s lights (lightNames: one per light, for --explain) from its
    // vertices. Throws std::invalid_argument past the device's layer limits. `scene` and this
    // object must outlive execution.
    // view: when not null, each face draws only the triangles that can shadow a point in that
    // frustum (passes/view_budget.h cullShadowCasters; cullRadii[i]: how far light i's patch
    // reaches from it, 0 for a point); null: every triangle of the face, for views the frustum
    // does not cover (mirrors).
    graph::PassId add(graph::RenderGraph& graph, vk::GraphExecutor& executor, const std::string& resource,
                      const SceneGpu& scene, std::span<const std::string> lightNames, std::uint32_t faceSize,
                      float nearPlane, const ViewFrustum* view = nullptr, std::span<const float> cullRadii = {});

    // The index list of each face (layer 6i+f): triangles of `positions` (three vertices each) not
    // entirely outside one side of the face's pyramid from light i, nor entirely nearer than
    // nearPlane along its axis. Ranges index into `indices`.
    struct FaceLists {
        std::vector<std::uint32_t> indices;
        std::vector<std::pair<std::uint32_t, std::uint32_t>> ranges;  // (first, count) per layer
    };
    // directional[i] != 0: light i is directional, its one orthographic map (face 0) takes every
    // triangle and faces 1..5 none; empty: all point lights.
    static FaceLists cullPerFace(std::span<const glm::vec3> positions, std::span<const glm::vec3> lights,
                                 float nearPlane, std::span<const std::uint8_t> directional = {});

private:
    // The variant `scene` needs: shared positions, or masked when it has alpha masks.
    vk::Pipeline& pipelineSlot(const SceneGpu& scene) const { return pipelines_[scene.alphaMasked() ? 1 : 0]; }
    void buildPipeline(const SceneGpu& scene) const;  // the executor's prepare step
    void updateFaceLists(const SceneGpu& scene, float nearPlane, const ViewFrustum* view,
                         std::span<const float> cullRadii);

    VulkanContext* context_;
    // Built when the pass is kept: shared positions (12-byte stride), or masked (alpha test, the
    // scene's textured vertices). Index: 0, 1.
    mutable vk::Pipeline pipelines_[2];
    std::uint32_t maxLayers_ = 0;
    // Face lists for (scene, its light set, near plane), rebuilt when any of them changes (indices
    // into the scene's unshared positions), then culled for the view and uploaded.
    FaceLists baseLists_;
    bool viewListsValid_ = false;
    bool listsCulled_ = false;
    ViewFrustum listsView_;
    std::vector<float> listsRadii_;
    vk::Buffer faceIndices_;
    std::vector<std::pair<std::uint32_t, std::uint32_t>> faceRanges_;
    const SceneGpu* listsScene_ = nullptr;
    std::uint64_t listsVersion_ = 0;
    float listsNear_ = -1.0f;
};

}  // namespace aamap::passes
