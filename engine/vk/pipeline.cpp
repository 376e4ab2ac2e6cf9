#include "engine/vk/pipeline.h"

#include <utility>
#include <vector>

#include "engine/vk/check.h"
#include "engine/vk/context.h"

namespace aamap::vk {
namespace {

// Shader modules only live as long as pipeline creation needs them.
class ShaderModule {
public:
    ShaderModule(VkDevice device, std::span<const std::uint32_t> spirv) : device_(device) {
        VkShaderModuleCreateInfo info{VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO};
        info.codeSize = spirv.size_bytes();
        info.pCode = spirv.data();
        VK_CHECK(vkCreateShaderModule(device, &info, nullptr, &module_));
    }
    ~ShaderModule() { vkDestroyShaderModule(device_, module_, nullptr); }
    ShaderModule(const ShaderModule&) = delete;
    ShaderModule& operator=(const ShaderModule&) = delete;
    VkShaderModule handle() const { return module_; }

private:
    VkDevice device_;
    VkShaderModule module_ = VK_NULL_HANDLE;
};

VkPipelineShaderStageCreateInfo stage(VkShaderStageFlagBits which, VkShaderModule module) {
    VkPipelineShaderStageCreateInfo info{VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO};
    info.stage = which;
    info.module = module;
    info.pName = "main";
    return info;
}

// Specialisation constant_id i = constants[i], 32 bits each. Points into itself and `constants`:
// keep both alive and unmoved until the pipeline is created.
class Specialization {
public:
    explicit Specialization(std::span<const std::uint32_t> constants) {
        for (std::uint32_t i = 0; i < constants.size(); ++i)
            entries_.push_back({i, static_cast<std::uint32_t>(i * sizeof(std::uint32_t)), sizeof(std::uint32_t)});
        info_.mapEntryCount = static_cast<std::uint32_t>(entries_.size());
        info_.pMapEntries = entries_.data();
        info_.dataSize = constants.size_bytes();
        info_.pData = constants.data();
    }
    Specialization(const Specialization&) = delete;
    Specialization& operator=(const Specialization&) = delete;
    const VkSpecializationInfo* info() const { return entries_.empty() ? nullptr : &info_; }

private:
    std::vector<VkSpecializationMapEntry> entries_;
    VkSpecializationInfo info_{};
};

}  // namespace

void Pipeline::createLayout(const LayoutDesc& desc) {
    stages_ = desc.stages;
    std::vector<VkDescriptorSetLayoutBinding> bindings;
    for (std::uint32_t i = 0; i < desc.bindings.size(); ++i)
        bindings.push_back({i, desc.bindings[i], 1, desc.stages, nullptr});
    VkDescriptorSetLayoutCreateInfo setInfo{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO};
    setInfo.flags = VK_DESCRIPTOR_SET_LAYOUT_CREATE_PUSH_DESCRIPTOR_BIT_KHR;
    setInfo.bindingCount = static_cast<std::uint32_t>(bindings.size());
    setInfo.pBindings = bindings.data();
    VK_CHECK(vkCreateDescriptorSetLayout(device_, &setInfo, nullptr, &setLayout_));
    const VkPushConstantRange range{desc.stages, 0, desc.pushConstantBytes};
    VkPipelineLayoutCreateInfo info{VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO};
    info.setLayoutCount = 1;
    info.pSetLayouts = &setLayout_;
    info.pushConstantRangeCount = desc.pushConstantBytes ? 1 : 0;
    info.pPushConstantRanges = &range;
    VK_CHECK(vkCreatePipelineLayout(device_, &info, nullptr, &layout_));
}

Pipeline::Pipeline(VulkanContext& context, std::span<const std::uint32_t> computeSpirv, const LayoutDesc& layout,
                   std::span<const std::uint32_t> constants)
    : device_(context.device()), bindPoint_(VK_PIPELINE_BIND_POINT_COMPUTE) {
    try {
        createLayout(layout);
        ShaderModule module(device_, computeSpirv);
        const Specialization specialization(constants);
        VkComputePipelineCreateInfo info{VK_STRUCTURE_TYPE_COMPUTE_PIPELINE_CREATE_INFO};
        info.stage = stage(VK_SHADER_STAGE_COMPUTE_BIT, module.handle());
        info.stage.pSpecializationInfo = specialization.info();
        info.layout = layout_;
        VK_CHECK(vkCreateComputePipelines(device_, VK_NULL_HANDLE, 1, &info, nullptr, &pipeline_));
    } catch (...) {
        reset();
        throw;
    }
}

Pipeline::Pipeline(VulkanContext& context, const GraphicsDesc& desc, const LayoutDesc& layout)
    : device_(context.device()), bindPoint_(VK_PIPELINE_BIND_POINT_GRAPHICS) {
    try {
        createLayout(layout);
        ShaderModule vs(device_, desc.vertexSpirv);
        ShaderModule fs(device_, desc.fragmentSpirv);
        VkPipelineShaderStageCreateInfo stages[] = {stage(VK_SHADER_STAGE_VERTEX_BIT, vs.handle()),
                                                    stage(VK_SHADER_STAGE_FRAGMENT_BIT, fs.handle())};
        const Specialization specialization(desc.fragmentConstants);
        stages[1].pSpecializationInfo = specialization.info();

        const VkVertexInputBindingDescription binding{0, desc.vertexInput.stride, VK_VERTEX_INPUT_RATE_VERTEX};
        VkPipelineVertexInputStateCreateInfo vertexInput{VK_STRUCTURE_TYPE_PIPELINE_VERTEX_INPUT_STATE_CREATE_INFO};
        if (desc.vertexInput.stride) {
            vertexInput.vertexBindingDescriptionCount = 1;
            vertexInput.pVertexBindingDescriptions = &binding;
            vertexInput.vertexAttributeDescriptionCount =
                static_cast<std::uint32_t>(desc.vertexInput.attributes.size());
            vertexInput.pVertexAttributeDescriptions = desc.vertexInput.attributes.data();
        }
        VkPipelineInputAssemblyStateCreateInfo assembly{VK_STRUCTURE_TYPE_PIPELINE_INPUT_ASSEMBLY_STATE_CREATE_INFO};
        assembly.topology = VK_PRIMITIVE_TOPOLOGY_TRIANGLE_LIST;
        VkPipelineViewportStateCreateInfo viewport{VK_STRUCTURE_TYPE_PIPELINE_VIEWPORT_STATE_CREATE_INFO};
        viewport.viewportCount = 1;
        viewport.scissorCount = 1;
        VkPipelineRasterizationStateCreateInfo raster{VK_STRUCTURE_TYPE_PIPELINE_RASTERIZATION_STATE_CREATE_INFO};
        raster.polygonMode = VK_POLYGON_MODE_FILL;
        raster.cullMode = desc.cullMode;
        raster.frontFace = VK_FRONT_FACE_COUNTER_CLOCKWISE;
        raster.lineWidth = 1.0f;
        VkPipelineMultisampleStateCreateInfo multisample{VK_STRUCTURE_TYPE_PIPELINE_MULTISAMPLE_STATE_CREATE_INFO};
        multisample.rasterizationSamples = VK_SAMPLE_COUNT_1_BIT;
        VkPipelineDepthStencilStateCreateInfo depth{VK_STRUCTURE_TYPE_PIPELINE_DEPTH_STENCIL_STATE_CREATE_INFO};
        const bool hasDepth = desc.depthFormat != VK_FORMAT_UNDEFINED;
        depth.depthTestEnable = hasDepth;
        depth.depthWriteEnable = hasDepth && desc.depthWrite;
        depth.depthCompareOp = desc.depthCompare;
        std::vector<VkPipelineColorBlendAttachmentState> blends(desc.colorFormats.size());
        for (auto& b : blends) {
            b.colorWriteMask = VK_COLOR_COMPONENT_R_BIT | VK_COLOR_COMPONENT_G_BIT | VK_COLOR_COMPONENT_B_BIT |
                               VK_COLOR_COMPONENT_A_BIT;
            if (desc.premultipliedBlend) {
                b.blendEnable = VK_TRUE;
                b.srcColorBlendFactor = b.srcAlphaBlendFactor = VK_BLEND_FACTOR_ONE;
                b.dstColorBlendFactor = b.dstAlphaBlendFactor = VK_BLEND_FACTOR_ONE_MINUS_SRC_ALPHA;
                b.colorBlendOp = b.alphaBlendOp = VK_BLEND_OP_ADD;
            }
        }
        VkPipelineColorBlendStateCreateInfo blend{VK_STRUCTURE_TYPE_PIPELINE_COLOR_BLEND_STATE_CREATE_INFO};
        blend.attachmentCount = static_cast<std::uint32_t>(blends.size());
        blend.pAttachments = blends.data();
        const VkDynamicState dynamicStates[] = {VK_DYNAMIC_STATE_VIEWPORT, VK_DYNAMIC_STATE_SCISSOR};
        VkPipelineDynamicStateCreateInfo dynamic{VK_STRUCTURE_TYPE_PIPELINE_DYNAMIC_STATE_CREATE_INFO};
        dynamic.dynamicStateCount = 2;
        dynamic.pDynamicStates = dynamicStates;
        // Dynamic rendering: formats instead of a render pass.
        VkPipelineRenderingCreateInfo rendering{VK_STRUCTURE_TYPE_PIPELINE_RENDERING_CREATE_INFO};
        rendering.colorAttachmentCount = static_cast<std::uint32_t>(desc.colorFormats.size());
        rendering.pColorAttachmentFormats = desc.colorFormats.data();
        rendering.depthAttachmentFormat = desc.depthFormat;

        VkGraphicsPipelineCreateInfo info{VK_STRUCTURE_TYPE_GRAPHICS_PIPELINE_CREATE_INFO, &rendering};
        info.stageCount = 2;
        info.pStages = stages;
        info.pVertexInputState = &vertexInput;
        info.pInputAssemblyState = &assembly;
        info.pViewportState = &viewport;
        info.pRasterizationState = &raster;
        info.pMultisampleState = &multisample;
        info.pDepthStencilState = &depth;
        info.pColorBlendState = &blend;
        info.pDynamicState = &dynamic;
        info.layout = layout_;
        VK_CHECK(vkCreateGraphicsPipelines(device_, VK_NULL_HANDLE, 1, &info, nullptr, &pipeline_));
    } catch (...) {
        reset();
        throw;
    }
}

Pipeline& Pipeline::operator=(Pipeline&& other) noexcept {
    if (this != &other) {
        reset();
        device_ = std::exchange(other.device_, VK_NULL_HANDLE);
        setLayout_ = std::exchange(other.setLayout_, VK_NULL_HANDLE);
        layout_ = std::exchange(other.layout_, VK_NULL_HANDLE);
        pipeline_ = std::exchange(other.pipeline_, VK_NULL_HANDLE);
        bindPoint_ = other.bindPoint_;
        stages_ = other.stages_;
    }
    return *this;
}

void Pipeline::reset() {
    if (pipeline_) vkDestroyPipeline(device_, pipeline_, nullptr);
    if (layout_) vkDestroyPipelineLayout(device_, layout_, nullptr);
    if (setLayout_) vkDestroyDescriptorSetLayout(device_, setLayout_, nullptr);
    pipeline_ = VK_NULL_HANDLE;
    layout_ = VK_NULL_HANDLE;
    setLayout_ = VK_NULL_HANDLE;
}

void Pipeline::pushConstants(VkCommandBuffer cmd, const void* data, std::uint32_t bytes) const {
    vkCmdPushConstants(cmd, layout_, stages_, 0, bytes, data);
}

DescriptorPush& DescriptorPush::storageImage(std::uint32_t binding, VkImageView view) {
    entries_.push_back(
        {binding, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, {VK_NULL_HANDLE, view, VK_IMAGE_LAYOUT_GENERAL}, {}});
    return *this;
}

DescriptorPush& DescriptorPush::sampledImage(std::uint32_t binding, VkImageView view, VkImageLayout layout) {
    entries_.push_back({binding, VK_DESCRIPTOR_TYPE_SAMPLED_IMAGE, {VK_NULL_HANDLE, view, layout}, {}});
    return *this;
}

DescriptorPush& DescriptorPush::storageBuffer(std::uint32_t binding, VkBuffer buffer, VkDeviceSize offset,
                                              VkDeviceSize range) {
    entries_.push_back({binding, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, {}, {buffer, offset, range}});
    return *this;
}

DescriptorPush& DescriptorPush::uniformBuffer(std::uint32_t binding, VkBuffer buffer, VkDeviceSize offset,
                                              VkDeviceSize range) {
    entries_.push_back({binding, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, {}, {buffer, offset, range}});
    return *this;
}

void DescriptorPush::push(const VulkanContext& context, VkCommandBuffer cmd, const Pipeline& pipeline) {
    std::vector<VkWriteDescriptorSet> writes;
    writes.reserve(entries_.size());
    for (const Entry& e : entries_) {  // entries_ no longer grows: the pointers stay valid
        VkWriteDescriptorSet w{VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET};
        w.dstBinding = e.binding;
        w.descriptorCount = 1;
        w.descriptorType = e.type;
        if (e.type == VK_DESCRIPTOR_TYPE_STORAGE_BUFFER || e.type == VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER)
            w.pBufferInfo = &e.buffer;
        else
            w.pImageInfo = &e.image;
        writes.push_back(w);
    }
    context.cmdPushDescriptorSet()(cmd, pipeline.bindPoint(), pipeline.layout(), 0,
                                   static_cast<std::uint32_t>(writes.size()), writes.data());
}

void setFullViewport(VkCommandBuffer cmd, VkExtent2D extent) {
    const VkViewport viewport{0.0f, 0.0f, static_cast<float>(extent.width), static_cast<float>(extent.height),
                              0.0f, 1.0f};
    const VkRect2D scissor{{0, 0}, extent};
    vkCmdSetViewport(cmd, 0, 1, &viewport);
    vkCmdSetScissor(cmd, 0, 1, &scissor);
}

VkRenderingAttachmentInfo clearedColourAttachment(VkImageView view, VkClearColorValue clear) {
    VkRenderingAttachmentInfo info{VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO};
    info.imageView = view;
    info.imageLayout = VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL;
    info.loadOp = VK_ATTACHMENT_LOAD_OP_CLEAR;
    info.storeOp = VK_ATTACHMENT_STORE_OP_STORE;
    info.clearValue.color = clear;
    return info;
}

VkRenderingAttachmentInfo loadedColourAttachment(VkImageView view) {
    VkRenderingAttachmentInfo info = clearedColourAttachment(view);
    info.loadOp = VK_ATTACHMENT_LOAD_OP_LOAD;
    return info;
}

void beginColourRendering(VkCommandBuffer cmd, const VkRenderingAttachmentInfo& colour, VkExtent2D extent) {
    VkRenderingInfo rendering{VK_STRUCTURE_TYPE_RENDERING_INFO};
    rendering.renderArea = {{0, 0}, extent};
    rendering.layerCount = 1;
    rendering.colorAttachmentCount = 1;
    rendering.pColorAttachments = &colour;
    vkCmdBeginRendering(cmd, &rendering);
    setFullViewport(cmd, extent);
}

void dispatch2D(VkCommandBuffer cmd, std::uint32_t width, std::uint32_t height, std::uint32_t groupX,
                std::uint32_t groupY) {
    vkCmdDispatch(cmd, (width + groupX - 1) / groupX, (height + groupY - 1) / groupY, 1);
}

}  // namespace aamap::vk
