#pragma once
// Compute and graphics pipelines whose one descriptor set is a push-descriptor set, so there are
// no descriptor pools to manage: passes push their bindings right before each draw or dispatch.
#include <cstdint>
#include <span>
#include <vector>

#include <vulkan/vulkan.h>

namespace aamap {
class VulkanContext;
}

namespace aamap::vk {

struct LayoutDesc {
    std::vector<VkDescriptorType> bindings;  // binding i has type bindings[i], one descriptor each
    std::uint32_t pushConstantBytes = 0;
    VkShaderStageFlags stages = VK_SHADER_STAGE_COMPUTE_BIT;  // for bindings and push constants
};

struct VertexInput {
    std::uint32_t stride = 0;
    std::vector<VkVertexInputAttributeDescription> attributes;  // binding 0
};

struct GraphicsDesc {
    std::span<const std::uint32_t> vertexSpirv;
    std::span<const std::uint32_t> fragmentSpirv;
    VertexInput vertexInput;
    std::vector<VkFormat> colorFormats;
    VkFormat depthFormat = VK_FORMAT_UNDEFINED;  // none
    VkCullModeFlags cullMode = VK_CULL_MODE_NONE;
    VkCompareOp depthCompare = VK_COMPARE_OP_LESS;
    bool depthWrite = true;  // off: test against the depth, keep it (surfaces drawn over others)
    // Premultiplied "over" on every colour attachment: dst = src.rgb + (1 - src.a) dst.
    bool premultipliedBlend = false;
    // Specialisation constants of the fragment stage: constant_id i takes fragmentConstants[i]
    // (32 bits each). Values a pipeline never changes, so the driver compiles them in.
    std::vector<std::uint32_t> fragmentConstants;
};

// Move-only owner of a pipeline, its layout and its push-descriptor set layout.
class Pipeline {
public:
    Pipeline() = default;
    // constants: the compute stage's specialisation constants, as GraphicsDesc::fragmentConstants.
    Pipeline(VulkanContext& context, std::span<const std::uint32_t> computeSpirv, const LayoutDesc& layout,
             std::span<const std::uint32_t> constants = {});
    Pipeline(VulkanContext& context, const GraphicsDesc& desc, const LayoutDesc& layout);
    ~Pipeline() { reset(); }
    Pipeline(Pipeline&& other) noexcept { *this = std::move(other); }
    Pipeline& operator=(Pipeline&& other) noexcept;
    Pipeline(const Pipeline&) = delete;
    Pipeline& operator=(const Pipeline&) = delete;

    VkPipeline handle() const { return pipeline_; }
    VkPipelineLayout layout() const { return layout_; }
    VkPipelineBindPoint bindPoint() const { return bindPoint_; }
    VkShaderStageFlags stages() const { return stages_; }
    void reset();

    void bind(VkCommandBuffer cmd) const { vkCmdBindPipeline(cmd, bindPoint_, pipeline_); }
    void pushConstants(VkCommandBuffer cmd, const void* data, std::uint32_t bytes) const;
    template <class T>
    void pushConstants(VkCommandBuffer cmd, const T& value) const {
        pushConstants(cmd, &value, static_cast<std::uint32_t>(sizeof(T)));
    }

private:
    void createLayout(const LayoutDesc& desc);

    VkDevice device_ = VK_NULL_HANDLE;
    VkDescriptorSetLayout setLayout_ = VK_NULL_HANDLE;
    VkPipelineLayout layout_ = VK_NULL_HANDLE;
    VkPipeline pipeline_ = VK_NULL_HANDLE;
    VkPipelineBindPoint bindPoint_ = VK_PIPELINE_BIND_POINT_COMPUTE;
    VkShaderStageFlags stages_ = 0;
};

// Collects descriptor writes for one push (binding numbers follow the LayoutDesc).
class DescriptorPush {
public:
    DescriptorPush& storageImage(std::uint32_t binding, VkImageView view);  // layout GENERAL
    DescriptorPush& sampledImage(std::uint32_t binding, VkImageView view, VkImageLayout layout);
    DescriptorPush& storageBuffer(std::uint32_t binding, VkBuffer buffer, VkDeviceSize offset = 0,
                                  VkDeviceSize range = VK_WHOLE_SIZE);
    DescriptorPush& uniformBuffer(std::uint32_t binding, VkBuffer buffer, VkDeviceSize offset = 0,
                                  VkDeviceSize range = VK_WHOLE_SIZE);
    void push(const VulkanContext& context, VkCommandBuffer cmd, const Pipeline& pipeline);

private:
    struct Entry {
        std::uint32_t binding;
        VkDescriptorType type;
        VkDescriptorImageInfo image;
        VkDescriptorBufferInfo buffer;
    };
    std::vector<Entry> entries_;
};

// Viewport and scissor covering the whole render area (both are dynamic state in our pipelines).
void setFullViewport(VkCommandBuffer cmd, VkExtent2D extent);

// A dynamic-rendering colour attachment on `view`, cleared to 0 and stored: what every raster
// pass of the Snapshot starts from (black, as rays that miss; 0 also means "nothing here" in the
// id and mask targets).
VkRenderingAttachmentInfo clearedColourAttachment(VkImageView view, VkClearColorValue clear = {});
// The same, loading what the attachment holds: a pass that draws over an earlier one's image.
VkRenderingAttachmentInfo loadedColourAttachment(VkImageView view);

// Begins dynamic rendering into the one colour attachment `colour` (one layer, no depth) of
// `extent`, with the full viewport set: the mask and overlay passes' whole setup.
void beginColourRendering(VkCommandBuffer cmd, const VkRenderingAttachmentInfo& colour, VkExtent2D extent);

// Dispatches enough workgroups of size groupX x groupY to cover width x height.
void dispatch2D(VkCommandBuffer cmd, std::uint32_t width, std::uint32_t height, std::uint32_t groupX,
                std::uint32_t groupY);

}  // namespace aamap::vk
