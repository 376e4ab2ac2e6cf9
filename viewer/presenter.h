#pragma once
// Puts CPU images on a GLFW window through a Vulkan swapchain: each frame is composed on the CPU
// (nearest-neighbour, letterboxed), copied into the acquired swapchain image and presented. The
// swapchain is UNORM, so the bytes on screen are the bytes of the PNGs `aamap run` writes; a
// screenshot reads the presented image back from the GPU.
#include <cstdint>
#include <optional>
#include <vector>

#include <vulkan/vulkan.h>

#include "core/image_io.h"
#include "engine/vk/resources.h"

struct GLFWwindow;

namespace aamap {

class VulkanContext;

class Presenter {
public:
    Presenter(VulkanContext& context, GLFWwindow* window);  // throws EnvironmentError
    ~Presenter();
    Presenter(const Presenter&) = delete;
    Presenter& operator=(const Presenter&) = delete;

    // Shows `content` scaled to fit the window (black when empty). With readBack, returns the
    // content as the GPU presented it (read from the swapchain image, at content resolution).
    std::optional<ImageRGB8> present(const ImageRGB8& content, bool readBack);

private:
    struct Layout {
        float scale = 1.0f;
        int offsetX = 0, offsetY = 0;
    };
    void createSwapchain();
    void destroySwapchain();
    Layout layoutFor(int contentWidth, int contentHeight) const;

    VulkanContext& context_;
    GLFWwindow* window_;
    VkSurfaceKHR surface_ = VK_NULL_HANDLE;
    VkSwapchainKHR swapchain_ = VK_NULL_HANDLE;
    VkFormat format_ = VK_FORMAT_UNDEFINED;
    bool bgr_ = true;  // B8G8R8A8 (else R8G8B8A8)
    VkExtent2D extent_{0, 0};
    std::vector<VkImage> images_;
    std::vector<VkSemaphore> presentReady_;  // one per swapchain image: signalled by the copy, waited by present
    VkSemaphore acquired_ = VK_NULL_HANDLE;
    VkFence done_ = VK_NULL_HANDLE;
    VkCommandBuffer cmd_ = VK_NULL_HANDLE;
    vk::Buffer upload_, readback_;
};

}  // namespace aamap
