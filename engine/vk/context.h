#pragma once
// The Vulkan 1.3 instance, device and queue, with the Khronos validation layer switchable.
// Integration-facing part; the engine may add members but keeps these signatures.
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include <vulkan/vulkan.h>

namespace aamap {

struct ContextOptions {
    bool validation = false;  // enable VK_LAYER_KHRONOS_validation and count its messages
    // "" picks the first discrete GPU, else integrated, else virtual, else CPU (lavapipe).
    // Otherwise a device index ("0") or a case-insensitive substring of the device name.
    std::string device;
    // Opt-in for a window (the viewer); left empty, the context stays headless. Extra instance
    // extensions (the surface ones GLFW names), VK_KHR_swapchain on the device, and a test the
    // chosen queue family must also pass (presentation support).
    std::vector<std::string> instanceExtensions;
    bool swapchain = false;
    std::function<bool(VkInstance, VkPhysicalDevice, std::uint32_t queueFamily)> canPresent;
};

class VulkanContext {
public:
    explicit VulkanContext(const ContextOptions& options);  // throws EnvironmentError with a clear message
    ~VulkanContext();
    VulkanContext(const VulkanContext&) = delete;
    VulkanContext& operator=(const VulkanContext&) = delete;

    // Names of all physical devices, in enumeration order (for --device and error messages).
    static std::vector<std::string> listDevices();

    const std::string& deviceName() const;
    bool validationEnabled() const;
    // Validation-layer messages of severity warning or error so far (each is also logged).
    std::uint64_t validationMessageCount() const;
    // The same count over every context of the process, including messages raised while a
    // context is destroyed (leaks): what tests check after tearing their context down.
    static std::uint64_t processValidationMessageCount();

    VkInstance instance() const;
    VkPhysicalDevice physicalDevice() const;
    VkDevice device() const;
    VkQueue queue() const;  // one queue with graphics + compute + transfer
    std::uint32_t queueFamily() const;
    double timestampPeriodNs() const;
    std::uint32_t maxImageDimension2D() const;  // the largest 2D image side the device allows

    // Engine-side additions (not needed by integration code).
    std::uint32_t timestampValidBits() const;
    const VkPhysicalDeviceMemoryProperties& memoryProperties() const;
    VkCommandPool commandPool() const;  // resettable buffers, for the queue family above
    PFN_vkCmdPushDescriptorSetKHR cmdPushDescriptorSet() const;  // VK_KHR_push_descriptor entry point

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

}  // namespace aamap
