#pragma once
// The Snapshot raster: the scene's mesh (passes/scene_gpu.h) with Lambert shading from point
// lights (and cosine-lobe point samples of area lights) plus emission, into linear colour and
// depth, for the camera and for the reflected views of planar mirrors.
//
// Depth pre-pass: unless the scene has alpha masks (cut-out texels must not write depth), the
// main view first draws the distinct positions (12-byte vertices, indexed) into depth alone, and
// the shading draw then tests GREATER_OR_EQUAL against it, so each pixel is shaded once however
// many surfaces overlap it. Reflected views (mirrors discard behind their plane) draw as before.
// Where surfaces tie in depth, all of them pass that test and the last drawn wins, so the shading
// draw goes through the triangles in reverse order (same corners, same provoking vertex): the
// first triangle of the mesh wins a tie, as with GREATER and no pre-pass, and the image is the same.
//
// Glass (passes/scene_gpu.h): the camera's view draws it last, over the opaque surfaces it shows,
// depth-tested but not written, blended as F * reflected + (1 - F) * behind with Schlick's F
// (glsl/gbuffer.glsl, GBUFFER_GLASS). Thin panes seen face-on barely change what is behind them,
// as in the tracer; at grazing angles F -> 1, so a glass object's silhouette and rim are in the
// snapshot, and in the aamap. Refraction offsets are not modelled. A device that cannot blend the
// colour format sees through glass as before (glassUnsupported() says why). Mirror views skip glass.
#include <array>
#include <compare>
#include <map>
#include <span>
#include <string>
#include <vector>

#include "engine/graph/render_graph.h"
#include "engine/vk/graph_executor.h"
#include "engine/vk/pipeline.h"
#include "engine/vk/resources.h"
#include "glsl/shared/snapshot_interface.h"
#include "passes/scene_gpu.h"
#include "passes/view_budget.h"
#include "scene/camera.h"

namespace aamap::passes {

// The shadow cube maps the G-buffer samples (see passes/shadow_cube.h); empty resource: none.
struct GBufferShadows {
    std::string resource;  // D32 2D array, layers 6i..6i+5 for light i
    float nearPlane = 0.0f;
    std::uint32_t faceSize = 0;
    float depthBias = 0.0f, slopeBias = 0.0f;  // in shadow-map texels at the receiver
    std::uint32_t pcf = 1;
};

// The grey of step 1 of the aamap (glsl/display_luma.glsl), written by the G-buffer as a second
// attachment when nothing changes the snapshot after it (no mirror composite): the luminance
// pass then has nothing left to do. Empty resource: not written.
struct GBufferGrey {
    std::string resource;  // R32F, the snapshot's size
    float exposure = 1.0f;
};

// One planar mirror's reflected view (passes/mirror.h): the camera's reversed view-projection
// times the reflection in the mirror plane, the reflected eye (for two-sided shading), and the
// plane, xyz . p >= w on the side that is seen in the mirror.
struct ReflectedView {
    glm::mat4 viewProj{1.0f};
    glm::vec3 eye{0.0f};
    glm::vec4 clipPlane{0.0f};
    VkRect2D scissor{};  // the pixels the view must shade (width 0: all)
};

// The camera a Snapshot raster draws from: its clip planes enclose the scene's bounding sphere
// (depth is reversed, so a tiny near plane costs no precision), and sceneSize (the bounding
// box's diagonal) scales the offsets that must not depend on the scene's units.
struct SnapshotView {
    PinholeCamera camera;
    float nearPlane = 0.0f, farPlane = 0.0f;
    float sceneSize = 1.0f;
    // Reversed depth (z' = w - z, cleared to 0, GREATER wins) applied to the camera's projection * view.
    glm::mat4 reversedViewProjection() const;
};

class GBufferPass {
public:
    static constexpr graph::Format kColourFormat = graph::Format::RGBA32Float;
    static constexpr graph::Format kDepthFormat = graph::Format::D32Float;
    static constexpr graph::Format kGreyFormat = graph::Format::R32Float;  // GBufferGrey

    // `scene` must outlive this pass: its buffers are drawn and bound here.
    GBufferPass(VulkanContext& context, const SceneGpu& scene);

    // Declares the pass "gbuffer" (writes `colour` and `depth`, and grey.resource if not empty;
    // reads the shadow maps if any) and registers its recording for the view. cullToView: the
    // opaque draws take only the triangles the view's frustum keeps (passes/view_budget.h; index
    // lists kept for the view until it changes). This object must outlive execution.
    graph::PassId add(graph::RenderGraph& graph, vk::GraphExecutor& executor, const std::string& colour,
                      const std::string& depth, const SnapshotView& view, const GBufferShadows& shadows = {},
                      const GBufferGrey& grey = {}, bool cullToView = false);

    // Declares pass `pass`, which renders the scene once per view into layer i of the layered
    // `colour` and `depth` (the G-buffer's shading, clipped to each view's plane).
    graph::PassId addReflected(graph::RenderGraph& graph, vk::GraphExecutor& executor, const std::string& pass,
                               const std::string& colour, const std::string& depth,
                               std::span<const ReflectedView> views, const GBufferShadows& shadows,
                               std::string purpose);
    // Reversed depth (z' = w - z, cleared to 0, GREATER wins) applied to projection * view.
    static glm::mat4 reversedViewProjection(const glm::mat4& projection, const glm::mat4& view);

    // Whether the camera's view draws glass over the opaque surfaces (the scene has glass and the
    // device blends kColourFormat); the G-buffer's grey is then not final (GBufferGrey).
    bool drawsGlass() const { return scene_->glassVertexCount() > 0 && glassUnsupported_.empty(); }
    const std::string& glassUnsupported() const { return glassUnsupported_; }

private:
    // The opaque triangles one view draws: index lists for the pre-pass (shared positions) and the
    // shading draw (the vertex buffer; reversed after a pre-pass).
    struct CulledDraw {
        vk::Buffer prepassIndices, shadingIndices;
        std::uint32_t indexCount = 0;
        ViewFrustum frustum;
        const SceneGpu* scene = nullptr;
    };
    void updateCulledDraw(const ViewFrustum& frustum);
    bool hasDepthPrepass() const { return depthPipeline_.handle() != VK_NULL_HANDLE; }
    // scissors: one per draw (width 0: the whole target), or empty for none.
    void record(vk::PassContext& pc, const std::string& colour, const std::string& grey, const std::string& depth,
                const vk::Pipeline& pipeline, const std::string& shadow, std::span<const gpu::GBufferPush> draws,
                bool prepass, const vk::Pipeline* glass, std::span<const VkRect2D> scissors = {},
                const CulledDraw* culled = nullptr) const;

    // The shading pipeline of each variant, specialised for the scene's light list of
    // `shadingVersion` (SceneGpu: light list and shadow face sizes; older versions are dropped:
    // their recordings must be declared again
    // anyway); built by the executor's prepare step of a kept pass (a scene without lights never
    // builds a shadowed one). A std::map, so the references that recordings hold stay valid.
    struct PipelineKey {
        bool shadowed = false, mirrored = false, grey = false;
        std::uint32_t pcf = 1;
        std::uint64_t shadingVersion = 0;
        auto operator<=>(const PipelineKey&) const = default;
    };
    // The pipeline slot for these settings, and in `prepare` the pass's step that builds it if the
    // graph keeps the pass. withGlass: the step also builds glassPipeline_ (the camera's view of a
    // glass scene).
    const vk::Pipeline& pipelineFor(vk::PrepareFn& prepare, bool shadowed, bool mirrored, bool grey, std::uint32_t pcf,
                                    bool withGlass);

    VulkanContext* context_;
    const SceneGpu* scene_;
    std::map<PipelineKey, vk::Pipeline> pipelines_;
    vk::Pipeline glassPipeline_;     // for shadingVersion glassShadingVersion_, built when the pass is kept
    std::uint64_t glassShadingVersion_ = 0;
    std::string glassUnsupported_;
    vk::Pipeline depthPipeline_;  // the pre-pass (SceneGpu::sharedPositions() only)
    CulledDraw culled_;           // the camera's view, when add culls to it
};

}  // namespace aamap::passes
