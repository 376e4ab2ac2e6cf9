#include "viewer/presenter.h"

#include <algorithm>
#include <cmath>
#include <cstring>

#define GLFW_INCLUDE_VULKAN
#include <GLFW/glfw3.h>
#include <fmt/format.h>

#include "core/error.h"
#include "engine/vk/check.h"
#include "engine/vk/context.h"

namespace aamap {
namespace {

// A transition of the whole (single-layer colour) swapchain image.
void transition(VkCommandBuffer cmd, VkImage image, const vk::ImageTransition& t) {
    vk::recordImageTransition(cmd, image, {VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1}, t);
}

// Which content pixel window pixel X shows (nearest neighbour); the one mapping both ways.
int contentIndex(int X, int offset, float scale) {
    return static_cast<int>(std::floor(static_cast<float>(X - offset) / scale));
}

// The first window pixel that shows content pixel x (scale >= 1, so there is one).
int firstWindowPixel(int x, int offset, float scale) {
    int X = offset + static_cast<int>(std::floor(static_cast<float>(x) * scale)) - 1;
    while (X < offset || contentIndex(X, offset, scale) < x) ++X;
    return X;
}

VkBufferImageCopy wholeImage(VkExtent2D extent) {
    VkBufferImageCopy region{};
    region.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
    region.imageExtent = {extent.width, extent.height, 1};
    return region;
}

}  // namespace

Presenter::Presenter(VulkanContext& context, GLFWwindow* window) : context_(context), window_(window) {
    const VkResult r = glfwCreateWindowSurface(context.instance(), window, nullptr, &surface_);
    if (r != VK_SUCCESS)
        throw EnvironmentError(fmt::format("cannot create a Vulkan surface for the window ({})", vk::resultName(r)));
    VkBool32 supported = VK_FALSE;
    vkGetPhysicalDeviceSurfaceSupportKHR(context.physicalDevice(), context.queueFamily(), surface_, &supported);
    if (!supported) {
        vkDestroySurfaceKHR(context.instance(), surface_, nullptr);
        throw EnvironmentError(fmt::format("Vulkan device '{}' cannot present to this window", context.deviceName()));
    }
    VkDevice device = context.device();
    VkSemaphoreCreateInfo si{VK_STRUCTURE_TYPE_SEMAPHORE_CREATE_INFO};
    VK_CHECK(vkCreateSemaphore(device, &si, nullptr, &acquired_));
    VkFenceCreateInfo fi{VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
    fi.flags = VK_FENCE_CREATE_SIGNALED_BIT;
    VK_CHECK(vkCreateFence(device, &fi, nullptr, &done_));
    VkCommandBufferAllocateInfo ai{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
    ai.commandPool = context.commandPool();
    ai.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
    ai.commandBufferCount = 1;
    VK_CHECK(vkAllocateCommandBuffers(device, &ai, &cmd_));
    createSwapchain();
}

Presenter::~Presenter() {
    VkDevice device = context_.device();
    vkDeviceWaitIdle(device);
    destroySwapchain();
    upload_.reset();
    readback_.reset();
    if (cmd_) vkFreeCommandBuffers(device, context_.commandPool(), 1, &cmd_);
    if (done_) vkDestroyFence(device, done_, nullptr);
    if (acquired_) vkDestroySemaphore(device, acquired_, nullptr);
    if (surface_) vkDestroySurfaceKHR(context_.instance(), surface_, nullptr);
}

void Presenter::destroySwapchain() {
    VkDevice device = context_.device();
    for (VkSemaphore s : presentReady_) vkDestroySemaphore(device, s, nullptr);
    presentReady_.clear();
    images_.clear();
    if (swapchain_) vkDestroySwapchainKHR(device, swapchain_, nullptr);
    swapchain_ = VK_NULL_HANDLE;
}

void Presenter::createSwapchain() {
    VkPhysicalDevice physical = context_.physicalDevice();
    VkDevice device = context_.device();
    vkDeviceWaitIdle(device);
    destroySwapchain();

    VkSurfaceCapabilitiesKHR caps;
    VK_CHECK(vkGetPhysicalDeviceSurfaceCapabilitiesKHR(physical, surface_, &caps));
    int fbW = 0, fbH = 0;
    glfwGetFramebufferSize(window_, &fbW, &fbH);
    extent_ = caps.currentExtent;
    if (extent_.width == 0xFFFFFFFFu) {
        extent_.width = std::clamp(static_cast<std::uint32_t>(fbW), caps.minImageExtent.width, caps.maxImageExtent.width);
        extent_.height = std::clamp(static_cast<std::uint32_t>(fbH), caps.minImageExtent.height, caps.maxImageExtent.height);
    }
    if (extent_.width == 0 || extent_.height == 0) return;  // minimised: try again next frame

    std::uint32_t count = 0;
    vkGetPhysicalDeviceSurfaceFormatsKHR(physical, surface_, &count, nullptr);
    std::vector<VkSurfaceFormatKHR> formats(count);
    vkGetPhysicalDeviceSurfaceFormatsKHR(physical, surface_, &count, formats.data());
    // UNORM on purpose: the composed bytes are already sRGB-encoded, as in the PNGs.
    const auto has = [&](VkFormat f) {
        return std::any_of(formats.begin(), formats.end(), [f](const VkSurfaceFormatKHR& s) { return s.format == f; });
    };
    if (has(VK_FORMAT_B8G8R8A8_UNORM)) format_ = VK_FORMAT_B8G8R8A8_UNORM, bgr_ = true;
    else if (has(VK_FORMAT_R8G8B8A8_UNORM)) format_ = VK_FORMAT_R8G8B8A8_UNORM, bgr_ = false;
    else throw EnvironmentError("the window offers no 8-bit UNORM swapchain format");
    const VkImageUsageFlags usage = VK_IMAGE_USAGE_TRANSFER_DST_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT;
    if ((caps.supportedUsageFlags & usage) != usage)
        throw EnvironmentError("the window's swapchain images cannot be copied to and from (transfer usage)");

    VkSwapchainCreateInfoKHR info{VK_STRUCTURE_TYPE_SWAPCHAIN_CREATE_INFO_KHR};
    info.surface = surface_;
    info.minImageCount = caps.maxImageCount > 0 ? std::min(caps.minImageCount + 1, caps.maxImageCount)
                                                : caps.minImageCount + 1;
    info.imageFormat = format_;
    info.imageColorSpace = VK_COLOR_SPACE_SRGB_NONLINEAR_KHR;
    info.imageExtent = extent_;
    info.imageArrayLayers = 1;
    info.imageUsage = usage;
    info.imageSharingMode = VK_SHARING_MODE_EXCLUSIVE;
    info.preTransform = caps.currentTransform;
    info.compositeAlpha = VK_COMPOSITE_ALPHA_OPAQUE_BIT_KHR;
    for (VkCompositeAlphaFlagBitsKHR a : {VK_COMPOSITE_ALPHA_OPAQUE_BIT_KHR, VK_COMPOSITE_ALPHA_INHERIT_BIT_KHR,
                                          VK_COMPOSITE_ALPHA_PRE_MULTIPLIED_BIT_KHR,
                                          VK_COMPOSITE_ALPHA_POST_MULTIPLIED_BIT_KHR})
        if (caps.supportedCompositeAlpha & a) {
            info.compositeAlpha = a;
            break;
        }
    info.presentMode = VK_PRESENT_MODE_FIFO_KHR;  // always supported
    info.clipped = VK_TRUE;
    VK_CHECK(vkCreateSwapchainKHR(device, &info, nullptr, &swapchain_));
    vkGetSwapchainImagesKHR(device, swapchain_, &count, nullptr);
    images_.resize(count);
    vkGetSwapchainImagesKHR(device, swapchain_, &count, images_.data());
    VkSemaphoreCreateInfo si{VK_STRUCTURE_TYPE_SEMAPHORE_CREATE_INFO};
    presentReady_.resize(count);
    for (VkSemaphore& s : presentReady_) VK_CHECK(vkCreateSemaphore(device, &si, nullptr, &s));

    const VkDeviceSize bytes = VkDeviceSize{extent_.width} * extent_.height * 4;
    upload_ = vk::Buffer(context_, bytes, VK_BUFFER_USAGE_TRANSFER_SRC_BIT, true);
    readback_ = vk::Buffer(context_, bytes, VK_BUFFER_USAGE_TRANSFER_DST_BIT, true);
}

Presenter::Layout Presenter::layoutFor(int w, int h) const {
    Layout l;
    if (w <= 0 || h <= 0) return l;
    l.scale = std::min(static_cast<float>(extent_.width) / static_cast<float>(w),
                       static_cast<float>(extent_.height) / static_cast<float>(h));
    l.offsetX = (static_cast<int>(extent_.width) - static_cast<int>(std::floor(static_cast<float>(w) * l.scale))) / 2;
    l.offsetY = (static_cast<int>(extent_.height) - static_cast<int>(std::floor(static_cast<float>(h) * l.scale))) / 2;
    return l;
}

std::optional<ImageRGB8> Presenter::present(const ImageRGB8& content, bool readBack) {
    int fbW = 0, fbH = 0;
    glfwGetFramebufferSize(window_, &fbW, &fbH);
    if (fbW == 0 || fbH == 0) return std::nullopt;
    if (!swapchain_ || static_cast<std::uint32_t>(fbW) != extent_.width || static_cast<std::uint32_t>(fbH) != extent_.height)
        createSwapchain();
    if (!swapchain_) return std::nullopt;

    VkDevice device = context_.device();
    VK_CHECK(vkWaitForFences(device, 1, &done_, VK_TRUE, UINT64_MAX));
    std::uint32_t index = 0;
    VkResult r = vkAcquireNextImageKHR(device, swapchain_, UINT64_MAX, acquired_, VK_NULL_HANDLE, &index);
    if (r == VK_ERROR_OUT_OF_DATE_KHR) {
        createSwapchain();
        return std::nullopt;
    }
    if (r != VK_SUCCESS && r != VK_SUBOPTIMAL_KHR) VK_CHECK(r);
    VK_CHECK(vkResetFences(device, 1, &done_));

    // Compose on the CPU: nearest neighbour, centred, black around.
    const Layout l = layoutFor(content.width(), content.height());
    auto* px = static_cast<std::uint8_t*>(upload_.mapped());
    const int W = static_cast<int>(extent_.width), H = static_cast<int>(extent_.height);
    std::memset(px, 0, static_cast<std::size_t>(W) * H * 4);
    if (!content.empty()) {
        for (int Y = 0; Y < H; ++Y) {
            const int y = contentIndex(Y, l.offsetY, l.scale);
            if (Y < l.offsetY || y >= content.height()) continue;
            for (int X = 0; X < W; ++X) {
                const int x = contentIndex(X, l.offsetX, l.scale);
                if (X < l.offsetX || x >= content.width()) continue;
                const glm::u8vec3 c = content.at(x, y);
                std::uint8_t* out = px + (static_cast<std::size_t>(Y) * W + X) * 4;
                out[0] = bgr_ ? c.b : c.r;
                out[1] = c.g;
                out[2] = bgr_ ? c.r : c.b;
                out[3] = 255;
            }
        }
    }

    VkCommandBufferBeginInfo begin{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
    begin.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
    VK_CHECK(vkResetCommandBuffer(cmd_, 0));
    VK_CHECK(vkBeginCommandBuffer(cmd_, &begin));
    VkImage image = images_[index];
    transition(cmd_, image,
               {VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, VK_PIPELINE_STAGE_2_COPY_BIT,
                VK_ACCESS_2_NONE, VK_PIPELINE_STAGE_2_COPY_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT});
    const VkBufferImageCopy region = wholeImage(extent_);
    vkCmdCopyBufferToImage(cmd_, upload_.handle(), image, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1, &region);
    VkImageLayout layout = VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL;
    if (readBack) {
        transition(cmd_, image,
                   {layout, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, VK_PIPELINE_STAGE_2_COPY_BIT,
                    VK_ACCESS_2_TRANSFER_WRITE_BIT, VK_PIPELINE_STAGE_2_COPY_BIT, VK_ACCESS_2_TRANSFER_READ_BIT});
        layout = VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL;
        vkCmdCopyImageToBuffer(cmd_, image, layout, readback_.handle(), 1, &region);
        vk::recordMemoryBarrier(cmd_, VK_PIPELINE_STAGE_2_COPY_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT,
                                VK_PIPELINE_STAGE_2_HOST_BIT, VK_ACCESS_2_HOST_READ_BIT);
    }
    // Presentation needs no access mask; the semaphore signal orders it after the copies.
    transition(cmd_, image,
               {layout, VK_IMAGE_LAYOUT_PRESENT_SRC_KHR, VK_PIPELINE_STAGE_2_COPY_BIT,
                readBack ? VK_ACCESS_2_NONE : VK_ACCESS_2_TRANSFER_WRITE_BIT, VK_PIPELINE_STAGE_2_NONE, VK_ACCESS_2_NONE});
    VK_CHECK(vkEndCommandBuffer(cmd_));

    VkSemaphoreSubmitInfo wait{VK_STRUCTURE_TYPE_SEMAPHORE_SUBMIT_INFO};
    wait.semaphore = acquired_;
    wait.stageMask = VK_PIPELINE_STAGE_2_COPY_BIT;
    VkSemaphoreSubmitInfo signal{VK_STRUCTURE_TYPE_SEMAPHORE_SUBMIT_INFO};
    signal.semaphore = presentReady_[index];
    signal.stageMask = VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT;
    VkCommandBufferSubmitInfo cb{VK_STRUCTURE_TYPE_COMMAND_BUFFER_SUBMIT_INFO};
    cb.commandBuffer = cmd_;
    VkSubmitInfo2 submit{VK_STRUCTURE_TYPE_SUBMIT_INFO_2};
    submit.waitSemaphoreInfoCount = 1;
    submit.pWaitSemaphoreInfos = &wait;
    submit.commandBufferInfoCount = 1;
    submit.pCommandBufferInfos = &cb;
    submit.signalSemaphoreInfoCount = 1;
    submit.pSignalSemaphoreInfos = &signal;
    VK_CHECK(vkQueueSubmit2(context_.queue(), 1, &submit, done_));

    VkPresentInfoKHR present{VK_STRUCTURE_TYPE_PRESENT_INFO_KHR};
    present.waitSemaphoreCount = 1;
    present.pWaitSemaphores = &presentReady_[index];
    present.swapchainCount = 1;
    present.pSwapchains = &swapchain_;
    present.pImageIndices = &index;
    r = vkQueuePresentKHR(context_.queue(), &present);
    if (r == VK_ERROR_OUT_OF_DATE_KHR || r == VK_SUBOPTIMAL_KHR) extent_ = {0, 0};  // recreate next frame
    else VK_CHECK(r);

    if (!readBack || content.empty()) return std::nullopt;
    VK_CHECK(vkWaitForFences(device, 1, &done_, VK_TRUE, UINT64_MAX));
    if (l.scale < 1.0f)
        throw EnvironmentError(fmt::format("the window ({}x{}) is smaller than the {}x{} image: no screenshot", W, H,
                                           content.width(), content.height()));
    const auto* in = static_cast<const std::uint8_t*>(readback_.mapped());
    ImageRGB8 shot(content.width(), content.height());
    for (int y = 0; y < content.height(); ++y)
        for (int x = 0; x < content.width(); ++x) {
            const int X = firstWindowPixel(x, l.offsetX, l.scale), Y = firstWindowPixel(y, l.offsetY, l.scale);
            const std::uint8_t* p = in + (static_cast<std::size_t>(Y) * W + X) * 4;
            shot.at(x, y) = bgr_ ? glm::u8vec3(p[2], p[1], p[0]) : glm::u8vec3(p[0], p[1], p[2]);
        }
    return shot;
}

}  // namespace aamap
