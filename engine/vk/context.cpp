// VulkanContext: instance (+ optional validation and debug messenger), device choice, one queue.
#include "engine/vk/context.h"

#include <algorithm>
#include <atomic>
#include <cctype>
#include <cstdlib>
#include <cstring>

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "core/error.h"
#include "engine/vk/check.h"

namespace aamap {
namespace {

constexpr const char* kValidationLayer = "VK_LAYER_KHRONOS_validation";
std::atomic<std::uint64_t> gProcessMessages{0};

std::string lower(std::string s) {
    std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return std::tolower(c); });
    return s;
}

// AAMAP_VALIDATION=1 (as for the app's --validation) turns the layer on; the gpu tests set it.
bool validationWanted(bool requested) {
    const char* env = std::getenv("AAMAP_VALIDATION");
    if (requested || !env || !*env) return requested;
    const std::string v = lower(env);
    return v == "1" || v == "true" || v == "on" || v == "yes";
}

bool layerAvailable(const char* name) {
    std::uint32_t count = 0;
    vkEnumerateInstanceLayerProperties(&count, nullptr);
    std::vector<VkLayerProperties> layers(count);
    vkEnumerateInstanceLayerProperties(&count, layers.data());
    return std::any_of(layers.begin(), layers.end(),
                       [&](const VkLayerProperties& l) { return std::strcmp(l.layerName, name) == 0; });
}

VKAPI_ATTR VkBool32 VKAPI_CALL debugCallback(VkDebugUtilsMessageSeverityFlagBitsEXT severity,
                                             VkDebugUtilsMessageTypeFlagsEXT /*types*/,
                                             const VkDebugUtilsMessengerCallbackDataEXT* data, void* user) {
    auto* counter = static_cast<std::atomic<std::uint64_t>*>(user);
    const char* msg = data && data->pMessage ? data->pMessage : "(no message)";
    if (severity & VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT) {
        counter->fetch_add(1);
        gProcessMessages.fetch_add(1);
        spdlog::error("[vulkan] {}", msg);
    } else if (severity & VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT) {
        counter->fetch_add(1);
        gProcessMessages.fetch_add(1);
        spdlog::warn("[vulkan] {}", msg);
    }
    return VK_FALSE;
}

VkDebugUtilsMessengerCreateInfoEXT messengerInfo(std::atomic<std::uint64_t>* counter) {
    VkDebugUtilsMessengerCreateInfoEXT info{VK_STRUCTURE_TYPE_DEBUG_UTILS_MESSENGER_CREATE_INFO_EXT};
    info.messageSeverity =
        VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT | VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT;
    info.messageType = VK_DEBUG_UTILS_MESSAGE_TYPE_GENERAL_BIT_EXT | VK_DEBUG_UTILS_MESSAGE_TYPE_VALIDATION_BIT_EXT |
                       VK_DEBUG_UTILS_MESSAGE_TYPE_PERFORMANCE_BIT_EXT;
    info.pfnUserCallback = debugCallback;
    info.pUserData = counter;
    return info;
}

VkInstance createInstance(bool validation, const std::vector<std::string>& extraExtensions,
                          std::atomic<std::uint64_t>* counter) {
    std::uint32_t version = 0;
    if (vkEnumerateInstanceVersion(&version) != VK_SUCCESS || version < VK_API_VERSION_1_3)
        throw EnvironmentError(fmt::format("the Vulkan loader offers version {}.{}, aamap needs 1.3",
                                           VK_API_VERSION_MAJOR(version), VK_API_VERSION_MINOR(version)));
    VkApplicationInfo app{VK_STRUCTURE_TYPE_APPLICATION_INFO};
    app.pApplicationName = "aamap";
    app.pEngineName = "aamap";
    app.apiVersion = VK_API_VERSION_1_3;

    std::vector<const char*> layers, extensions;
    // Synchronisation validation checks the executor's derived barriers, the part most likely wrong.
    const VkValidationFeatureEnableEXT enables[] = {VK_VALIDATION_FEATURE_ENABLE_SYNCHRONIZATION_VALIDATION_EXT};
    VkValidationFeaturesEXT features{VK_STRUCTURE_TYPE_VALIDATION_FEATURES_EXT};
    features.enabledValidationFeatureCount = 1;
    features.pEnabledValidationFeatures = enables;
    VkDebugUtilsMessengerCreateInfoEXT debugInfo = messengerInfo(counter);

    VkInstanceCreateInfo info{VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO};
    info.pApplicationInfo = &app;
    for (const std::string& e : extraExtensions) extensions.push_back(e.c_str());
    if (validation) {
        if (!layerAvailable(kValidationLayer))
            throw EnvironmentError(
                "Vulkan validation was requested but VK_LAYER_KHRONOS_validation is not installed "
                "(Debian: apt-get install vulkan-validationlayers)");
        layers.push_back(kValidationLayer);
        extensions.push_back(VK_EXT_DEBUG_UTILS_EXTENSION_NAME);
        debugInfo.pNext = &features;
        info.pNext = &debugInfo;  // also reports problems in vkCreateInstance itself
    }
    info.enabledLayerCount = static_cast<std::uint32_t>(layers.size());
    info.ppEnabledLayerNames = layers.data();
    info.enabledExtensionCount = static_cast<std::uint32_t>(extensions.size());
    info.ppEnabledExtensionNames = extensions.data();

    VkInstance instance = VK_NULL_HANDLE;
    const VkResult r = vkCreateInstance(&info, nullptr, &instance);
    if (r != VK_SUCCESS)
        throw EnvironmentError(fmt::format("vkCreateInstance failed ({}): is a Vulkan driver installed? "
                                           "(Debian: mesa-vulkan-drivers for lavapipe)",
                                           vk::resultName(r)));
    return instance;
}

struct Candidate {
    VkPhysicalDevice device = VK_NULL_HANDLE;
    VkPhysicalDeviceProperties props{};
    std::uint32_t queueFamily = 0;
    std::string problem;  // empty: usable
};

Candidate inspect(VkInstance instance, VkPhysicalDevice device, const ContextOptions& options) {
    Candidate c{device};
    vkGetPhysicalDeviceProperties(device, &c.props);
    if (c.props.apiVersion < VK_API_VERSION_1_3) {
        c.problem = fmt::format("offers Vulkan {}.{}, aamap needs 1.3", VK_API_VERSION_MAJOR(c.props.apiVersion),
                                VK_API_VERSION_MINOR(c.props.apiVersion));
        return c;
    }
    VkPhysicalDeviceVulkan13Features f13{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_3_FEATURES};
    VkPhysicalDeviceFeatures2 f2{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2, &f13};
    vkGetPhysicalDeviceFeatures2(device, &f2);
    if (!f13.dynamicRendering || !f13.synchronization2 || !f13.maintenance4) {
        c.problem = "lacks dynamicRendering, synchronization2 or maintenance4";
        return c;
    }
    std::uint32_t count = 0;
    vkEnumerateDeviceExtensionProperties(device, nullptr, &count, nullptr);
    std::vector<VkExtensionProperties> exts(count);
    vkEnumerateDeviceExtensionProperties(device, nullptr, &count, exts.data());
    if (std::none_of(exts.begin(), exts.end(), [](const VkExtensionProperties& e) {
            return std::strcmp(e.extensionName, VK_KHR_PUSH_DESCRIPTOR_EXTENSION_NAME) == 0;
        })) {
        c.problem = "lacks VK_KHR_push_descriptor";
        return c;
    }
    if (options.swapchain && std::none_of(exts.begin(), exts.end(), [](const VkExtensionProperties& e) {
            return std::strcmp(e.extensionName, VK_KHR_SWAPCHAIN_EXTENSION_NAME) == 0;
        })) {
        c.problem = "lacks VK_KHR_swapchain";
        return c;
    }
    vkGetPhysicalDeviceQueueFamilyProperties(device, &count, nullptr);
    std::vector<VkQueueFamilyProperties> families(count);
    vkGetPhysicalDeviceQueueFamilyProperties(device, &count, families.data());
    const VkQueueFlags need = VK_QUEUE_GRAPHICS_BIT | VK_QUEUE_COMPUTE_BIT;
    for (std::uint32_t i = 0; i < count; ++i) {
        if ((families[i].queueFlags & need) == need && families[i].timestampValidBits > 0 &&
            (!options.canPresent || options.canPresent(instance, device, i))) {
            c.queueFamily = i;
            return c;
        }
    }
    c.problem = options.canPresent ? "has no graphics+compute queue with timestamps that can present to the window"
                                   : "has no graphics+compute queue with timestamps";
    return c;
}

int typeRank(VkPhysicalDeviceType type) {
    switch (type) {
        case VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU: return 0;
        case VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU: return 1;
        case VK_PHYSICAL_DEVICE_TYPE_VIRTUAL_GPU: return 2;
        case VK_PHYSICAL_DEVICE_TYPE_CPU: return 3;
        default: return 4;
    }
}

std::vector<VkPhysicalDevice> enumerate(VkInstance instance) {
    std::uint32_t count = 0;
    vkEnumeratePhysicalDevices(instance, &count, nullptr);
    std::vector<VkPhysicalDevice> devices(count);
    vkEnumeratePhysicalDevices(instance, &count, devices.data());
    return devices;
}

Candidate choose(VkInstance instance, const ContextOptions& options) {
    const std::string& wanted = options.device;
    std::vector<Candidate> all;
    for (VkPhysicalDevice d : enumerate(instance)) all.push_back(inspect(instance, d, options));
    if (all.empty()) throw EnvironmentError("no Vulkan device found (Debian: mesa-vulkan-drivers provides lavapipe)");
    std::string listing;
    for (std::size_t i = 0; i < all.size(); ++i)
        listing += fmt::format("\n  [{}] {}{}", i, all[i].props.deviceName,
                               all[i].problem.empty() ? "" : " (unusable: " + all[i].problem + ")");
    auto usable = [&](const Candidate& c) {
        if (!c.problem.empty())
            throw RequestedDeviceError(
                fmt::format("Vulkan device '{}' {}; devices:{}", c.props.deviceName, c.problem, listing));
        return c;
    };
    if (!wanted.empty()) {
        const bool numeric =
            std::all_of(wanted.begin(), wanted.end(), [](unsigned char ch) { return std::isdigit(ch) != 0; });
        if (numeric) {
            const std::size_t index = std::stoul(wanted);
            if (index >= all.size())
                throw RequestedDeviceError(fmt::format("no Vulkan device with index {}; devices:{}", wanted, listing));
            return usable(all[index]);
        }
        for (const Candidate& c : all)
            if (lower(c.props.deviceName).find(lower(wanted)) != std::string::npos) return usable(c);
        throw RequestedDeviceError(fmt::format("no Vulkan device matches '{}'; devices:{}", wanted, listing));
    }
    const Candidate* best = nullptr;
    for (const Candidate& c : all)
        if (c.problem.empty() && (!best || typeRank(c.props.deviceType) < typeRank(best->props.deviceType))) best = &c;
    if (!best) throw EnvironmentError(fmt::format("no usable Vulkan 1.3 device; devices:{}", listing));
    return *best;
}

}  // namespace

struct VulkanContext::Impl {
    std::atomic<std::uint64_t> messages{0};
    bool validation = false;
    VkInstance instance = VK_NULL_HANDLE;
    VkDebugUtilsMessengerEXT messenger = VK_NULL_HANDLE;
    VkPhysicalDevice physical = VK_NULL_HANDLE;
    VkPhysicalDeviceProperties props{};
    VkPhysicalDeviceMemoryProperties memory{};
    VkDevice device = VK_NULL_HANDLE;
    VkQueue queue = VK_NULL_HANDLE;
    std::uint32_t family = 0;
    std::uint32_t timestampBits = 0;
    VkCommandPool pool = VK_NULL_HANDLE;
    PFN_vkCmdPushDescriptorSetKHR pushDescriptorSet = nullptr;
    std::string name;

    void destroy() {
        if (device) {
            vkDeviceWaitIdle(device);
            if (pool) vkDestroyCommandPool(device, pool, nullptr);
            vkDestroyDevice(device, nullptr);
        }
        if (messenger) {
            auto fn = reinterpret_cast<PFN_vkDestroyDebugUtilsMessengerEXT>(
                vkGetInstanceProcAddr(instance, "vkDestroyDebugUtilsMessengerEXT"));
            if (fn) fn(instance, messenger, nullptr);
        }
        if (instance) vkDestroyInstance(instance, nullptr);
    }
};

VulkanContext::VulkanContext(const ContextOptions& options) : impl_(std::make_unique<Impl>()) {
    Impl& s = *impl_;
    s.validation = validationWanted(options.validation);
    try {
        s.instance = createInstance(s.validation, options.instanceExtensions, &s.messages);
        if (s.validation) {
            auto fn = reinterpret_cast<PFN_vkCreateDebugUtilsMessengerEXT>(
                vkGetInstanceProcAddr(s.instance, "vkCreateDebugUtilsMessengerEXT"));
            const VkDebugUtilsMessengerCreateInfoEXT info = messengerInfo(&s.messages);
            if (!fn || fn(s.instance, &info, nullptr, &s.messenger) != VK_SUCCESS)
                throw EnvironmentError("cannot create the Vulkan debug messenger");
        }
        const Candidate chosen = choose(s.instance, options);
        s.physical = chosen.device;
        s.props = chosen.props;
        s.family = chosen.queueFamily;
        s.name = chosen.props.deviceName;
        vkGetPhysicalDeviceMemoryProperties(s.physical, &s.memory);

        std::uint32_t count = 0;
        vkGetPhysicalDeviceQueueFamilyProperties(s.physical, &count, nullptr);
        std::vector<VkQueueFamilyProperties> families(count);
        vkGetPhysicalDeviceQueueFamilyProperties(s.physical, &count, families.data());
        s.timestampBits = families[s.family].timestampValidBits;

        const float priority = 1.0f;
        VkDeviceQueueCreateInfo queueInfo{VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO};
        queueInfo.queueFamilyIndex = s.family;
        queueInfo.queueCount = 1;
        queueInfo.pQueuePriorities = &priority;
        VkPhysicalDeviceVulkan13Features f13{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_3_FEATURES};
        f13.dynamicRendering = VK_TRUE;
        f13.synchronization2 = VK_TRUE;
        f13.maintenance4 = VK_TRUE;  // glslc's SPIR-V 1.6 declares workgroup sizes with LocalSizeId
        // gl_Layer from the vertex shader: all shadow cube faces in one draw. Optional; the shadow
        // pass checks for it and says so when a device lacks it.
        VkPhysicalDeviceVulkan12Features f12{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_2_FEATURES};
        VkPhysicalDeviceFeatures2 supported{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2, &f12};
        vkGetPhysicalDeviceFeatures2(s.physical, &supported);
        const VkBool32 outputLayer = f12.shaderOutputLayer;
        f12 = {VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_2_FEATURES};
        f12.shaderOutputLayer = outputLayer;
        f13.pNext = &f12;
        VkPhysicalDeviceFeatures2 features{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2, &f13};
        const char* extensions[] = {VK_KHR_PUSH_DESCRIPTOR_EXTENSION_NAME, VK_KHR_SWAPCHAIN_EXTENSION_NAME};
        VkDeviceCreateInfo info{VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO, &features};
        info.queueCreateInfoCount = 1;
        info.pQueueCreateInfos = &queueInfo;
        info.enabledExtensionCount = options.swapchain ? 2 : 1;  // the swapchain only when asked for
        info.ppEnabledExtensionNames = extensions;
        const VkResult r = vkCreateDevice(s.physical, &info, nullptr, &s.device);
        if (r != VK_SUCCESS)
            throw EnvironmentError(fmt::format("vkCreateDevice on '{}' failed ({})", s.name, vk::resultName(r)));
        vkGetDeviceQueue(s.device, s.family, 0, &s.queue);
        s.pushDescriptorSet = reinterpret_cast<PFN_vkCmdPushDescriptorSetKHR>(
            vkGetDeviceProcAddr(s.device, "vkCmdPushDescriptorSetKHR"));
        if (!s.pushDescriptorSet) throw EnvironmentError("vkCmdPushDescriptorSetKHR is missing");

        VkCommandPoolCreateInfo poolInfo{VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO};
        poolInfo.flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT | VK_COMMAND_POOL_CREATE_TRANSIENT_BIT;
        poolInfo.queueFamilyIndex = s.family;
        VK_CHECK(vkCreateCommandPool(s.device, &poolInfo, nullptr, &s.pool));
    } catch (...) {
        s.destroy();
        throw;
    }
    spdlog::info("Vulkan device: {} (validation {})", s.name, s.validation ? "on" : "off");
}

VulkanContext::~VulkanContext() {
    if (impl_) impl_->destroy();
}

std::vector<std::string> VulkanContext::listDevices() {
    VkApplicationInfo app{VK_STRUCTURE_TYPE_APPLICATION_INFO};
    app.apiVersion = VK_API_VERSION_1_3;
    VkInstanceCreateInfo info{VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO};
    info.pApplicationInfo = &app;
    VkInstance instance = VK_NULL_HANDLE;
    if (vkCreateInstance(&info, nullptr, &instance) != VK_SUCCESS) return {};
    std::vector<std::string> names;
    for (VkPhysicalDevice d : enumerate(instance)) {
        VkPhysicalDeviceProperties props;
        vkGetPhysicalDeviceProperties(d, &props);
        names.emplace_back(props.deviceName);
    }
    vkDestroyInstance(instance, nullptr);
    return names;
}

const std::string& VulkanContext::deviceName() const { return impl_->name; }
bool VulkanContext::validationEnabled() const { return impl_->validation; }
std::uint64_t VulkanContext::validationMessageCount() const { return impl_->messages.load(); }
std::uint64_t VulkanContext::processValidationMessageCount() { return gProcessMessages.load(); }
VkInstance VulkanContext::instance() const { return impl_->instance; }
VkPhysicalDevice VulkanContext::physicalDevice() const { return impl_->physical; }
VkDevice VulkanContext::device() const { return impl_->device; }
VkQueue VulkanContext::queue() const { return impl_->queue; }
std::uint32_t VulkanContext::queueFamily() const { return impl_->family; }
double VulkanContext::timestampPeriodNs() const { return impl_->props.limits.timestampPeriod; }
std::uint32_t VulkanContext::maxImageDimension2D() const { return impl_->props.limits.maxImageDimension2D; }
std::uint32_t VulkanContext::timestampValidBits() const { return impl_->timestampBits; }
const VkPhysicalDeviceMemoryProperties& VulkanContext::memoryProperties() const { return impl_->memory; }
VkCommandPool VulkanContext::commandPool() const { return impl_->pool; }
PFN_vkCmdPushDescriptorSetKHR VulkanContext::cmdPushDescriptorSet() const { return impl_->pushDescriptorSet; }

}  // namespace aamap
