#include "engine/vk/resources.h"

#include <algorithm>
#include <cstring>
#include <stdexcept>
#include <utility>

#include <fmt/format.h>

#include "core/error.h"
#include "engine/vk/check.h"
#include "engine/vk/context.h"

namespace aamap::vk {
namespace {

std::uint32_t findMemoryType(const VulkanContext& context, std::uint32_t typeBits, VkMemoryPropertyFlags want) {
    const VkPhysicalDeviceMemoryProperties& props = context.memoryProperties();
    for (std::uint32_t i = 0; i < props.memoryTypeCount; ++i)
        if ((typeBits & (1u << i)) && (props.memoryTypes[i].propertyFlags & want) == want) return i;
    throw EnvironmentError(fmt::format("no Vulkan memory type with flags {:#x} for bits {:#x}", want, typeBits));
}

VkDeviceMemory allocateDedicated(VulkanContext& context, const VkMemoryRequirements& req, VkMemoryPropertyFlags flags,
                                 VkImage image, VkBuffer buffer) {
    VkMemoryDedicatedAllocateInfo dedicated{VK_STRUCTURE_TYPE_MEMORY_DEDICATED_ALLOCATE_INFO};
    dedicated.image = image;
    dedicated.buffer = buffer;
    VkMemoryAllocateInfo info{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO, &dedicated};
    info.allocationSize = req.size;
    info.memoryTypeIndex = findMemoryType(context, req.memoryTypeBits, flags);
    VkDeviceMemory memory = VK_NULL_HANDLE;
    VK_CHECK(vkAllocateMemory(context.device(), &info, nullptr, &memory));
    return memory;
}

}  // namespace

VkFormat toVkFormat(graph::Format format) {
    switch (format) {
        case graph::Format::RGBA8Unorm: return VK_FORMAT_R8G8B8A8_UNORM;
        case graph::Format::RGBA16Float: return VK_FORMAT_R16G16B16A16_SFLOAT;
        case graph::Format::RGBA32Float: return VK_FORMAT_R32G32B32A32_SFLOAT;
        case graph::Format::R32Float: return VK_FORMAT_R32_SFLOAT;
        case graph::Format::R16Float: return VK_FORMAT_R16_SFLOAT;
        case graph::Format::D32Float: return VK_FORMAT_D32_SFLOAT;
    }
    return VK_FORMAT_UNDEFINED;
}

Buffer::Buffer(VulkanContext& context, VkDeviceSize bytes, VkBufferUsageFlags usage, bool hostVisible)
    : device_(context.device()), size_(bytes) {
    VkBufferCreateInfo info{VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO};
    info.size = bytes;
    info.usage = usage;
    info.sharingMode = VK_SHARING_MODE_EXCLUSIVE;
    VK_CHECK(vkCreateBuffer(device_, &info, nullptr, &buffer_));
    try {
        VkMemoryRequirements req;
        vkGetBufferMemoryRequirements(device_, buffer_, &req);
        const VkMemoryPropertyFlags flags =
            hostVisible ? VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT
                        : VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT;
        memory_ = allocateDedicated(context, req, flags, VK_NULL_HANDLE, buffer_);
        VK_CHECK(vkBindBufferMemory(device_, buffer_, memory_, 0));
        if (hostVisible) VK_CHECK(vkMapMemory(device_, memory_, 0, VK_WHOLE_SIZE, 0, &mapped_));
    } catch (...) {
        reset();
        throw;
    }
}

Buffer& Buffer::operator=(Buffer&& other) noexcept {
    if (this != &other) {
        reset();
        device_ = std::exchange(other.device_, VK_NULL_HANDLE);
        buffer_ = std::exchange(other.buffer_, VK_NULL_HANDLE);
        memory_ = std::exchange(other.memory_, VK_NULL_HANDLE);
        size_ = std::exchange(other.size_, 0);
        mapped_ = std::exchange(other.mapped_, nullptr);
    }
    return *this;
}

void Buffer::reset() {
    if (buffer_) vkDestroyBuffer(device_, buffer_, nullptr);
    if (memory_) vkFreeMemory(device_, memory_, nullptr);  // unmaps implicitly
    buffer_ = VK_NULL_HANDLE;
    memory_ = VK_NULL_HANDLE;
    mapped_ = nullptr;
    size_ = 0;
}

Image::Image(VulkanContext& context, const ImageInfo& info) : device_(context.device()), info_(info) {
    VkImageCreateInfo ci{VK_STRUCTURE_TYPE_IMAGE_CREATE_INFO};
    ci.flags = info.cube ? VK_IMAGE_CREATE_CUBE_COMPATIBLE_BIT : 0;
    ci.imageType = VK_IMAGE_TYPE_2D;
    ci.format = info.format;
    ci.extent = {info.width, info.height, 1};
    ci.mipLevels = 1;
    ci.arrayLayers = info.layers;
    ci.samples = VK_SAMPLE_COUNT_1_BIT;
    ci.tiling = VK_IMAGE_TILING_OPTIMAL;
    ci.usage = info.usage;
    ci.sharingMode = VK_SHARING_MODE_EXCLUSIVE;
    ci.initialLayout = VK_IMAGE_LAYOUT_UNDEFINED;
    VK_CHECK(vkCreateImage(device_, &ci, nullptr, &image_));
    try {
        VkMemoryRequirements req;
        vkGetImageMemoryRequirements(device_, image_, &req);
        memory_ = allocateDedicated(context, req, VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT, image_, VK_NULL_HANDLE);
        VK_CHECK(vkBindImageMemory(device_, image_, memory_, 0));
        // Views only for images a shader or attachment uses (transfer-only images may not have one).
        const VkImageUsageFlags viewUsages = VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_STORAGE_BIT |
                                             VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT |
                                             VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT;
        if (!(info.usage & viewUsages)) return;
        VkImageViewCreateInfo vi{VK_STRUCTURE_TYPE_IMAGE_VIEW_CREATE_INFO};
        vi.image = image_;
        vi.viewType = info.cube ? VK_IMAGE_VIEW_TYPE_CUBE
                                : (info.layers > 1 ? VK_IMAGE_VIEW_TYPE_2D_ARRAY : VK_IMAGE_VIEW_TYPE_2D);
        vi.format = info.format;
        vi.subresourceRange = range();
        VK_CHECK(vkCreateImageView(device_, &vi, nullptr, &view_));
    } catch (...) {
        reset();
        throw;
    }
}

Image& Image::operator=(Image&& other) noexcept {
    if (this != &other) {
        reset();
        device_ = std::exchange(other.device_, VK_NULL_HANDLE);
        image_ = std::exchange(other.image_, VK_NULL_HANDLE);
        memory_ = std::exchange(other.memory_, VK_NULL_HANDLE);
        view_ = std::exchange(other.view_, VK_NULL_HANDLE);
        info_ = other.info_;
    }
    return *this;
}

void Image::reset() {
    if (view_) vkDestroyImageView(device_, view_, nullptr);
    if (image_) vkDestroyImage(device_, image_, nullptr);
    if (memory_) vkFreeMemory(device_, memory_, nullptr);
    view_ = VK_NULL_HANDLE;
    image_ = VK_NULL_HANDLE;
    memory_ = VK_NULL_HANDLE;
}

VkImageAspectFlags Image::aspect() const {
    switch (info_.format) {
        case VK_FORMAT_D32_SFLOAT:
        case VK_FORMAT_D16_UNORM: return VK_IMAGE_ASPECT_DEPTH_BIT;
        default: return VK_IMAGE_ASPECT_COLOR_BIT;
    }
}

void submitAndWait(VulkanContext& context, const std::function<void(VkCommandBuffer)>& record) {
    VkDevice device = context.device();
    VkCommandBufferAllocateInfo ai{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
    ai.commandPool = context.commandPool();
    ai.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
    ai.commandBufferCount = 1;
    VkCommandBuffer cmd = VK_NULL_HANDLE;
    VK_CHECK(vkAllocateCommandBuffers(device, &ai, &cmd));
    VkFence fence = VK_NULL_HANDLE;
    auto cleanup = [&] {
        if (fence) vkDestroyFence(device, fence, nullptr);
        vkFreeCommandBuffers(device, context.commandPool(), 1, &cmd);
    };
    try {
        VkCommandBufferBeginInfo bi{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
        bi.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
        VK_CHECK(vkBeginCommandBuffer(cmd, &bi));
        record(cmd);
        VK_CHECK(vkEndCommandBuffer(cmd));
        VkFenceCreateInfo fi{VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
        VK_CHECK(vkCreateFence(device, &fi, nullptr, &fence));
        VkCommandBufferSubmitInfo cmdInfo{VK_STRUCTURE_TYPE_COMMAND_BUFFER_SUBMIT_INFO};
        cmdInfo.commandBuffer = cmd;
        VkSubmitInfo2 submit{VK_STRUCTURE_TYPE_SUBMIT_INFO_2};
        submit.commandBufferInfoCount = 1;
        submit.pCommandBufferInfos = &cmdInfo;
        VK_CHECK(vkQueueSubmit2(context.queue(), 1, &submit, fence));
        VK_CHECK(vkWaitForFences(device, 1, &fence, VK_TRUE, UINT64_MAX));
    } catch (...) {
        vkQueueWaitIdle(context.queue());  // the buffer may be in flight; never free it early
        cleanup();
        throw;
    }
    cleanup();
}

Buffer uploadBuffer(VulkanContext& context, std::span<const std::byte> bytes, VkBufferUsageFlags usage) {
    const VkDeviceSize size = std::max<VkDeviceSize>(bytes.size(), 4);  // zero-sized buffers are invalid
    Buffer staging(context, size, VK_BUFFER_USAGE_TRANSFER_SRC_BIT, true);
    if (!bytes.empty()) std::memcpy(staging.mapped(), bytes.data(), bytes.size());
    Buffer buffer(context, size, usage | VK_BUFFER_USAGE_TRANSFER_DST_BIT, false);
    submitAndWait(context, [&](VkCommandBuffer cmd) {
        const VkBufferCopy copy{0, 0, size};
        vkCmdCopyBuffer(cmd, staging.handle(), buffer.handle(), 1, &copy);
        // The caller's first use comes in a later submission; the fence wait orders the copy
        // before it on the host side, and this barrier makes the data available to every stage.
        recordMemoryBarrier(cmd, VK_PIPELINE_STAGE_2_COPY_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT,
                            VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, VK_ACCESS_2_MEMORY_READ_BIT);
    });
    return buffer;
}

namespace {
VkBufferImageCopy wholeImage(const Image& image) {
    VkBufferImageCopy region{};
    region.imageSubresource = {image.aspect(), 0, 0, 1};
    region.imageExtent = {image.info().width, image.info().height, 1};
    return region;
}
}  // namespace

Image uploadImage(VulkanContext& context, ImageInfo info, std::span<const std::byte> texels,
                  VkPipelineStageFlags2 readStages) {
    const std::size_t texelCount = static_cast<std::size_t>(info.width) * info.height * info.layers;
    if (texelCount == 0 || texels.empty() || texels.size() % texelCount != 0)
        throw std::logic_error("uploadImage: the texels do not fill the image");
    info.usage |= VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT;
    Image image(context, info);
    Buffer staging(context, texels.size(), VK_BUFFER_USAGE_TRANSFER_SRC_BIT, true);
    std::memcpy(staging.mapped(), texels.data(), texels.size());
    submitAndWait(context, [&](VkCommandBuffer cmd) {
        recordImageTransition(cmd, image.handle(), image.range(),
                              {VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL,
                               VK_PIPELINE_STAGE_2_NONE, VK_ACCESS_2_NONE, VK_PIPELINE_STAGE_2_COPY_BIT,
                               VK_ACCESS_2_TRANSFER_WRITE_BIT});
        VkBufferImageCopy region{};
        region.imageSubresource = {image.aspect(), 0, 0, info.layers};
        region.imageExtent = {info.width, info.height, 1};
        vkCmdCopyBufferToImage(cmd, staging.handle(), image.handle(), VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1, &region);
        recordImageTransition(cmd, image.handle(), image.range(),
                              {VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL,
                               VK_PIPELINE_STAGE_2_COPY_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT, readStages,
                               VK_ACCESS_2_SHADER_SAMPLED_READ_BIT});
    });
    return image;
}

VkImageMemoryBarrier2 imageBarrier(VkImage image, const VkImageSubresourceRange& range,
                                   const ImageTransition& transition) {
    VkImageMemoryBarrier2 barrier{VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER_2};
    barrier.srcStageMask = transition.srcStage;
    barrier.srcAccessMask = transition.srcAccess;
    barrier.dstStageMask = transition.dstStage;
    barrier.dstAccessMask = transition.dstAccess;
    barrier.oldLayout = transition.from;
    barrier.newLayout = transition.to;
    barrier.srcQueueFamilyIndex = barrier.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
    barrier.image = image;
    barrier.subresourceRange = range;
    return barrier;
}

void recordImageTransition(VkCommandBuffer cmd, VkImage image, const VkImageSubresourceRange& range,
                           const ImageTransition& transition) {
    const VkImageMemoryBarrier2 barrier = imageBarrier(image, range, transition);
    VkDependencyInfo dep{VK_STRUCTURE_TYPE_DEPENDENCY_INFO};
    dep.imageMemoryBarrierCount = 1;
    dep.pImageMemoryBarriers = &barrier;
    vkCmdPipelineBarrier2(cmd, &dep);
}

void recordMemoryBarrier(VkCommandBuffer cmd, VkPipelineStageFlags2 srcStage, VkAccessFlags2 srcAccess,
                         VkPipelineStageFlags2 dstStage, VkAccessFlags2 dstAccess) {
    VkMemoryBarrier2 barrier{VK_STRUCTURE_TYPE_MEMORY_BARRIER_2};
    barrier.srcStageMask = srcStage;
    barrier.srcAccessMask = srcAccess;
    barrier.dstStageMask = dstStage;
    barrier.dstAccessMask = dstAccess;
    VkDependencyInfo dep{VK_STRUCTURE_TYPE_DEPENDENCY_INFO};
    dep.memoryBarrierCount = 1;
    dep.pMemoryBarriers = &barrier;
    vkCmdPipelineBarrier2(cmd, &dep);
}

void recordCopyBufferToImage(VkCommandBuffer cmd, const Buffer& src, const Image& dst) {
    const VkBufferImageCopy region = wholeImage(dst);
    vkCmdCopyBufferToImage(cmd, src.handle(), dst.handle(), VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1, &region);
}

void recordCopyImageToBuffer(VkCommandBuffer cmd, const Image& src, const Buffer& dst) {
    const VkBufferImageCopy region = wholeImage(src);
    vkCmdCopyImageToBuffer(cmd, src.handle(), VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, dst.handle(), 1, &region);
}

}  // namespace aamap::vk
