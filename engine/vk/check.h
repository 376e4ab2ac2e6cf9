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

// Test hook for device failure mid-run (tests/robustness): AAMAP_TEST_VK_FAULT=<VkResult name>@<n>,
// e.g. VK_ERROR_DEVICE_LOST@1, makes every queue wait after the first n return that result instead
// of `result`, as a lost device does. Unset (normal use) it returns `result` unchanged.
VkResult withTestFault(VkResult result);

}  // namespace aamap::vk

#define VK_CHECK(call)                                                                      \
    do {                                                                                    \
        const VkResult aamapVkResult_ = (call);                                             \
        if (aamapVkResult_ != VK_SUCCESS)                                                   \
            throw ::aamap::vk::VulkanError(#call, aamapVkResult_, __FILE__, __LINE__);      \
    } while (false)
