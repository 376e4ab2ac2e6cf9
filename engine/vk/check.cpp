#include "engine/vk/check.h"

#include <fmt/format.h>

namespace aamap::vk {

const char* resultName(VkResult result) {
    switch (result) {
#define AAMAP_CASE(x) \
    case x: return #x;
        AAMAP_CASE(VK_SUCCESS)
        AAMAP_CASE(VK_NOT_READY)
        AAMAP_CASE(VK_TIMEOUT)
        AAMAP_CASE(VK_INCOMPLETE)
        AAMAP_CASE(VK_ERROR_OUT_OF_HOST_MEMORY)
        AAMAP_CASE(VK_ERROR_OUT_OF_DEVICE_MEMORY)
        AAMAP_CASE(VK_ERROR_INITIALIZATION_FAILED)
        AAMAP_CASE(VK_ERROR_DEVICE_LOST)
        AAMAP_CASE(VK_ERROR_MEMORY_MAP_FAILED)
        AAMAP_CASE(VK_ERROR_LAYER_NOT_PRESENT)
        AAMAP_CASE(VK_ERROR_EXTENSION_NOT_PRESENT)
        AAMAP_CASE(VK_ERROR_FEATURE_NOT_PRESENT)
        AAMAP_CASE(VK_ERROR_INCOMPATIBLE_DRIVER)
        AAMAP_CASE(VK_ERROR_TOO_MANY_OBJECTS)
        AAMAP_CASE(VK_ERROR_FORMAT_NOT_SUPPORTED)
        AAMAP_CASE(VK_ERROR_UNKNOWN)
#undef AAMAP_CASE
        default: return "VkResult(?)";
    }
}

VulkanError::VulkanError(const char* call, VkResult result, const char* file, int line)
    : std::runtime_error(fmt::format("{}:{}: {} failed with {} ({})", file, line, call, resultName(result),
                                     static_cast<int>(result))),
      result_(result) {}

}  // namespace aamap::vk
