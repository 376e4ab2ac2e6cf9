#pragma once
// The Snapshot raster: the scene's mesh with Lambert shading from point lights (and cosine-lobe
// point samples of area lights) plus emission, into linear colour and depth. Holds the scene's
// GPU state (vertices, materials, lights, the texture atlas) so that several views reuse it.
//
// Depth pre-pass: unless the scene has alpha masks (cut-out texels must not write depth), the
// main view first draws the distinct positions (12-byte vertices, indexed) into depth alone, and
// the shading draw then tests GREATER_OR_EQUAL against it, so each pixel is shaded once however
// many surfaces overlap it. Reflected views (mirrors discard behind their plane) draw as before.
// Where surfaces tie in depth, all of them pass that test and the last drawn wins, so the shading
// draw goes through the triangles in reverse order (same corners, same provoking vertex): the
// first triangle of the mesh wins a tie, as with GREATER and no pre-pass, and the image is the same.
//
// Glass: the tracer ignores a dielectric's kd and shows what lies behind it (Fresnel reflection
// and refraction; a thin pane transmits ~92 % of it, barely shifted), and its shadow rays stop at
// glass. So the camera's draws skip glass triangles (the Snapshot sees through them, without the
// refraction offset: curved glass is out of scope), while the shadow cube maps still draw them.
// They come last in the vertex buffer, so the camera draws the first vertexCount() vertices and
// the shadow pass all occluderVertexCount().
//
// Textures and alpha (passes/gbuffer_textures.h): a scene whose used materials sample a texture
// gets the textured pipeline variants (uv and atlas entry per vertex, one atlas binding); other
// scenes bind no texture at all. Alpha-tested materials with constant coverage need no texture:
// their triangles are either dropped (alpha < cutoff) or opaque.
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
};

class GBufferPass {
public:
    static constexpr graph::Format kColourFormat = graph::Format::RGBA32Float;
    static constexpr graph::Format kDepthFormat = graph::Format::D32Float;
    static constexpr graph::Format kGreyFormat = graph::Format::R32Float;  // GBufferGrey

    GBufferPass(VulkanContext& context, const Scene& scene);  // uploads the mesh with its materials
    // Uploads the light list: the point lights, then the directional ones (each shadowed by an
    // orthographic map over the bounding sphere of the mesh), and the ambient SH irradiance
    // (passes/environment_lighting.h; null: none). Throws std::invalid_argument past
    // GBUFFER_MAX_LIGHTS (256) lights. Passes declared before must be declared again (add,
    // addReflected) before they execute.
    void setLights(std::span<const PointLight> lights, std::span<const DirectionalLight> directionals = {},
                   const std::array<glm::vec3, 9>* ambientSH = nullptr);

    // Declares the pass "gbuffer" (writes `colour` and `depth`, and grey.resource if not empty;
    // reads the shadow maps if any) and registers its recording for the camera with the given
    // clip planes. This object must outlive execution.
    graph::PassId add(graph::RenderGraph& graph, vk::GraphExecutor& executor, const std::string& colour,
                      const std::string& depth, const PinholeCamera& camera, float nearPlane, float farPlane,
                      const GBufferShadows& shadows = {}, const GBufferGrey& grey = {});

    // Declares pass `pass`, which renders the scene once per view into layer i of the layered
    // `colour` and `depth` (the G-buffer's shading, clipped to each view's plane).
    graph::PassId addReflected(graph::RenderGraph& graph, vk::GraphExecutor& executor, const std::string& pass,
                               const std::string& colour, const std::string& depth,
                               std::span<const ReflectedView> views, const GBufferShadows& shadows,
                               std::string purpose);
    // Reversed depth (z' = w - z, cleared to 0, GREATER wins) applied to projection * view.
    static glm::mat4 reversedViewProjection(const glm::mat4& projection, const glm::mat4& view);

    // Vertices the camera draws (three per triangle, vertex-buffer order from 0), and those the
    // shadow pass draws: the same followed by the glass triangles (see "Glass" above).
    std::uint32_t vertexCount() const { return vertexCount_; }
    std::uint32_t occluderVertexCount() const { return occluderVertexCount_; }
    // The mesh triangle of each triangle of the vertex buffer (occluderVertexCount() / 3 of them).
    std::span<const std::uint32_t> drawnTriangles() const { return drawnTriangles_; }
    bool textured() const { return textured_; }        // the atlas is bound (scene has textures)
    bool alphaMasked() const { return alphaMasked_; }  // some texel can be cut out (shadows test it)
    const vk::Image& atlas() const { return atlas_; }  // valid only when textured()
    std::string atlasSummary() const;                  // for --explain
    // Radiance of the background (where no surface is drawn), and its grey; black by default.
    // Passes declared before must be declared again, as after setLights.
    void setBackground(const glm::vec3& radiance) { background_ = radiance; }
    std::uint32_t lightCount() const { return lightCount_; }
    bool ambient() const { return ambient_; }  // the environment's SH term is shaded
    // The LIGHTING_SPEC_* specialisation constants of a lit fragment shader drawing these lights
    // with this PCF side (glsl/lights.glsl), for the passes that share the G-buffer's lights.
    std::vector<std::uint32_t> lightingConstants(std::uint32_t pcf) const;
    // For the shadow pass, which draws the same vertices from the same lights.
    const vk::Buffer& vertexBuffer() const { return vertices_; }
    const vk::Buffer& lightBuffer() const { return lights_; }
    // CPU copies for the shadow pass's per-face culling: the occluders' vertex positions (three per
    // triangle, in vertex-buffer order) and the lights' positions, with a counter of setLights.
    std::span<const glm::vec3> vertexPositions() const { return positions_; }
    std::span<const glm::vec3> lightPositions() const { return lightPositions_; }
    // Per light: 1 if directional (its shadow map is one orthographic layer, face 0), else 0.
    std::span<const std::uint8_t> lightDirectional() const { return lightDirectional_; }
    std::uint64_t lightsVersion() const { return lightsVersion_; }
    // The distinct positions (bit-equal corners merged) and, per vertex of vertexBuffer(), its
    // index among them: position-only passes (depth pre-pass, shadow cube maps) draw these, so
    // the vertex cache shades a shared corner once. Empty when alphaMasked() (those passes then
    // need uv and atlas entry per vertex).
    bool sharedPositions() const { return !positionIndex_.empty(); }
    const vk::Buffer& positionBuffer() const { return sharedPositions_; }
    std::span<const std::uint32_t> positionIndex() const { return positionIndex_; }
    // Vertex layout (passes/gbuffer.cpp): position at 0; uv, atlas entry and its parameters at
    // the offsets below only in the textured layout.
    std::uint32_t vertexStride() const { return textured_ ? kTexturedVertexStride : kVertexStride; }
    static constexpr std::uint32_t kVertexStride = 48;
    static constexpr std::uint32_t kTexturedVertexStride = 72;
    static constexpr std::uint32_t kUvOffset = 48, kTexRectOffset = 56, kTexParamsOffset = 64;

private:
    bool hasDepthPrepass() const { return depthPipeline_.handle() != VK_NULL_HANDLE; }
    void record(vk::PassContext& pc, const std::string& colour, const std::string& grey, const std::string& depth,
                const vk::Pipeline& pipeline, const std::string& shadow, std::span<const gpu::GBufferPush> draws,
                bool prepass) const;

    // The shading pipeline of each variant, specialised for the light list of setLights call
    // `lightsVersion` (setLights drops the others); built by the executor's prepare step of a kept
    // pass (a scene without lights never builds a shadowed one). A std::map, so the references
    // that recordings hold stay valid.
    struct PipelineKey {
        bool shadowed = false, mirrored = false, grey = false;
        std::uint32_t pcf = 1;
        std::uint64_t lightsVersion = 0;
        auto operator<=>(const PipelineKey&) const = default;
    };
    const vk::Pipeline& pipelineFor(vk::GraphExecutor& executor, const std::string& pass, bool shadowed,
                                    bool mirrored, bool grey, std::uint32_t pcf);

    VulkanContext* context_;
    std::map<PipelineKey, vk::Pipeline> pipelines_;
    vk::Pipeline depthPipeline_;  // the pre-pass (sharedPositions() only)
    vk::Buffer vertices_, lights_;
    vk::Buffer sharedPositions_, positionIndices_;  // positionIndex_ as an index buffer
    vk::Buffer reversedTriangles_;  // vertices_ by triangle, last triangle first (after the pre-pass)
    std::vector<std::uint32_t> positionIndex_;
    vk::Image atlas_;
    std::vector<glm::vec3> positions_, lightPositions_;
    std::vector<std::uint8_t> lightDirectional_;
    glm::vec3 coverCentre_{0.0f};  // the sphere every directional shadow map covers
    float coverRadius_ = 1.0f;
    bool ambient_ = false;
    glm::vec3 background_{0.0f};
    std::array<glm::vec3, 9> ambientSH_{};
    std::uint64_t lightsVersion_ = 0;
    bool textured_ = false, alphaMasked_ = false;
    std::uint32_t atlasEntries_ = 0;
    std::uint32_t vertexCount_ = 0, occluderVertexCount_ = 0;
    std::vector<std::uint32_t> drawnTriangles_;
    std::uint32_t lightCount_ = 0, lightKinds_ = 0;  // LIGHT_KIND_* bits
    std::vector<gpu::GpuLight> inlineLights_;        // the first LIGHTING_INLINE_LIGHTS, for the constants
};

}  // namespace aamap::passes
