#include "gpu_copy.h"

#include "engine/vk/check.h"
#include "engine/vk/context.h"
#include "engine/vk/resources.h"

namespace aamap::bench {
namespace {

// Everything earlier (the fill, the previous copy) before this copy's reads and writes.
void copyBarrier(VkCommandBuffer cmd) {
    vk::recordMemoryBarrier(cmd, VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, VK_ACCESS_2_MEMORY_WRITE_BIT,
                            VK_PIPELINE_STAGE_2_COPY_BIT | VK_PIPELINE_STAGE_2_CLEAR_BIT,
                            VK_ACCESS_2_TRANSFER_READ_BIT | VK_ACCESS_2_TRANSFER_WRITE_BIT);
}

}  // namespace

GpuCopyTimer::GpuCopyTimer(VulkanContext& context) : context_(context) {
    VkQueryPoolCreateInfo info{VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO};
    info.queryType = VK_QUERY_TYPE_TIMESTAMP;
    info.queryCount = 2;
    VK_CHECK(vkCreateQueryPool(context_.device(), &info, nullptr, &queries_));
}

GpuCopyTimer::~GpuCopyTimer() {
    vkDeviceWaitIdle(context_.device());
    vkDestroyQueryPool(context_.device(), queries_, nullptr);
}

void GpuCopyTimer::ensureBuffers(std::size_t bytes) {
    if (bytes == bytes_) return;
    const VkBufferUsageFlags usage = VK_BUFFER_USAGE_TRANSFER_SRC_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT;
    src_ = vk::Buffer(context_, bytes, usage, false);
    dst_ = vk::Buffer(context_, bytes, usage, false);
    bytes_ = bytes;
    // Defined contents, and both buffers touched once before they are timed.
    vk::submitAndWait(context_, [&](VkCommandBuffer cmd) {
        copyBarrier(cmd);
        vkCmdFillBuffer(cmd, src_.handle(), 0, VK_WHOLE_SIZE, 0x3f000000u);  // 0.5f
        vkCmdFillBuffer(cmd, dst_.handle(), 0, VK_WHOLE_SIZE, 0u);
    });
}

double GpuCopyTimer::copyMilliseconds(std::size_t bytes) {
    ensureBuffers(bytes);
    vk::submitAndWait(context_, [&](VkCommandBuffer cmd) {
        vkCmdResetQueryPool(cmd, queries_, 0, 2);
        copyBarrier(cmd);
        vkCmdWriteTimestamp2(cmd, VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, queries_, 0);
        const VkBufferCopy region{0, 0, bytes};
        vkCmdCopyBuffer(cmd, src_.handle(), dst_.handle(), 1, &region);
        vkCmdWriteTimestamp2(cmd, VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, queries_, 1);
    });
    std::uint64_t stamps[2] = {0, 0};
    VK_CHECK(vkGetQueryPoolResults(context_.device(), queries_, 0, 2, sizeof(stamps), stamps, sizeof(stamps[0]),
                                   VK_QUERY_RESULT_64_BIT | VK_QUERY_RESULT_WAIT_BIT));
    const std::uint32_t bits = context_.timestampValidBits();
    const std::uint64_t mask = bits >= 64 ? ~0ull : ((1ull << bits) - 1);
    const std::uint64_t ticks = ((stamps[1] & mask) - (stamps[0] & mask)) & mask;
    return static_cast<double>(ticks) * context_.timestampPeriodNs() * 1e-6;
}

}  // namespace aamap::bench
