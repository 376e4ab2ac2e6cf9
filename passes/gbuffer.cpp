#include "passes/gbuffer.h"

#include <algorithm>
#include <utility>
#include <vector>

#include <aamap/spirv.h>
#include <fmt/format.h>

#include "core/image_io.h"
#include "engine/vk/context.h"
#include "glsl/shared/aamap_filter.h"
#include "glsl/shared/snapshot_interface.h"
#include "passes/snapshot_graph.h"

namespace aamap::passes {
namespace {

// The attributes of gbuffer_vertex.glsl every layout has (SceneGpu's first kVertexStride bytes).
std::vector<VkVertexInputAttributeDescription> baseVertexAttributes() {
    return {
        {GBUFFER_LOCATION_POSITION, 0, VK_FORMAT_R32G32B32_SFLOAT, 0},
        {GBUFFER_LOCATION_NORMAL, 0, VK_FORMAT_R32G32B32_SFLOAT, SceneGpu::kNormalOffset},
        {GBUFFER_LOCATION_KD, 0, VK_FORMAT_R32G32B32_SFLOAT, SceneGpu::kKdOffset},
        {GBUFFER_LOCATION_KE, 0, VK_FORMAT_R32G32B32_SFLOAT, SceneGpu::kKeOffset},
        {GBUFFER_LOCATION_SPECULAR, 0, VK_FORMAT_R32G32B32A32_SFLOAT, SceneGpu::kSpecularOffset},
        {GBUFFER_LOCATION_LOBE, 0, VK_FORMAT_R16G16B16A16_SFLOAT, SceneGpu::kLobeOffset},
        {GBUFFER_LOCATION_LOBE_ETA, 0, VK_FORMAT_R16G16B16A16_SFLOAT, SceneGpu::kLobeEtaOffset},
        {GBUFFER_LOCATION_LOBE_K, 0, VK_FORMAT_R16G16B16A16_SFLOAT, SceneGpu::kLobeKOffset},
    };
}

// The pre-pass: positions in, depth out, no fragment work (the empty depth-only shader).
vk::Pipeline makeDepthPipeline(VulkanContext& context) {
    vk::GraphicsDesc desc;
    desc.vertexSpirv = spirv::gbuffer_depth_vert;
    desc.fragmentSpirv = spirv::shadow_cube_frag;
    desc.vertexInput.stride = sizeof(glm::vec3);
    desc.vertexInput.attributes = {{GBUFFER_LOCATION_POSITION, 0, VK_FORMAT_R32G32B32_SFLOAT, 0}};
    desc.depthFormat = vk::toVkFormat(GBufferPass::kDepthFormat);
    desc.depthCompare = VK_COMPARE_OP_GREATER;  // reversed depth
    return vk::Pipeline(context, desc,
                        vk::LayoutDesc{{}, static_cast<std::uint32_t>(sizeof(gpu::GBufferPush)),
                                       VK_SHADER_STAGE_VERTEX_BIT});
}

vk::Pipeline makePipeline(VulkanContext& context, bool shadowed, bool textured, bool mirrored, bool grey,
                          bool afterPrepass, std::vector<std::uint32_t> lightingConstants) {
    vk::GraphicsDesc desc;
    desc.fragmentConstants = std::move(lightingConstants);
    if (grey) {  // the camera's view only (passes/gbuffer.h, GBufferGrey)
        desc.vertexSpirv = textured ? spirv::gbuffer_textured_vert : spirv::gbuffer_vert;
        desc.fragmentSpirv = textured ? (shadowed ? spirv::gbuffer_textured_shadowed_grey_frag
                                                  : spirv::gbuffer_textured_grey_frag)
                                      : (shadowed ? spirv::gbuffer_shadowed_grey_frag : spirv::gbuffer_grey_frag);
    } else if (mirrored) {
        desc.vertexSpirv = textured ? spirv::gbuffer_mirror_textured_vert : spirv::gbuffer_mirror_vert;
        desc.fragmentSpirv = textured ? (shadowed ? spirv::gbuffer_mirror_textured_shadowed_frag
                                                  : spirv::gbuffer_mirror_textured_frag)
                                      : (shadowed ? spirv::gbuffer_mirror_shadowed_frag : spirv::gbuffer_mirror_frag);
    } else {
        desc.vertexSpirv = textured ? spirv::gbuffer_textured_vert : spirv::gbuffer_vert;
        desc.fragmentSpirv = textured ? (shadowed ? spirv::gbuffer_textured_shadowed_frag : spirv::gbuffer_textured_frag)
                                      : (shadowed ? spirv::gbuffer_shadowed_frag : spirv::gbuffer_frag);
    }
    desc.vertexInput.stride = textured ? SceneGpu::kTexturedVertexStride : SceneGpu::kVertexStride;
    desc.vertexInput.attributes = baseVertexAttributes();
    if (textured) {
        desc.vertexInput.attributes.push_back({GBUFFER_LOCATION_UV, 0, VK_FORMAT_R32G32_SFLOAT, SceneGpu::kUvOffset});
        desc.vertexInput.attributes.push_back(
            {GBUFFER_LOCATION_TEX_RECT, 0, VK_FORMAT_R16G16B16A16_UINT, SceneGpu::kTexRectOffset});
        desc.vertexInput.attributes.push_back(
            {GBUFFER_LOCATION_TEX_PARAMS, 0, VK_FORMAT_R32G32_SFLOAT, SceneGpu::kTexParamsOffset});
    }
    desc.colorFormats = {vk::toVkFormat(GBufferPass::kColourFormat)};
    if (grey) desc.colorFormats.push_back(vk::toVkFormat(GBufferPass::kGreyFormat));
    desc.depthFormat = vk::toVkFormat(GBufferPass::kDepthFormat);
    // Reversed depth; after the pre-pass the nearest surface's own depth passes.
    desc.depthCompare = afterPrepass ? VK_COMPARE_OP_GREATER_OR_EQUAL : VK_COMPARE_OP_GREATER;
    std::vector<VkDescriptorType> bindings{VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER};  // GBUFFER_BINDING_LIGHTS
    static_assert(GBUFFER_BINDING_LIGHTS == 0 && GBUFFER_BINDING_SHADOW == 1);
    if (shadowed) bindings.push_back(VK_DESCRIPTOR_TYPE_SAMPLED_IMAGE);  // texelFetch only: no sampler
    static_assert(GBUFFER_BINDING_ATLAS_UNSHADOWED == 1 && GBUFFER_BINDING_ATLAS_SHADOWED == 2);
    if (textured) bindings.push_back(VK_DESCRIPTOR_TYPE_SAMPLED_IMAGE);  // the atlas, after the shadow maps
    return vk::Pipeline(context, desc,
                        vk::LayoutDesc{bindings, static_cast<std::uint32_t>(sizeof(gpu::GBufferPush)),
                                       VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT});
}

// Glass over the opaque surfaces (passes/gbuffer.h): the plain vertex stage reads the first
// attributes of either layout; depth-tested against the opaque depth, not written; blended.
vk::Pipeline makeGlassPipeline(VulkanContext& context, bool textured, std::vector<std::uint32_t> lightingConstants) {
    vk::GraphicsDesc desc;
    desc.fragmentConstants = std::move(lightingConstants);
    desc.vertexSpirv = spirv::gbuffer_vert;
    desc.fragmentSpirv = spirv::gbuffer_glass_frag;
    desc.vertexInput.stride = textured ? SceneGpu::kTexturedVertexStride : SceneGpu::kVertexStride;
    desc.vertexInput.attributes = baseVertexAttributes();
    desc.colorFormats = {vk::toVkFormat(GBufferPass::kColourFormat)};
    desc.depthFormat = vk::toVkFormat(GBufferPass::kDepthFormat);
    desc.depthCompare = VK_COMPARE_OP_GREATER;  // reversed depth: in front of the opaque surface
    desc.depthWrite = false;
    desc.premultipliedBlend = true;
    return vk::Pipeline(context, desc,
                        vk::LayoutDesc{{VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER},  // GBUFFER_BINDING_LIGHTS
                                       static_cast<std::uint32_t>(sizeof(gpu::GBufferPush)),
                                       VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT});
}

}  // namespace

GBufferPass::GBufferPass(VulkanContext& context, const SceneGpu& scene) : context_(&context), scene_(&scene) {
    if (scene.sharedPositions() && scene.vertexCount() > 0) depthPipeline_ = makeDepthPipeline(context);
    if (scene.glassVertexCount() > 0) {
        VkFormatProperties props{};
        vkGetPhysicalDeviceFormatProperties(context.physicalDevice(), vk::toVkFormat(kColourFormat), &props);
        if (!(props.optimalTilingFeatures & VK_FORMAT_FEATURE_COLOR_ATTACHMENT_BLEND_BIT))
            glassUnsupported_ = fmt::format("'{}' cannot blend into the snapshot's RGBA32F: glass is seen through",
                                            context.deviceName());
    }
}

glm::mat4 SnapshotView::reversedViewProjection() const {
    return GBufferPass::reversedViewProjection(camera.projectionMatrix(nearPlane, farPlane), camera.viewMatrix());
}

graph::PassId GBufferPass::add(graph::RenderGraph& graph, vk::GraphExecutor& executor, const std::string& colour,
                               const std::string& depth, const SnapshotView& view, const GBufferShadows& shadows,
                               const GBufferGrey& grey, bool cullToView) {
    const bool shadowed = !shadows.resource.empty();
    const ViewFrustum frustum = ViewFrustum::fromViewProjection(view.reversedViewProjection());
    if (cullToView && scene_->vertexCount() > 0) updateCulledDraw(frustum);
    const CulledDraw* culled = cullToView && scene_->vertexCount() > 0 ? &culled_ : nullptr;
    std::vector<graph::Access> accesses{graph::writes(colour, graph::Usage::ColorAttachment),
                                        graph::writes(depth, graph::Usage::DepthAttachment)};
    if (!grey.resource.empty()) accesses.push_back(graph::writes(grey.resource, graph::Usage::ColorAttachment));
    if (shadowed) accesses.push_back(graph::reads(shadows.resource, graph::Usage::Sampled));
    vk::PassDeclaration pass;
    const vk::Pipeline& pipeline =
        pipelineFor(pass.prepare, shadowed, false, !grey.resource.empty(), shadows.pcf, drawsGlass());
    const vk::Pipeline* glass = drawsGlass() ? &glassPipeline_ : nullptr;
    gpu::GBufferPush push{};
    push.exposure = grey.exposure;
    push.viewProj = view.reversedViewProjection();
    push.cameraPos = glm::vec4(view.camera.origin, 1.0f);
    push.shadow = glm::vec4(shadows.nearPlane, shadows.depthBias, shadows.slopeBias,
                            static_cast<float>(shadows.faceSize));
    pass.desc = {kGBufferPass, graph::QueueKind::Graphics, accesses,
                 std::string(shadowed
                                 ? "rasterise the scene with local illumination and shadow-map visibility per light"
                                 : "rasterise the scene with local illumination") +
                     (scene_->textured() ? "; " + scene_->atlasSummary() : "") +
                     (grey.resource.empty() ? std::string() : "; and the greyscale of the aamap's step 1") +
                     (scene_->glassVertexCount() == 0 ? std::string()
                      : drawsGlass() ? fmt::format("; then {} glass triangles over what they show, Fresnel-weighted",
                                                   scene_->glassVertexCount() / 3)
                                     : fmt::format("; {} glass triangles seen through ({})",
                                                   scene_->glassVertexCount() / 3, glassUnsupported_)) +
                     (culled == nullptr ? std::string()
                                        : fmt::format("; {} of {} opaque triangles in the view frustum",
                                                      culled->indexCount / 3, scene_->vertexCount() / 3))};
    pass.record = [this, colour, depth, push, &pipeline, shadow = shadows.resource, grey = grey.resource, glass,
                   culled](vk::PassContext& pc) {
        record(pc, colour, grey, depth, pipeline, shadow, {&push, 1}, hasDepthPrepass(), glass, {}, culled);
    };
    const graph::PassId id = vk::declarePass(graph, executor, std::move(pass));
    return id;
}

void GBufferPass::updateCulledDraw(const ViewFrustum& frustum) {
    if (culled_.scene == scene_ && culled_.frustum == frustum && culled_.indexCount > 0) return;
    const std::uint32_t triangles = scene_->vertexCount() / 3;
    const std::vector<std::uint32_t> kept = trianglesInView(scene_->vertexPositions(), triangles, frustum);
    std::vector<std::uint32_t> prepass, shading;
    const bool shared = hasDepthPrepass();
    shading.reserve(3 * kept.size());
    if (shared) {
        // The shading draw walks the kept triangles in reverse (ties: the mesh's first wins, as
        // without culling); the pre-pass takes them in order, on the shared positions.
        prepass.reserve(3 * kept.size());
        const std::span<const std::uint32_t> index = scene_->positionIndex();
        for (const std::uint32_t t : kept)
            for (std::uint32_t k = 0; k < 3; ++k) prepass.push_back(index[3 * t + k]);
        for (auto it = kept.rbegin(); it != kept.rend(); ++it)
            for (std::uint32_t k = 0; k < 3; ++k) shading.push_back(3 * *it + k);
    } else {
        for (const std::uint32_t t : kept)
            for (std::uint32_t k = 0; k < 3; ++k) shading.push_back(3 * t + k);
    }
    culled_.indexCount = static_cast<std::uint32_t>(shading.size());
    if (shading.empty()) shading.push_back(0);  // a buffer needs a size; nothing reads it
    if (prepass.empty()) prepass.push_back(0);
    culled_.shadingIndices = vk::uploadBuffer(*context_, std::as_bytes(std::span<const std::uint32_t>(shading)),
                                              VK_BUFFER_USAGE_INDEX_BUFFER_BIT);
    culled_.prepassIndices = vk::uploadBuffer(*context_, std::as_bytes(std::span<const std::uint32_t>(prepass)),
                                              VK_BUFFER_USAGE_INDEX_BUFFER_BIT);
    culled_.frustum = frustum;
    culled_.scene = scene_;
}

const vk::Pipeline& GBufferPass::pipelineFor(vk::PrepareFn& prepare, bool shadowed, bool mirrored, bool grey,
                                             std::uint32_t pcf, bool withGlass) {
    const PipelineKey key{shadowed, mirrored, grey, shadowed ? std::max(pcf, 1u) : 1u, scene_->shadingVersion()};
    std::erase_if(pipelines_, [&](const auto& entry) { return entry.first.shadingVersion != key.shadingVersion; });
    if (withGlass && glassShadingVersion_ != key.shadingVersion) glassPipeline_.reset();  // lights inlined
    vk::Pipeline& pipeline = pipelines_[key];
    prepare = [this, &pipeline, key, withGlass] {
        if (!pipeline.handle())
            pipeline = makePipeline(*context_, key.shadowed, scene_->textured(), key.mirrored, key.grey,
                                    !key.mirrored && hasDepthPrepass(), scene_->lightingConstants(key.pcf));
        if (withGlass && !glassPipeline_.handle()) {
            glassPipeline_ = makeGlassPipeline(*context_, scene_->textured(), scene_->lightingConstants(1));
            glassShadingVersion_ = key.shadingVersion;
        }
    };
    return pipeline;
}

glm::mat4 GBufferPass::reversedViewProjection(const glm::mat4& projection, const glm::mat4& view) {
    // Reversed depth (z' = w - z, cleared to 0, GREATER wins): float depth then has about uniform
    // relative precision, so a small near plane does not cost z-fighting far away.
    glm::mat4 reverse(1.0f);
    reverse[2][2] = -1.0f;
    reverse[3][2] = 1.0f;
    return reverse * projection * view;
}

graph::PassId GBufferPass::addReflected(graph::RenderGraph& graph, vk::GraphExecutor& executor,
                                        const std::string& pass, const std::string& colour, const std::string& depth,
                                        std::span<const ReflectedView> views, const GBufferShadows& shadows,
                                        std::string purpose) {
    const bool shadowed = !shadows.resource.empty();
    std::vector<graph::Access> accesses{graph::writes(colour, graph::Usage::ColorAttachment),
                                        graph::writes(depth, graph::Usage::DepthAttachment)};
    if (shadowed) accesses.push_back(graph::reads(shadows.resource, graph::Usage::Sampled));
    vk::PassDeclaration declaration;
    const vk::Pipeline& pipeline = pipelineFor(declaration.prepare, shadowed, true, false, shadows.pcf, false);
    std::vector<gpu::GBufferPush> pushes;
    std::vector<VkRect2D> scissors;
    for (std::size_t i = 0; i < views.size(); ++i) {
        scissors.push_back(views[i].scissor);
        gpu::GBufferPush push{};
        push.viewProj = views[i].viewProj;
        push.cameraPos = glm::vec4(views[i].eye, 1.0f);
        push.mirrorLayer = static_cast<std::uint32_t>(i);
        push.shadow = glm::vec4(shadows.nearPlane, shadows.depthBias, shadows.slopeBias,
                                static_cast<float>(shadows.faceSize));
        push.clipPlane = views[i].clipPlane;
        pushes.push_back(push);
    }
    declaration.desc = {pass, graph::QueueKind::Graphics, accesses, std::move(purpose)};
    declaration.record = [this, colour, depth, pushes, scissors, &pipeline,
                          shadow = shadows.resource](vk::PassContext& pc) {
        record(pc, colour, "", depth, pipeline, shadow, pushes, false, nullptr, scissors);
    };
    const graph::PassId id = vk::declarePass(graph, executor, std::move(declaration));
    return id;
}

void GBufferPass::record(vk::PassContext& pc, const std::string& colour, const std::string& grey,
                         const std::string& depth, const vk::Pipeline& pipeline, const std::string& shadow,
                         std::span<const gpu::GBufferPush> draws, bool prepass, const vk::Pipeline* glass,
                         std::span<const VkRect2D> scissors, const CulledDraw* culled) const {
    const vk::Image& target = pc.image(colour);
    const vk::Image& z = pc.image(depth);
    const VkExtent2D extent{target.info().width, target.info().height};
    // The background (black unless the scene has a sky), and its grey as glsl/display_luma.glsl
    // computes it.
    const glm::vec3 background = scene_->background();
    const VkClearColorValue sky{{background.r, background.g, background.b, 0.0f}};
    std::vector<VkRenderingAttachmentInfo> colourInfos{vk::clearedColourAttachment(target.view(), sky)};
    if (!grey.empty()) {
        const float e = draws[0].exposure;
        const float g = static_cast<float>(AAMAP_LUMA_R) * srgbEncode(e * background.r) +
                        static_cast<float>(AAMAP_LUMA_G) * srgbEncode(e * background.g) +
                        static_cast<float>(AAMAP_LUMA_B) * srgbEncode(e * background.b);
        colourInfos.push_back(vk::clearedColourAttachment(pc.image(grey).view(), VkClearColorValue{{g, 0.0f, 0.0f, 0.0f}}));
    }
    VkRenderingAttachmentInfo depthInfo{VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO};
    depthInfo.imageView = z.view();
    depthInfo.imageLayout = VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL;
    depthInfo.loadOp = VK_ATTACHMENT_LOAD_OP_CLEAR;
    depthInfo.storeOp = VK_ATTACHMENT_STORE_OP_STORE;
    depthInfo.clearValue.depthStencil = {0.0f, 0};  // reversed depth: 0 is the far plane
    VkRenderingInfo rendering{VK_STRUCTURE_TYPE_RENDERING_INFO};
    rendering.renderArea = {{0, 0}, extent};
    rendering.layerCount = target.info().layers;  // mirror.colour: one layer per mirror (gl_Layer)
    rendering.colorAttachmentCount = static_cast<std::uint32_t>(colourInfos.size());
    rendering.pColorAttachments = colourInfos.data();
    rendering.pDepthAttachment = &depthInfo;

    VkCommandBuffer cmd = pc.cmd();
    vkCmdBeginRendering(cmd, &rendering);
    vk::setFullViewport(cmd, extent);
    const std::uint32_t vertexCount = scene_->vertexCount();
    if (vertexCount > 0 && prepass) {
        depthPipeline_.bind(cmd);
        depthPipeline_.pushConstants(cmd, draws[0]);
        const VkBuffer vb = scene_->positionBuffer().handle();
        const VkDeviceSize offset = 0;
        vkCmdBindVertexBuffers(cmd, 0, 1, &vb, &offset);
        vkCmdBindIndexBuffer(cmd, culled ? culled->prepassIndices.handle() : scene_->positionIndexBuffer().handle(), 0,
                             VK_INDEX_TYPE_UINT32);
        if (!culled || culled->indexCount > 0) vkCmdDrawIndexed(cmd, culled ? culled->indexCount : vertexCount, 1, 0, 0, 0);
    }
    if (vertexCount > 0) {
        pipeline.bind(cmd);
        vk::DescriptorPush descriptors;
        descriptors.uniformBuffer(GBUFFER_BINDING_LIGHTS, scene_->lightBuffer().handle());
        if (!shadow.empty())
            descriptors.sampledImage(GBUFFER_BINDING_SHADOW, pc.image(shadow).view(),
                                     VK_IMAGE_LAYOUT_DEPTH_STENCIL_READ_ONLY_OPTIMAL);
        if (scene_->textured())
            descriptors.sampledImage(shadow.empty() ? GBUFFER_BINDING_ATLAS_UNSHADOWED : GBUFFER_BINDING_ATLAS_SHADOWED,
                                     scene_->atlas().view(), VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
        descriptors.push(*context_, cmd, pipeline);
        const VkBuffer vb = scene_->vertexBuffer().handle();
        const VkDeviceSize offset = 0;
        vkCmdBindVertexBuffers(cmd, 0, 1, &vb, &offset);
        if (culled) vkCmdBindIndexBuffer(cmd, culled->shadingIndices.handle(), 0, VK_INDEX_TYPE_UINT32);
        else if (prepass) vkCmdBindIndexBuffer(cmd, scene_->reversedTriangleBuffer().handle(), 0, VK_INDEX_TYPE_UINT32);
        for (std::size_t d = 0; d < draws.size(); ++d) {
            const gpu::GBufferPush& push = draws[d];
            if (d < scissors.size()) {
                const VkRect2D rect = scissors[d].extent.width > 0 ? scissors[d] : VkRect2D{{0, 0}, extent};
                vkCmdSetScissor(cmd, 0, 1, &rect);
            }
            pipeline.pushConstants(cmd, push);
            if (culled) {
                if (culled->indexCount > 0) vkCmdDrawIndexed(cmd, culled->indexCount, 1, 0, 0, 0);
            } else if (prepass) {
                vkCmdDrawIndexed(cmd, vertexCount, 1, 0, 0, 0);
            } else {
                vkCmdDraw(cmd, vertexCount, 1, 0, 0);
            }
        }
    }
    if (glass != nullptr) {  // one view: the camera's (add)
        glass->bind(cmd);
        vk::DescriptorPush descriptors;
        descriptors.uniformBuffer(GBUFFER_BINDING_LIGHTS, scene_->lightBuffer().handle());
        descriptors.push(*context_, cmd, *glass);
        const VkBuffer vb = scene_->vertexBuffer().handle();
        const VkDeviceSize offset = 0;
        vkCmdBindVertexBuffers(cmd, 0, 1, &vb, &offset);
        glass->pushConstants(cmd, draws[0]);
        vkCmdDraw(cmd, scene_->glassVertexCount(), 1, vertexCount, 0);
    }
    vkCmdEndRendering(cmd);
}

}  // namespace aamap::passes

