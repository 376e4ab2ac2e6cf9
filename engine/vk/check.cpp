#include "engine/vk/check.h"

#include <atomic>
#include <cstdlib>
#include <string>

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

VkResult withTestFault(VkResult result) {
    struct Fault {
        VkResult result = VK_SUCCESS;
        long after = 0;
    };
    static const Fault fault = [] {
        Fault f;
        const char* env = std::getenv("AAMAP_TEST_VK_FAULT");
        if (!env || !*env) return f;
        const std::string spec(env);
        const std::string name = spec.substr(0, spec.find('@'));
        for (VkResult r : {VK_ERROR_DEVICE_LOST, VK_ERROR_OUT_OF_DEVICE_MEMORY, VK_ERROR_OUT_OF_HOST_MEMORY,
                           VK_ERROR_INITIALIZATION_FAILED, VK_ERROR_UNKNOWN})
            if (name == resultName(r)) f.result = r;
        if (spec.find('@') != std::string::npos) f.after = std::strtol(spec.c_str() + spec.find('@') + 1, nullptr, 10);
        return f;
    }();
    static std::atomic<long> calls{0};
    if (fault.result == VK_SUCCESS || result != VK_SUCCESS) return result;
    return calls++ >= fault.after ? fault.result : result;
}

}  // namespace aamap::vk
