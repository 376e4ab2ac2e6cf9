#pragma once
// The GPU side of the bandwidth limit: a device-local buffer-to-buffer copy of one image's bytes,
// timed with timestamp queries around the copy alone. Built on the public engine API only.
#include <cstddef>

#include <vulkan/vulkan.h>

#include "engine/vk/resources.h"

namespace aamap {
class VulkanContext;
}

namespace aamap::bench {

class GpuCopyTimer {
public:
    explicit GpuCopyTimer(VulkanContext& context);
    ~GpuCopyTimer();
    GpuCopyTimer(const GpuCopyTimer&) = delete;
    GpuCopyTimer& operator=(const GpuCopyTimer&) = delete;

    // GPU milliseconds of one vkCmdCopyBuffer of `bytes` bytes (buffers are kept between calls).
    double copyMilliseconds(std::size_t bytes);

private:
    void ensureBuffers(std::size_t bytes);

    VulkanContext& context_;
    VkQueryPool queries_ = VK_NULL_HANDLE;
    vk::Buffer src_, dst_;
    std::size_t bytes_ = 0;
};

}  // namespace aamap::bench
