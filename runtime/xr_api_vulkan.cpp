// XR_KHR_vulkan_enable and XR_KHR_vulkan_enable2: graphics requirements, the physical device, the
// Vulkan extensions a window needs, xrCreateVulkanInstanceKHR / xrCreateVulkanDeviceKHR and the
// validation messenger.
#include <cstdlib>
#include <cstring>

#include "runtime/xr_objects.h"
#include "runtime/xr_verify.h"

namespace wrsfov::xr {

namespace {

VKAPI_ATTR VkBool32 VKAPI_CALL vulkanMessage(VkDebugUtilsMessageSeverityFlagBitsEXT severity,
                                             VkDebugUtilsMessageTypeFlagsEXT, const VkDebugUtilsMessengerCallbackDataEXT* d,
                                             void* user) {
    auto* inst = static_cast<Instance*>(user);
    const bool error = severity & VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT;
    (error ? inst->vkErrors : inst->vkWarnings)++;
    logLine(std::string("[vulkan ") + (error ? "error" : "warning") + "] " + (d && d->pMessage ? d->pMessage : ""));
    return VK_FALSE;
}

XrResult graphicsRequirements(XrInstance h, XrSystemId id, XrGraphicsRequirementsVulkanKHR* req) {
    std::lock_guard lock(stateMutex(h));
    Instance* inst = getInstance(h);
    if (XrResult r = checkSystem(inst, id); r != XR_SUCCESS) return r;
    if (!inst->enabled(XR_KHR_VULKAN_ENABLE_EXTENSION_NAME) && !inst->enabled(XR_KHR_VULKAN_ENABLE2_EXTENSION_NAME))
        return XR_ERROR_FUNCTION_UNSUPPORTED;
    if (!req || req->type != XR_TYPE_GRAPHICS_REQUIREMENTS_VULKAN_KHR) return XR_ERROR_VALIDATION_FAILURE;
    // The passes are SPIR-V 1.0 and need no optional feature: any Vulkan 1.x device will do.
    req->minApiVersionSupported = XR_MAKE_VERSION(1, 0, 0);
    req->maxApiVersionSupported = XR_MAKE_VERSION(1, 3, 0);
    inst->graphicsRequirementsQueried = true;
    return XR_SUCCESS;
}

}  // namespace

XRAPI_ATTR XrResult XRAPI_CALL xrGetVulkanGraphicsRequirementsKHR(XrInstance h, XrSystemId id,
                                                                  XrGraphicsRequirementsVulkanKHR* req) {
    return graphicsRequirements(h, id, req);
}
XRAPI_ATTR XrResult XRAPI_CALL xrGetVulkanGraphicsRequirements2KHR(XrInstance h, XrSystemId id,
                                                                   XrGraphicsRequirementsVulkanKHR* req) {
    return graphicsRequirements(h, id, req);
}

namespace {

/// WRSFOV_DEVICE by name if set, else the most capable type (as vk::Context chooses).
XrResult chooseDevice(Instance* inst, VkInstance vkInstance, PFN_vkGetInstanceProcAddr gipa, VkPhysicalDevice* out) {
    if (!vkInstance || !out) return XR_ERROR_VALIDATION_FAILURE;
    auto enumerate = reinterpret_cast<PFN_vkEnumeratePhysicalDevices>(gipa(vkInstance, "vkEnumeratePhysicalDevices"));
    auto properties =
        reinterpret_cast<PFN_vkGetPhysicalDeviceProperties>(gipa(vkInstance, "vkGetPhysicalDeviceProperties"));
    if (!enumerate || !properties) return XR_ERROR_RUNTIME_FAILURE;
    uint32_t n = 0;
    enumerate(vkInstance, &n, nullptr);
    std::vector<VkPhysicalDevice> devices(n);
    enumerate(vkInstance, &n, devices.data());
    const char* wanted = std::getenv("WRSFOV_DEVICE");
    int best = -1;
    VkPhysicalDevice chosen = VK_NULL_HANDLE;
    for (VkPhysicalDevice d : devices) {
        VkPhysicalDeviceProperties p;
        properties(d, &p);
        if (wanted && *wanted && !std::strstr(p.deviceName, wanted)) continue;
        const int score = vk::deviceTypeScore(p.deviceType);
        if (score > best) best = score, chosen = d;
    }
    if (!chosen) {
        logLine("no Vulkan device" + std::string(wanted && *wanted ? std::string(" named like ") + wanted : ""));
        return XR_ERROR_RUNTIME_FAILURE;
    }
    inst->graphicsDevice = chosen;
    *out = chosen;
    return XR_SUCCESS;
}

}  // namespace

XRAPI_ATTR XrResult XRAPI_CALL xrGetVulkanGraphicsDeviceKHR(XrInstance h, XrSystemId id, VkInstance vkInstance,
                                                            VkPhysicalDevice* device) {
    std::lock_guard lock(stateMutex(h));
    Instance* inst = getInstance(h);
    if (XrResult r = checkSystem(inst, id); r != XR_SUCCESS) return r;
    if (!inst->enabled(XR_KHR_VULKAN_ENABLE_EXTENSION_NAME)) return XR_ERROR_FUNCTION_UNSUPPORTED;
    return chooseDevice(inst, vkInstance, vkGetInstanceProcAddr, device);
}

XRAPI_ATTR XrResult XRAPI_CALL xrGetVulkanGraphicsDevice2KHR(XrInstance h, const XrVulkanGraphicsDeviceGetInfoKHR* info,
                                                             VkPhysicalDevice* device) {
    std::lock_guard lock(stateMutex(h));
    Instance* inst = getInstance(h);
    if (!inst) return XR_ERROR_HANDLE_INVALID;
    if (!inst->enabled(XR_KHR_VULKAN_ENABLE2_EXTENSION_NAME)) return XR_ERROR_FUNCTION_UNSUPPORTED;
    if (!info || info->type != XR_TYPE_VULKAN_GRAPHICS_DEVICE_GET_INFO_KHR) return XR_ERROR_VALIDATION_FAILURE;
    if (XrResult r = checkSystem(inst, info->systemId); r != XR_SUCCESS) return r;
    if (inst->vkInstance != VK_NULL_HANDLE && info->vulkanInstance != inst->vkInstance)
        return XR_ERROR_VALIDATION_FAILURE;  // not the instance xrCreateVulkanInstanceKHR made
    return chooseDevice(inst, info->vulkanInstance, vkGetInstanceProcAddr, device);
}

namespace {

/// The space-separated extension list of xrGetVulkan{Instance,Device}ExtensionsKHR: the passes need
/// none; a window needs the surface extensions and VK_KHR_swapchain.
XrResult extensionList(XrInstance h, XrSystemId id, uint32_t capacity, uint32_t* countOutput, char* buffer,
                       bool device) {
    std::lock_guard lock(stateMutex(h));
    Instance* inst = getInstance(h);
    if (XrResult r = checkSystem(inst, id); r != XR_SUCCESS) return r;
    if (!inst->enabled(XR_KHR_VULKAN_ENABLE_EXTENSION_NAME)) return XR_ERROR_FUNCTION_UNSUPPORTED;
    std::string list;
    if (inst->window) {
        const std::vector<std::string> exts =
            device ? std::vector<std::string>{VK_KHR_SWAPCHAIN_EXTENSION_NAME} : inst->windowExtensions;
        for (const std::string& e : exts) list += (list.empty() ? "" : " ") + e;
    }
    return fillString(capacity, countOutput, buffer, list);
}

}  // namespace

XRAPI_ATTR XrResult XRAPI_CALL xrGetVulkanInstanceExtensionsKHR(XrInstance h, XrSystemId id, uint32_t capacity,
                                                                uint32_t* countOutput, char* buffer) {
    return extensionList(h, id, capacity, countOutput, buffer, false);
}
XRAPI_ATTR XrResult XRAPI_CALL xrGetVulkanDeviceExtensionsKHR(XrInstance h, XrSystemId id, uint32_t capacity,
                                                              uint32_t* countOutput, char* buffer) {
    return extensionList(h, id, capacity, countOutput, buffer, true);
}

XRAPI_ATTR XrResult XRAPI_CALL xrCreateVulkanInstanceKHR(XrInstance h, const XrVulkanInstanceCreateInfoKHR* info,
                                                         VkInstance* vkInstance, VkResult* vkResult) {
    std::lock_guard lock(stateMutex(h));
    Instance* inst = getInstance(h);
    if (!inst) return XR_ERROR_HANDLE_INVALID;
    if (!inst->enabled(XR_KHR_VULKAN_ENABLE2_EXTENSION_NAME)) return XR_ERROR_FUNCTION_UNSUPPORTED;
    if (!info || !vkInstance || !vkResult || info->type != XR_TYPE_VULKAN_INSTANCE_CREATE_INFO_KHR ||
        !info->pfnGetInstanceProcAddr || !info->vulkanCreateInfo || info->createFlags != 0)
        return XR_ERROR_VALIDATION_FAILURE;
    if (XrResult r = checkSystem(inst, info->systemId); r != XR_SUCCESS) return r;
    auto create = reinterpret_cast<PFN_vkCreateInstance>(info->pfnGetInstanceProcAddr(nullptr, "vkCreateInstance"));
    if (!create) return XR_ERROR_RUNTIME_FAILURE;
    VkInstanceCreateInfo ci = *info->vulkanCreateInfo;
    std::vector<const char*> layers(ci.ppEnabledLayerNames, ci.ppEnabledLayerNames + ci.enabledLayerCount);
    std::vector<const char*> exts(ci.ppEnabledExtensionNames, ci.ppEnabledExtensionNames + ci.enabledExtensionCount);
    auto has = [](const std::vector<const char*>& v, const char* n) {
        for (const char* s : v)
            if (std::strcmp(s, n) == 0) return true;
        return false;
    };
    for (const std::string& e : inst->windowExtensions)  // empty without a window
        if (!has(exts, e.c_str())) exts.push_back(e.c_str());
    bool count = false;
    if (inst->config.validation) {
        // Count every message of the instance (the application's rendering and our passes alike).
        auto enumLayers = reinterpret_cast<PFN_vkEnumerateInstanceLayerProperties>(
            info->pfnGetInstanceProcAddr(nullptr, "vkEnumerateInstanceLayerProperties"));
        uint32_t n = 0;
        if (enumLayers) enumLayers(&n, nullptr);
        std::vector<VkLayerProperties> available(n);
        if (enumLayers) enumLayers(&n, available.data());
        bool present = false;
        for (auto& l : available) present = present || std::strcmp(l.layerName, "VK_LAYER_KHRONOS_validation") == 0;
        if (!present) {
            logLine("validation = 1 but VK_LAYER_KHRONOS_validation is not installed (vulkan-validationlayers)");
        } else {
            if (!has(layers, "VK_LAYER_KHRONOS_validation")) layers.push_back("VK_LAYER_KHRONOS_validation");
            if (!has(exts, VK_EXT_DEBUG_UTILS_EXTENSION_NAME)) exts.push_back(VK_EXT_DEBUG_UTILS_EXTENSION_NAME);
            count = true;
        }
    }
    ci.enabledLayerCount = uint32_t(layers.size());
    ci.ppEnabledLayerNames = layers.data();
    ci.enabledExtensionCount = uint32_t(exts.size());
    ci.ppEnabledExtensionNames = exts.data();
    *vkResult = create(&ci, info->vulkanAllocator, vkInstance);
    if (*vkResult != VK_SUCCESS) return XR_SUCCESS;  // the Vulkan failure is in vkResult
    inst->vkInstance = *vkInstance;
    if (count) {
        VkDebugUtilsMessengerCreateInfoEXT m{VK_STRUCTURE_TYPE_DEBUG_UTILS_MESSENGER_CREATE_INFO_EXT};
        m.messageSeverity = VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT | VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT;
        m.messageType = VK_DEBUG_UTILS_MESSAGE_TYPE_GENERAL_BIT_EXT | VK_DEBUG_UTILS_MESSAGE_TYPE_VALIDATION_BIT_EXT;
        m.pfnUserCallback = &vulkanMessage;
        m.pUserData = inst;
        auto fn = reinterpret_cast<PFN_vkCreateDebugUtilsMessengerEXT>(
            info->pfnGetInstanceProcAddr(*vkInstance, "vkCreateDebugUtilsMessengerEXT"));
        if (fn) fn(*vkInstance, &m, nullptr, &inst->messenger);
        logLine("Vulkan validation on: counting the instance's messages");
    }
    return XR_SUCCESS;
}

XRAPI_ATTR XrResult XRAPI_CALL xrCreateVulkanDeviceKHR(XrInstance h, const XrVulkanDeviceCreateInfoKHR* info,
                                                       VkDevice* device, VkResult* vkResult) {
    std::lock_guard lock(stateMutex(h));
    Instance* inst = getInstance(h);
    if (!inst) return XR_ERROR_HANDLE_INVALID;
    if (!inst->enabled(XR_KHR_VULKAN_ENABLE2_EXTENSION_NAME)) return XR_ERROR_FUNCTION_UNSUPPORTED;
    if (!info || !device || !vkResult || info->type != XR_TYPE_VULKAN_DEVICE_CREATE_INFO_KHR ||
        !info->pfnGetInstanceProcAddr || !info->vulkanCreateInfo || info->createFlags != 0)
        return XR_ERROR_VALIDATION_FAILURE;
    if (XrResult r = checkSystem(inst, info->systemId); r != XR_SUCCESS) return r;
    if (!inst->graphicsDevice || info->vulkanPhysicalDevice != inst->graphicsDevice)
        return XR_ERROR_VALIDATION_FAILURE;  // must be what xrGetVulkanGraphicsDevice2KHR returned
    auto create =
        reinterpret_cast<PFN_vkCreateDevice>(info->pfnGetInstanceProcAddr(inst->vkInstance, "vkCreateDevice"));
    if (!create) return XR_ERROR_RUNTIME_FAILURE;
    // The passes need nothing beyond core Vulkan 1.0; a window needs VK_KHR_swapchain.
    VkDeviceCreateInfo ci = *info->vulkanCreateInfo;
    std::vector<const char*> exts(ci.ppEnabledExtensionNames, ci.ppEnabledExtensionNames + ci.enabledExtensionCount);
    if (inst->window) {
        bool present = false;
        for (const char* e : exts) present = present || std::strcmp(e, VK_KHR_SWAPCHAIN_EXTENSION_NAME) == 0;
        if (!present) exts.push_back(VK_KHR_SWAPCHAIN_EXTENSION_NAME);
    }
    ci.enabledExtensionCount = uint32_t(exts.size());
    ci.ppEnabledExtensionNames = exts.data();
    *vkResult = create(info->vulkanPhysicalDevice, &ci, info->vulkanAllocator, device);
    return XR_SUCCESS;
}

void destroyMessenger(Instance* inst) {
    if (!inst->messenger) return;
    auto fn = reinterpret_cast<PFN_vkDestroyDebugUtilsMessengerEXT>(
        vkGetInstanceProcAddr(inst->vkInstance, "vkDestroyDebugUtilsMessengerEXT"));
    if (fn) fn(inst->vkInstance, inst->messenger, nullptr);
    inst->messenger = VK_NULL_HANDLE;
}

}  // namespace wrsfov::xr
