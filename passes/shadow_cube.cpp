#include "passes/shadow_cube.h"

#include <algorithm>
#include <stdexcept>

#include <aamap/spirv.h>
#include <fmt/format.h>

#include "core/error.h"
#include "engine/vk/context.h"
#include "glsl/shared/snapshot_interface.h"

namespace aamap::passes {

ShadowCubePass::ShadowCubePass(VulkanContext& context) : context_(&context) {
    VkPhysicalDeviceVulkan12Features f12{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_2_FEATURES};
    VkPhysicalDeviceFeatures2 f2{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2, &f12};
    vkGetPhysicalDeviceFeatures2(context.physicalDevice(), &f2);
    if (!f12.shaderOutputLayer)
        throw EnvironmentError(fmt::format("'{}' lacks shaderOutputLayer (Vulkan 1.2), which the shadow cube maps "
                                           "need; turn snapshot shadows off",
                                           context.deviceName()));
    VkPhysicalDeviceProperties props;
    vkGetPhysicalDeviceProperties(context.physicalDevice(), &props);
    maxLayers_ = std::min(props.limits.maxFramebufferLayers, props.limits.maxImageArrayLayers);

    vk::GraphicsDesc desc;
    desc.vertexSpirv = spirv::shadow_cube_vert;
    desc.fragmentSpirv = spirv::shadow_cube_frag;
    desc.vertexInput.stride = GBufferPass::kVertexStride;  // the G-buffer's vertices, position at 0
    desc.vertexInput.attributes = {{SHADOW_LOCATION_POSITION, 0, VK_FORMAT_R32G32B32_SFLOAT, 0}};
    desc.depthFormat = vk::toVkFormat(kFormat);
    desc.depthCompare = VK_COMPARE_OP_GREATER;  // reversed: near/ma, nearer is larger
    static_assert(SHADOW_BINDING_LIGHTS == 0);
    pipeline_ = vk::Pipeline(context, desc,
                             vk::LayoutDesc{{VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER},
                                            static_cast<std::uint32_t>(sizeof(gpu::ShadowPush)),
                                            VK_SHADER_STAGE_VERTEX_BIT});
}

graph::PassId ShadowCubePass::add(graph::RenderGraph& graph, vk::GraphExecutor& executor, const std::string& resource,
                                  const GBufferPass& geometry, std::span<const std::string> lightNames,
                                  std::uint32_t faceSize, float nearPlane) const {
    const auto lights = static_cast<std::uint32_t>(lightNames.size());
    if (lights == 0 || lights != geometry.lightCount())
        throw std::logic_error("ShadowCubePass::add: one name per light of the G-buffer, and at least one");
    const std::uint32_t layers = 6 * lights;
    if (layers > maxLayers_)
        throw std::invalid_argument(fmt::format("{} shadow cube maps need {} layers; '{}' allows {}: fewer lights or "
                                                "area-light samples, or shadows off",
                                                lights, layers, context_->deviceName(), maxLayers_));
    graph::ResourceDesc desc;
    desc.name = resource;
    desc.format = kFormat;
    desc.size = graph::Size::absolute(faceSize, faceSize);
    desc.layers = layers;  // an array, not `cube`: the receiver picks faces itself (texelFetch)
    graph.addResource(desc);

    std::string names;
    for (std::uint32_t i = 0; i < lights && i < 6; ++i) names += fmt::format("{}'{}'", i ? ", " : "", lightNames[i]);
    if (lights > 6) names += fmt::format(", ... ({} more)", lights - 6);
    const graph::PassId id = graph.addPass(
        {kShadowPass, graph::QueueKind::Graphics, {graph::writes(resource, graph::Usage::DepthAttachment)},
         fmt::format("shadow cube maps ({}^2 per face, 6 layers each) for {} light{}: {}", faceSize, lights,
                     lights == 1 ? "" : "s", names)});

    gpu::ShadowPush push{};
    push.nearPlane = nearPlane;
    executor.setRecord(kShadowPass, [this, &geometry, resource, push, layers](vk::PassContext& pc) {
        const vk::Image& target = pc.image(resource);
        const VkExtent2D extent{target.info().width, target.info().height};
        VkRenderingAttachmentInfo depthInfo{VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO};
        depthInfo.imageView = target.view();
        depthInfo.imageLayout = VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL;
        depthInfo.loadOp = VK_ATTACHMENT_LOAD_OP_CLEAR;
        depthInfo.storeOp = VK_ATTACHMENT_STORE_OP_STORE;
        depthInfo.clearValue.depthStencil = {0.0f, 0};  // near/ma = 0: nothing in the way
        VkRenderingInfo rendering{VK_STRUCTURE_TYPE_RENDERING_INFO};
        rendering.renderArea = {{0, 0}, extent};
        rendering.layerCount = layers;
        rendering.pDepthAttachment = &depthInfo;

        VkCommandBuffer cmd = pc.cmd();
        vkCmdBeginRendering(cmd, &rendering);
        vk::setFullViewport(cmd, extent);
        if (geometry.vertexCount() > 0) {
            pipeline_.bind(cmd);
            vk::DescriptorPush()
                .uniformBuffer(SHADOW_BINDING_LIGHTS, geometry.lightBuffer().handle())
                .push(*context_, cmd, pipeline_);
            pipeline_.pushConstants(cmd, push);
            const VkBuffer vb = geometry.vertexBuffer().handle();
            const VkDeviceSize offset = 0;
            vkCmdBindVertexBuffers(cmd, 0, 1, &vb, &offset);
            vkCmdDraw(cmd, geometry.vertexCount(), layers, 0, 0);  // instance 6i+f: face f of light i
        }
        vkCmdEndRendering(cmd);
    });
    return id;
}

}  // namespace aamap::passes
