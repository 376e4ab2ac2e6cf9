#include "passes/geometry_buffer.h"

#include <algorithm>
#include <cstddef>
#include <span>
#include <stdexcept>
#include <string>
#include <utility>

#include <aamap/spirv.h>
#include <fmt/format.h>

#include "engine/vk/context.h"
#include "glsl/shared/snapshot_interface.h"
#include "passes/snapshot_graph.h"

namespace aamap::passes {

namespace {

// (object, material) of each triangle the G-buffer's camera draws, in its vertex-buffer order.
std::vector<glm::uvec2> drawnTriangleIds(const Scene& scene, const SceneGpu& sceneGpu) {
    const TriangleMesh& mesh = scene.mesh;
    const std::span<const std::uint32_t> drawn = sceneGpu.drawnTriangles().first(sceneGpu.vertexCount() / 3);
    std::vector<glm::uvec2> out;
    out.reserve(drawn.size());
    for (const std::uint32_t t : drawn) {
        const std::uint32_t material = t < mesh.materialIds.size() ? mesh.materialIds[t] : 0u;
        const std::uint32_t object = t < mesh.objectIds.size() ? mesh.objectIds[t] : 0u;
        out.push_back({object, material});
    }
    return out;
}

// The scene's vertex layout (passes/scene_gpu.h): position and normal, and in the textured
// layout uv and atlas entry for the alpha test.
vk::Pipeline makePipeline(VulkanContext& context, const SceneGpu& scene, bool shadowed,
                          std::vector<std::uint32_t> lightingConstants) {
    const bool textured = scene.textured();
    vk::GraphicsDesc desc;
    desc.fragmentConstants = std::move(lightingConstants);
    desc.vertexSpirv = textured ? spirv::geometry_buffer_textured_vert : spirv::geometry_buffer_vert;
    if (textured)
        desc.fragmentSpirv =
            shadowed ? spirv::geometry_buffer_textured_shadowed_frag : spirv::geometry_buffer_textured_frag;
    else
        desc.fragmentSpirv = shadowed ? spirv::geometry_buffer_shadowed_frag : spirv::geometry_buffer_frag;
    desc.vertexInput.stride = scene.vertexStride();
    desc.vertexInput.attributes = {
        {GEOMETRY_LOCATION_POSITION, 0, VK_FORMAT_R32G32B32_SFLOAT, 0},
        {GEOMETRY_LOCATION_NORMAL, 0, VK_FORMAT_R32G32B32_SFLOAT, SceneGpu::kNormalOffset},
    };
    if (textured) {
        desc.vertexInput.attributes.push_back(
            {GEOMETRY_LOCATION_UV, 0, VK_FORMAT_R32G32_SFLOAT, SceneGpu::kUvOffset});
        desc.vertexInput.attributes.push_back(
            {GEOMETRY_LOCATION_TEX_RECT, 0, VK_FORMAT_R16G16B16A16_UINT, SceneGpu::kTexRectOffset});
        desc.vertexInput.attributes.push_back(
            {GEOMETRY_LOCATION_TEX_PARAMS, 0, VK_FORMAT_R32G32_SFLOAT, SceneGpu::kTexParamsOffset});
    }
    const VkFormat f = vk::toVkFormat(GeometryBufferPass::kFormat);
    desc.colorFormats = {f, f};
    desc.depthFormat = vk::toVkFormat(graph::Format::D32Float);
    desc.depthCompare = VK_COMPARE_OP_GREATER;  // reversed depth, as the G-buffer
    std::vector<VkDescriptorType> bindings{VK_DESCRIPTOR_TYPE_STORAGE_BUFFER};
    if (shadowed) {
        bindings.push_back(VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER);
        bindings.push_back(VK_DESCRIPTOR_TYPE_SAMPLED_IMAGE);
    }
    if (textured) bindings.push_back(VK_DESCRIPTOR_TYPE_SAMPLED_IMAGE);
    static_assert(GEOMETRY_BINDING_IDS == 0 && GEOMETRY_BINDING_LIGHTS == 1 && GEOMETRY_BINDING_SHADOW == 2 &&
                  GEOMETRY_BINDING_ATLAS_UNSHADOWED == 1 && GEOMETRY_BINDING_ATLAS_SHADOWED == 3);
    return vk::Pipeline(context, desc,
                        vk::LayoutDesc{bindings, static_cast<std::uint32_t>(sizeof(gpu::GeometryPush)),
                                       VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT});
}

}  // namespace

GeometryBufferPass::GeometryBufferPass(VulkanContext& context, const Scene& scene, const SceneGpu& sceneGpu)
    : context_(&context), scene_(&sceneGpu), pendingIds_(drawnTriangleIds(scene, sceneGpu)) {
    triangleCount_ = static_cast<std::uint32_t>(pendingIds_.size());
}

GeometryBufferPass::~GeometryBufferPass() = default;

void GeometryBufferPass::prepare() {
    const int slot = shadowed_ ? 1 : 0;
    if (!pipelines_[slot].handle() || builtConstants_[slot] != constants_) {
        pipelines_[slot] = makePipeline(*context_, *scene_, shadowed_, constants_);
        builtConstants_[slot] = constants_;
    }
    if (triangleCount_ == 0 || ids_) return;
    const auto* bytes = reinterpret_cast<const std::byte*>(pendingIds_.data());
    ids_ = vk::uploadBuffer(*context_, {bytes, pendingIds_.size() * sizeof(glm::uvec2)},
                            VK_BUFFER_USAGE_STORAGE_BUFFER_BIT);
    pendingIds_ = {};
}

void GeometryBufferPass::add(graph::RenderGraph& graph, vk::GraphExecutor& executor, const graph::Size& size,
                             const SnapshotView& view, const GBufferShadows& shadows) {
    const bool shadowed = !shadows.resource.empty();
    graph.addResource(graph::imageResource(kGeometryNormalDepth, kFormat, size));
    graph.addResource(graph::imageResource(kGeometryIds, kFormat, size));
    graph.addResource(graph::imageResource(kGeometryDepth, graph::Format::D32Float, size));
    std::vector<graph::Access> accesses{graph::writes(kGeometryNormalDepth, graph::Usage::ColorAttachment),
                                        graph::writes(kGeometryIds, graph::Usage::ColorAttachment),
                                        graph::writes(kGeometryDepth, graph::Usage::DepthAttachment)};
    if (shadowed) accesses.push_back(graph::reads(shadows.resource, graph::Usage::Sampled));
    shadowed_ = shadowed;
    constants_ = scene_->lightingConstants(shadows.pcf);
    const vk::Pipeline& pipeline = pipelines_[shadowed ? 1 : 0];  // built by prepare()
    gpu::GeometryPush push{};
    push.viewProj = view.reversedViewProjection();  // reversed depth, as the G-buffer
    const ViewFrustum frustum = ViewFrustum::fromViewProjection(push.viewProj);
    if (triangleCount_ > 0 && !(viewValid_ && viewFrustum_ == frustum)) {
        std::vector<std::uint32_t> indices;
        for (const std::uint32_t t : trianglesInView(scene_->vertexPositions(), triangleCount_, frustum))
            indices.insert(indices.end(), {3 * t, 3 * t + 1, 3 * t + 2});
        viewIndexCount_ = static_cast<std::uint32_t>(indices.size());
        if (indices.empty()) indices.push_back(0);  // a buffer needs a size; nothing reads it
        viewIndices_ = vk::uploadBuffer(*context_, std::as_bytes(std::span<const std::uint32_t>(indices)),
                                        VK_BUFFER_USAGE_INDEX_BUFFER_BIT);
        viewFrustum_ = frustum;
        viewValid_ = true;
    }
    push.cameraPos = glm::vec4(view.camera.origin, 1.0f);
    push.cameraForward = glm::vec4(view.camera.forward, 0.0f);
    push.shadow =
        glm::vec4(shadows.nearPlane, shadows.depthBias, shadows.slopeBias, static_cast<float>(shadows.faceSize));
    vk::PassDeclaration pass;
    pass.desc = {kGeometryBufferPass, graph::QueueKind::Graphics, accesses,
                 shadowed ? "rasterise normals, view depth, object/material ids and the shadow occlusion mask "
                            "for the geometric aamap"
                          : "rasterise normals, view depth and object/material ids for the geometric or subpixel aamap"};
    pass.desc.purpose += fmt::format("; {} of {} triangles in the view frustum", viewIndexCount_ / 3, triangleCount_);
    pass.prepare = [this] { prepare(); };
    pass.record = [this, push, &pipeline, shadow = shadows.resource](vk::PassContext& pc) {
        if (!prepared() || !pipeline.handle())
            throw std::logic_error("GeometryBufferPass recorded before its prepare step");
        const vk::Image& normalDepth = pc.image(kGeometryNormalDepth);
        const vk::Image& z = pc.image(kGeometryDepth);
        const VkExtent2D extent{normalDepth.info().width, normalDepth.info().height};
        // Cleared to 0: depth 0 and id 0 mean "uncovered".
        const VkRenderingAttachmentInfo colours[2] = {vk::clearedColourAttachment(normalDepth.view()),
                                                      vk::clearedColourAttachment(pc.image(kGeometryIds).view())};
        VkRenderingAttachmentInfo depthInfo{VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO};
        depthInfo.imageView = z.view();
        depthInfo.imageLayout = VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL;
        depthInfo.loadOp = VK_ATTACHMENT_LOAD_OP_CLEAR;
        depthInfo.storeOp = VK_ATTACHMENT_STORE_OP_DONT_CARE;
        depthInfo.clearValue.depthStencil = {0.0f, 0};
        VkRenderingInfo rendering{VK_STRUCTURE_TYPE_RENDERING_INFO};
        rendering.renderArea = {{0, 0}, extent};
        rendering.layerCount = 1;
        rendering.colorAttachmentCount = 2;
        rendering.pColorAttachments = colours;
        rendering.pDepthAttachment = &depthInfo;
        VkCommandBuffer cmd = pc.cmd();
        vkCmdBeginRendering(cmd, &rendering);
        vk::setFullViewport(cmd, extent);
        if (triangleCount_ > 0) {
            pipeline.bind(cmd);
            vk::DescriptorPush descriptors;
            descriptors.storageBuffer(GEOMETRY_BINDING_IDS, ids_.handle());
            if (!shadow.empty())
                descriptors.uniformBuffer(GEOMETRY_BINDING_LIGHTS, scene_->lightBuffer().handle())
                    .sampledImage(GEOMETRY_BINDING_SHADOW, pc.image(shadow).view(),
                                  VK_IMAGE_LAYOUT_DEPTH_STENCIL_READ_ONLY_OPTIMAL);
            if (scene_->textured())
                descriptors.sampledImage(
                    shadow.empty() ? GEOMETRY_BINDING_ATLAS_UNSHADOWED : GEOMETRY_BINDING_ATLAS_SHADOWED,
                    scene_->atlas().view(), VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
            descriptors.push(*context_, cmd, pipeline);
            pipeline.pushConstants(cmd, push);
            const VkBuffer vb = scene_->vertexBuffer().handle();
            const VkDeviceSize offset = 0;
            vkCmdBindVertexBuffers(cmd, 0, 1, &vb, &offset);
            vkCmdBindIndexBuffer(cmd, viewIndices_.handle(), 0, VK_INDEX_TYPE_UINT32);
            if (viewIndexCount_ > 0) vkCmdDrawIndexed(cmd, viewIndexCount_, 1, 0, 0, 0);
        }
        vkCmdEndRendering(cmd);
    };
    vk::declarePass(graph, executor, std::move(pass));
}

}  // namespace aamap::passes
