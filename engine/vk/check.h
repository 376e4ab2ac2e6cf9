#pragma once
// VK_CHECK: turns a failed Vulkan call into an exception naming the call and the result.
#include <stdexcept>
#include <string>

#include <vulkan/vulkan.h>

namespace aamap::vk {

const char* resultName(VkResult result);

class VulkanError : public std::runtime_error {
public:
    VulkanError(const char* call, VkResult result, const char* file, int line);
    VkResult result() const { return result_; }

private:
    VkResult result_;
};

}  // namespace aamap::vk

#define VK_CHECK(call)                                                                      \
    do {                                                                                    \
        const VkResult aamapVkResult_ = (call);                                             \
        if (aamapVkResult_ != VK_SUCCESS)                                                   \
            throw ::aamap::vk::VulkanError(#call, aamapVkResult_, __FILE__, __LINE__);      \
    } while (false)
