// graph::Usage -> Vulkan layout / stages / access, and host-side conversion of read-back texels.
#include <cstddef>
#include <cstring>

#include "engine/vk/graph_executor.h"

namespace aamap::vk {
namespace {

// Shader access can come from any shader stage the queue runs (vertex pulling, fragment, compute).
constexpr VkPipelineStageFlags2 kShaderStages = VK_PIPELINE_STAGE_2_VERTEX_SHADER_BIT |
                                                VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT |
                                                VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT;

float halfToFloat(std::uint16_t h) {
    const std::uint32_t sign = (h & 0x8000u) << 16;
    std::uint32_t exponent = (h >> 10) & 0x1fu;
    std::uint32_t mantissa = h & 0x3ffu;
    std::uint32_t bits;
    if (exponent == 0x1f) {
        bits = sign | 0x7f800000u | (mantissa << 13);  // inf / nan
    } else if (exponent != 0) {
        bits = sign | ((exponent + 112) << 23) | (mantissa << 13);
    } else if (mantissa == 0) {
        bits = sign;
    } else {  // subnormal: normalise
        exponent = 113;
        while (!(mantissa & 0x400u)) {
            mantissa <<= 1;
            --exponent;
        }
        bits = sign | (exponent << 23) | ((mantissa & 0x3ffu) << 13);
    }
    float f;
    std::memcpy(&f, &bits, 4);
    return f;
}

}  // namespace

UsageState usageState(graph::Usage usage, bool depth) {
    using graph::Usage;
    switch (usage) {
        case Usage::Undefined: return {VK_IMAGE_LAYOUT_UNDEFINED, VK_PIPELINE_STAGE_2_NONE, VK_ACCESS_2_NONE};
        case Usage::Sampled:
            return {depth ? VK_IMAGE_LAYOUT_DEPTH_STENCIL_READ_ONLY_OPTIMAL : VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL,
                    kShaderStages, VK_ACCESS_2_SHADER_SAMPLED_READ_BIT};
        case Usage::StorageRead: return {VK_IMAGE_LAYOUT_GENERAL, kShaderStages, VK_ACCESS_2_SHADER_STORAGE_READ_BIT};
        case Usage::StorageWrite:
            return {VK_IMAGE_LAYOUT_GENERAL, kShaderStages,
                    VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT | VK_ACCESS_2_SHADER_STORAGE_READ_BIT};
        case Usage::ColorAttachment:
            return {VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL, VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT,
                    VK_ACCESS_2_COLOR_ATTACHMENT_READ_BIT | VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT};
        case Usage::DepthAttachment:
            return {VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL,
                    VK_PIPELINE_STAGE_2_EARLY_FRAGMENT_TESTS_BIT | VK_PIPELINE_STAGE_2_LATE_FRAGMENT_TESTS_BIT,
                    VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_READ_BIT | VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT};
        case Usage::TransferSrc:
            return {VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT,
                    VK_ACCESS_2_TRANSFER_READ_BIT};
        case Usage::TransferDst:
            // All transfer commands: copies, blits and clears.
            return {VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT,
                    VK_ACCESS_2_TRANSFER_WRITE_BIT};
    }
    return {};
}

VkImageUsageFlags imageUsageFlags(graph::Usage usage) {
    using graph::Usage;
    switch (usage) {
        case Usage::Sampled: return VK_IMAGE_USAGE_SAMPLED_BIT;
        case Usage::StorageRead:
        case Usage::StorageWrite: return VK_IMAGE_USAGE_STORAGE_BIT;
        case Usage::ColorAttachment: return VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT;
        case Usage::DepthAttachment: return VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT;
        case Usage::TransferSrc: return VK_IMAGE_USAGE_TRANSFER_SRC_BIT;
        case Usage::TransferDst: return VK_IMAGE_USAGE_TRANSFER_DST_BIT;
        case Usage::Undefined: return 0;
    }
    return 0;
}

std::uint32_t HostData::channels() const {
    switch (format) {
        case graph::Format::RGBA8Unorm:
        case graph::Format::RGBA16Float:
        case graph::Format::RGBA32Float: return 4;
        case graph::Format::R32Float:
        case graph::Format::R16Float:
        case graph::Format::D32Float: return 1;
    }
    return 1;
}

std::vector<float> HostData::floats() const {
    const std::size_t n = static_cast<std::size_t>(width) * height * channels();
    std::vector<float> out(n);
    switch (format) {
        case graph::Format::RGBA32Float:
        case graph::Format::R32Float:
        case graph::Format::D32Float: std::memcpy(out.data(), bytes.data(), n * 4); break;
        case graph::Format::RGBA16Float:
        case graph::Format::R16Float:
            for (std::size_t i = 0; i < n; ++i) {
                std::uint16_t h;
                std::memcpy(&h, bytes.data() + 2 * i, 2);
                out[i] = halfToFloat(h);
            }
            break;
        case graph::Format::RGBA8Unorm:
            for (std::size_t i = 0; i < n; ++i)
                out[i] = static_cast<float>(std::to_integer<unsigned>(bytes[i])) / 255.0f;
            break;
    }
    return out;
}

}  // namespace aamap::vk
