#pragma once
// GPU buffers and images with one dedicated allocation each (plenty at this scale), one-shot
// command submission, and host upload / readback helpers.
#include <cstddef>
#include <cstdint>
#include <functional>
#include <span>
#include <vector>

#include <vulkan/vulkan.h>

#include "engine/graph/render_graph.h"

namespace aamap {
class VulkanContext;
}

namespace aamap::vk {

VkFormat toVkFormat(graph::Format format);

// Move-only owner of a VkBuffer and its memory. Host-visible buffers stay mapped.
class Buffer {
public:
    Buffer() = default;
    Buffer(VulkanContext& context, VkDeviceSize bytes, VkBufferUsageFlags usage, bool hostVisible);
    ~Buffer() { reset(); }
    Buffer(Buffer&& other) noexcept { *this = std::move(other); }
    Buffer& operator=(Buffer&& other) noexcept;
    Buffer(const Buffer&) = delete;
    Buffer& operator=(const Buffer&) = delete;

    VkBuffer handle() const { return buffer_; }
    VkDeviceSize size() const { return size_; }
    void* mapped() const { return mapped_; }  // null unless host-visible
    explicit operator bool() const { return buffer_ != VK_NULL_HANDLE; }
    void reset();

private:
    VkDevice device_ = VK_NULL_HANDLE;
    VkBuffer buffer_ = VK_NULL_HANDLE;
    VkDeviceMemory memory_ = VK_NULL_HANDLE;
    VkDeviceSize size_ = 0;
    void* mapped_ = nullptr;
};

struct ImageInfo {
    VkFormat format = VK_FORMAT_R32_SFLOAT;
    std::uint32_t width = 1, height = 1, layers = 1;
    bool cube = false;  // view as a cube map (layers must be 6)
    VkImageUsageFlags usage = 0;
};

// Move-only owner of a 2D (array / cube) image, its memory and one view of all layers.
class Image {
public:
    Image() = default;
    Image(VulkanContext& context, const ImageInfo& info);
    ~Image() { reset(); }
    Image(Image&& other) noexcept { *this = std::move(other); }
    Image& operator=(Image&& other) noexcept;
    Image(const Image&) = delete;
    Image& operator=(const Image&) = delete;

    VkImage handle() const { return image_; }
    VkImageView view() const { return view_; }  // null for transfer-only images
    const ImageInfo& info() const { return info_; }
    VkImageAspectFlags aspect() const;
    VkImageSubresourceRange range() const { return {aspect(), 0, 1, 0, info_.layers}; }
    explicit operator bool() const { return image_ != VK_NULL_HANDLE; }
    void reset();

private:
    VkDevice device_ = VK_NULL_HANDLE;
    VkImage image_ = VK_NULL_HANDLE;
    VkDeviceMemory memory_ = VK_NULL_HANDLE;
    VkImageView view_ = VK_NULL_HANDLE;
    ImageInfo info_;
};

// Records `record` into a fresh command buffer, submits it and waits for it.
void submitAndWait(VulkanContext& context, const std::function<void(VkCommandBuffer)>& record);

// A device-local buffer filled with `bytes` through a staging buffer (usage gains TRANSFER_DST).
Buffer uploadBuffer(VulkanContext& context, std::span<const std::byte> bytes, VkBufferUsageFlags usage);

// A sampled image filled with tightly packed texels of every layer (mip 0) through a staging
// buffer, left in SHADER_READ_ONLY_OPTIMAL and visible to `readStages` (usage gains
// TRANSFER_DST and SAMPLED). For static inputs the render graph does not own, e.g. a texture atlas.
Image uploadImage(VulkanContext& context, ImageInfo info, std::span<const std::byte> texels,
                  VkPipelineStageFlags2 readStages);

// One layout transition of an image the render graph does not own (an upload, a swapchain image):
// the graph derives its own barriers, everything else records them through here.
struct ImageTransition {
    VkImageLayout from = VK_IMAGE_LAYOUT_UNDEFINED, to = VK_IMAGE_LAYOUT_UNDEFINED;
    VkPipelineStageFlags2 srcStage = VK_PIPELINE_STAGE_2_NONE;
    VkAccessFlags2 srcAccess = VK_ACCESS_2_NONE;
    VkPipelineStageFlags2 dstStage = VK_PIPELINE_STAGE_2_NONE;
    VkAccessFlags2 dstAccess = VK_ACCESS_2_NONE;
};
// The barrier for `transition` (the graph executor batches these; the rest record one at a time).
VkImageMemoryBarrier2 imageBarrier(VkImage image, const VkImageSubresourceRange& range,
                                   const ImageTransition& transition);
void recordImageTransition(VkCommandBuffer cmd, VkImage image, const VkImageSubresourceRange& range,
                           const ImageTransition& transition);

// Image copies for tightly packed texels of layer 0, mip 0 (layout must be TRANSFER_SRC/DST).
// One global memory dependency (synchronization2): for hazards that are not about one
// resource, e.g. making copies visible to the host or to every later stage.
void recordMemoryBarrier(VkCommandBuffer cmd, VkPipelineStageFlags2 srcStage, VkAccessFlags2 srcAccess,
                         VkPipelineStageFlags2 dstStage, VkAccessFlags2 dstAccess);

void recordCopyBufferToImage(VkCommandBuffer cmd, const Buffer& src, const Image& dst);
void recordCopyImageToBuffer(VkCommandBuffer cmd, const Image& src, const Buffer& dst);

}  // namespace aamap::vk
