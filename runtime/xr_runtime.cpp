// The runtime's instance-level half: loader negotiation, xrGetInstanceProcAddr, instance, system,
// paths, events, XR_KHR_vulkan_enable / enable2 and the action system. Sessions, spaces,
// swapchains and frames are in xr_session.cpp.
#include <cmath>
#include <cstdio>
#include <cstring>
#include <ctime>
#include <new>
#include <unordered_set>

#include <openxr/openxr_reflection.h>

#include "runtime/loader_negotiation.h"
#include "runtime/xr_objects.h"

#define WRSFOV_XR_EXPORT extern "C" __attribute__((visibility("default")))

namespace wrsfov::xr {

// ---------------------------------------------------------------------------------------------
// Registry, logging, pose math

std::recursive_mutex& apiMutex() {
    static std::recursive_mutex m;
    return m;
}

namespace {
std::unordered_map<const void*, ObjectType>& registry() {
    static std::unordered_map<const void*, ObjectType> r;
    return r;
}
}  // namespace

void registerObject(Object* o) { registry()[o] = o->type; }
void unregisterObject(Object* o) { registry().erase(o); }
Object* findObject(const void* handle, ObjectType type) {
    auto it = registry().find(handle);
    if (it == registry().end() || it->second != type) return nullptr;
    return static_cast<Object*>(const_cast<void*>(handle));
}

void logLine(const std::string& line) { std::fprintf(stderr, "[wrsfov-xr] %s\n", line.c_str()); }

XrTime nowXrTime() {
    timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return XrTime(ts.tv_sec) * 1000000000 + ts.tv_nsec;
}

Pose operator*(const Pose& a, const Pose& b) { return {a.q * b.q, a.p + a.q * b.p}; }
Pose inverse(const Pose& a) {
    const glm::quat c = glm::conjugate(a.q);
    return {c, -(c * a.p)};
}
Pose fromXr(const XrPosef& p) {
    return {glm::normalize(glm::quat(p.orientation.w, p.orientation.x, p.orientation.y, p.orientation.z)),
            {p.position.x, p.position.y, p.position.z}};
}
XrPosef toXr(const Pose& p) {
    XrPosef o;
    o.orientation = {p.q.x, p.q.y, p.q.z, p.q.w};
    o.position = {p.p.x, p.p.y, p.p.z};
    return o;
}
bool isValidPose(const XrPosef& p) {
    const float v[7] = {p.orientation.x, p.orientation.y, p.orientation.z, p.orientation.w,
                        p.position.x,    p.position.y,    p.position.z};
    for (float f : v)
        if (!std::isfinite(f)) return false;
    const float n = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2] + v[3] * v[3]);
    return std::abs(n - 1.0f) <= 1e-3f;
}

XrResult fillString(uint32_t capacity, uint32_t* countOutput, char* out, const std::string& value) {
    if (!countOutput) return XR_ERROR_VALIDATION_FAILURE;
    *countOutput = uint32_t(value.size() + 1);
    if (capacity == 0) return XR_SUCCESS;
    if (capacity < value.size() + 1) return XR_ERROR_SIZE_INSUFFICIENT;
    if (!out) return XR_ERROR_VALIDATION_FAILURE;
    std::memcpy(out, value.c_str(), value.size() + 1);
    return XR_SUCCESS;
}

// ---------------------------------------------------------------------------------------------
// Paths and events

namespace {

/// OpenXR path syntax: absolute, components of [a-z0-9-_.] that are not "." or "..", no empty one.
bool wellFormedPath(const char* s) {
    if (!s || s[0] != '/') return false;
    std::size_t n = std::strlen(s);
    if (n >= XR_MAX_PATH_LENGTH || s[n - 1] == '/') return false;
    std::string component;
    for (std::size_t i = 1; i <= n; ++i) {
        const char c = s[i];
        if (c == '/' || c == '\0') {
            if (component.empty() || component == "." || component == "..") return false;
            component.clear();
            continue;
        }
        if (!((c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '-' || c == '_' || c == '.')) return false;
        component += c;
    }
    return true;
}

/// Action and action-set names: NAME_INVALID when empty, PATH_FORMAT_INVALID when not one well-formed
/// path component (lower case, digits, '-', '_', '.'; terminated within the array).
XrResult checkName(const char* s, std::size_t max) {
    const std::size_t n = strnlen(s, max);
    if (n == 0) return XR_ERROR_NAME_INVALID;
    if (n == max) return XR_ERROR_PATH_FORMAT_INVALID;
    for (std::size_t i = 0; i < n; ++i) {
        const char c = s[i];
        if (!((c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '-' || c == '_' || c == '.'))
            return XR_ERROR_PATH_FORMAT_INVALID;
    }
    return XR_SUCCESS;
}

}  // namespace

XrPath Instance::path(const std::string& s) {
    auto it = pathIds.find(s);
    if (it != pathIds.end()) return it->second;
    paths.push_back(s);
    const XrPath id = XrPath(paths.size());
    pathIds.emplace(s, id);
    return id;
}

std::string Instance::pathString(XrPath p) const {
    if (p == XR_NULL_PATH || p > paths.size()) return {};
    return paths[p - 1];
}

XrResult checkSubaction(const Action& a, XrPath subaction) {
    if (subaction == XR_NULL_PATH) return XR_SUCCESS;
    if (a.set->instance->pathString(subaction).empty()) return XR_ERROR_PATH_INVALID;
    return std::find(a.subactionPaths.begin(), a.subactionPaths.end(), subaction) != a.subactionPaths.end()
               ? XR_SUCCESS
               : XR_ERROR_PATH_UNSUPPORTED;
}

void Instance::pushEvent(const XrEventDataBuffer& e) {
    constexpr std::size_t kMaxEvents = 256;
    if (events.size() >= kMaxEvents) {
        events.pop_front();
        eventsLost = true;
        ++lostCount;
    }
    events.push_back(e);
}

// ---------------------------------------------------------------------------------------------
// Instance and system

namespace {

constexpr XrSystemId kSystemId = 1;
constexpr uint32_t kMaxLayers = 16;

struct ExtensionInfo {
    const char* name;
    uint32_t version;
};
constexpr ExtensionInfo kExtensions[] = {
    {XR_KHR_VULKAN_ENABLE_EXTENSION_NAME, 8},
    {XR_KHR_VULKAN_ENABLE2_EXTENSION_NAME, 2},
    {XR_KHR_COMPOSITION_LAYER_DEPTH_EXTENSION_NAME, 5},
    {XR_EXT_EYE_GAZE_INTERACTION_EXTENSION_NAME, 1},
    {XR_FB_SPACE_WARP_EXTENSION_NAME, 1},
};

Instance* getInstance(XrInstance h) { return lookup<Instance>(h, ObjectType::Instance); }

XrResult checkSystem(Instance* inst, XrSystemId id) {
    if (!inst) return XR_ERROR_HANDLE_INVALID;
    return id == kSystemId ? XR_SUCCESS : XR_ERROR_SYSTEM_INVALID;
}

XRAPI_ATTR XrResult XRAPI_CALL xrEnumerateInstanceExtensionProperties(const char* layerName, uint32_t capacity,
                                                                      uint32_t* countOutput,
                                                                      XrExtensionProperties* properties) {
    std::lock_guard lock(apiMutex());
    if (layerName && *layerName) return XR_ERROR_API_LAYER_NOT_PRESENT;
    if (!countOutput) return XR_ERROR_VALIDATION_FAILURE;
    const uint32_t n = uint32_t(std::size(kExtensions));
    *countOutput = n;
    if (capacity == 0) return XR_SUCCESS;
    if (capacity < n) return XR_ERROR_SIZE_INSUFFICIENT;
    if (!properties) return XR_ERROR_VALIDATION_FAILURE;
    for (uint32_t i = 0; i < n; ++i) {
        if (properties[i].type != XR_TYPE_EXTENSION_PROPERTIES) return XR_ERROR_VALIDATION_FAILURE;
        std::snprintf(properties[i].extensionName, XR_MAX_EXTENSION_NAME_SIZE, "%s", kExtensions[i].name);
        properties[i].extensionVersion = kExtensions[i].version;
    }
    return XR_SUCCESS;
}

XRAPI_ATTR XrResult XRAPI_CALL xrEnumerateApiLayerProperties(uint32_t capacity, uint32_t* countOutput,
                                                             XrApiLayerProperties*) {
    if (!countOutput) return XR_ERROR_VALIDATION_FAILURE;
    (void)capacity;
    *countOutput = 0;  // the runtime has no layers of its own; the loader lists the installed ones
    return XR_SUCCESS;
}

XRAPI_ATTR XrResult XRAPI_CALL xrCreateInstance(const XrInstanceCreateInfo* info, XrInstance* out) {
    std::lock_guard lock(apiMutex());
    if (!info || !out || info->type != XR_TYPE_INSTANCE_CREATE_INFO) return XR_ERROR_VALIDATION_FAILURE;
    if (info->createFlags != 0) return XR_ERROR_VALIDATION_FAILURE;
    const XrVersion v = info->applicationInfo.apiVersion;
    if (XR_VERSION_MAJOR(v) != 1 || XR_VERSION_MINOR(v) != 0) return XR_ERROR_API_VERSION_UNSUPPORTED;
    if (info->applicationInfo.applicationName[0] == '\0') return XR_ERROR_NAME_INVALID;
    // The loader passes the create info down unchanged: the names of the layers it enabled (and
    // loaded above us) arrive here. The runtime has no layers of its own, so it only checks them.
    if (info->enabledApiLayerCount > 0 && !info->enabledApiLayerNames) return XR_ERROR_VALIDATION_FAILURE;
    for (uint32_t i = 0; i < info->enabledApiLayerCount; ++i)
        if (!info->enabledApiLayerNames[i]) return XR_ERROR_VALIDATION_FAILURE;
    auto inst = std::make_unique<Instance>();
    for (uint32_t i = 0; i < info->enabledExtensionCount; ++i) {
        const char* e = info->enabledExtensionNames ? info->enabledExtensionNames[i] : nullptr;
        if (!e) return XR_ERROR_VALIDATION_FAILURE;
        bool known = false;
        for (const auto& k : kExtensions) known = known || std::strcmp(k.name, e) == 0;
        if (!known) return XR_ERROR_EXTENSION_NOT_PRESENT;
        inst->extensions.insert(e);
    }
    auto config = loadRuntimeConfig();
    if (!config) {
        logLine("configuration: " + config.error().message);
        return XR_ERROR_INITIALIZATION_FAILED;
    }
    inst->config = *config;
    inst->applicationName = info->applicationInfo.applicationName;
    const bool display = std::getenv("DISPLAY") || std::getenv("WAYLAND_DISPLAY");
    if (config->output == Output::Window || (config->output == Output::Auto && display)) {
        auto exts = XrWindow::instanceExtensions();
        if (exts) {
            inst->window = true;
            inst->windowExtensions = *exts;
        } else {
            logLine("no window (" + exts.error().message + "): headless");
        }
    }
    inst->epoch = nowXrTime();
    registerObject(inst.get());
    *out = reinterpret_cast<XrInstance>(inst.get());
    logLine("instance for '" + inst->applicationName + "': method " +
            (config->compose ? std::string(toString(config->compositor.method)) : std::string("off")) +
            ", fovea " + std::to_string(config->compositor.foveaDeg) + " deg, " + std::to_string(config->width) + "x" +
            std::to_string(config->height) + " per eye at " + std::to_string(config->displayHz) + " Hz" +
            (config->record.empty() ? "" : ", recording to " + config->record));
    inst.release();
    return XR_SUCCESS;
}

void destroyMessenger(Instance* inst) {
    if (!inst->messenger) return;
    auto fn = reinterpret_cast<PFN_vkDestroyDebugUtilsMessengerEXT>(
        vkGetInstanceProcAddr(inst->vkInstance, "vkDestroyDebugUtilsMessengerEXT"));
    if (fn) fn(inst->vkInstance, inst->messenger, nullptr);
    inst->messenger = VK_NULL_HANDLE;
}

XRAPI_ATTR XrResult XRAPI_CALL xrDestroyInstance(XrInstance h) {
    std::lock_guard lock(apiMutex());
    Instance* inst = getInstance(h);
    if (!inst) return XR_ERROR_HANDLE_INVALID;
    while (!inst->sessions.empty()) destroySession(inst->sessions.back().get());
    for (auto& set : inst->actionSets) {
        for (auto& a : set->actions) unregisterObject(a.get());
        unregisterObject(set.get());
    }
    destroyMessenger(inst);
    unregisterObject(inst);
    delete inst;
    return XR_SUCCESS;
}

XRAPI_ATTR XrResult XRAPI_CALL xrGetInstanceProperties(XrInstance h, XrInstanceProperties* props) {
    std::lock_guard lock(apiMutex());
    if (!getInstance(h)) return XR_ERROR_HANDLE_INVALID;
    if (!props || props->type != XR_TYPE_INSTANCE_PROPERTIES) return XR_ERROR_VALIDATION_FAILURE;
    props->runtimeVersion = XR_MAKE_VERSION(0, 1, 0);
    std::snprintf(props->runtimeName, XR_MAX_RUNTIME_NAME_SIZE, "wrsfov simulated HMD");
    return XR_SUCCESS;
}

XRAPI_ATTR XrResult XRAPI_CALL xrPollEvent(XrInstance h, XrEventDataBuffer* event) {
    std::lock_guard lock(apiMutex());
    Instance* inst = getInstance(h);
    if (!inst) return XR_ERROR_HANDLE_INVALID;
    if (!event || event->type != XR_TYPE_EVENT_DATA_BUFFER) return XR_ERROR_VALIDATION_FAILURE;
    if (inst->eventsLost) {
        inst->eventsLost = false;
        auto* lost = reinterpret_cast<XrEventDataEventsLost*>(event);
        lost->type = XR_TYPE_EVENT_DATA_EVENTS_LOST;
        lost->next = nullptr;
        lost->lostEventCount = inst->lostCount;
        inst->lostCount = 0;
        return XR_SUCCESS;
    }
    if (inst->events.empty()) return XR_EVENT_UNAVAILABLE;
    *event = inst->events.front();
    inst->events.pop_front();
    return XR_SUCCESS;
}

/// A value without a name in our headers is printed as the specification asks:
/// `unknown` followed by the value in decimal (XR_UNKNOWN_SUCCESS_n, XR_UNKNOWN_FAILURE_-n,
/// XR_UNKNOWN_STRUCTURE_TYPE_n).
template <typename Enum>
XrResult enumString(XrInstance h, Enum value, char* buffer, std::size_t size, const char* (*name)(Enum),
                    const char* unknown) {
    std::lock_guard lock(apiMutex());
    if (!getInstance(h)) return XR_ERROR_HANDLE_INVALID;
    if (!buffer) return XR_ERROR_VALIDATION_FAILURE;
    if (const char* n = name(value)) std::snprintf(buffer, size, "%s", n);
    else
        std::snprintf(buffer, size, "%s%d", unknown, int(value));
    return XR_SUCCESS;
}

#define WRSFOV_ENUM_CASE(name, value) \
    case name:                        \
        return #name;
const char* resultName(XrResult r) {
    switch (r) {
        XR_LIST_ENUM_XrResult(WRSFOV_ENUM_CASE) default : return nullptr;
    }
}
const char* structureName(XrStructureType t) {
    switch (t) {
        XR_LIST_ENUM_XrStructureType(WRSFOV_ENUM_CASE) default : return nullptr;
    }
}
#undef WRSFOV_ENUM_CASE

XRAPI_ATTR XrResult XRAPI_CALL xrResultToString(XrInstance h, XrResult value, char buffer[XR_MAX_RESULT_STRING_SIZE]) {
    return enumString(h, value, buffer, XR_MAX_RESULT_STRING_SIZE, &resultName,
                      XR_SUCCEEDED(value) ? "XR_UNKNOWN_SUCCESS_" : "XR_UNKNOWN_FAILURE_");
}
XRAPI_ATTR XrResult XRAPI_CALL xrStructureTypeToString(XrInstance h, XrStructureType value,
                                                       char buffer[XR_MAX_STRUCTURE_NAME_SIZE]) {
    return enumString(h, value, buffer, XR_MAX_STRUCTURE_NAME_SIZE, &structureName, "XR_UNKNOWN_STRUCTURE_TYPE_");
}

XRAPI_ATTR XrResult XRAPI_CALL xrGetSystem(XrInstance h, const XrSystemGetInfo* info, XrSystemId* id) {
    std::lock_guard lock(apiMutex());
    if (!getInstance(h)) return XR_ERROR_HANDLE_INVALID;
    if (!info || !id || info->type != XR_TYPE_SYSTEM_GET_INFO) return XR_ERROR_VALIDATION_FAILURE;
    if (info->formFactor == XR_FORM_FACTOR_HEAD_MOUNTED_DISPLAY) {
        *id = kSystemId;
        return XR_SUCCESS;
    }
    // Any other value, known or not (XR_FORM_FACTOR_MAX_ENUM included), is a form factor this
    // runtime does not have: the specification's answer for it is FORM_FACTOR_UNSUPPORTED.
    return XR_ERROR_FORM_FACTOR_UNSUPPORTED;
}

XRAPI_ATTR XrResult XRAPI_CALL xrGetSystemProperties(XrInstance h, XrSystemId id, XrSystemProperties* props) {
    std::lock_guard lock(apiMutex());
    Instance* inst = getInstance(h);
    if (XrResult r = checkSystem(inst, id); r != XR_SUCCESS) return r;
    if (!props || props->type != XR_TYPE_SYSTEM_PROPERTIES) return XR_ERROR_VALIDATION_FAILURE;
    props->systemId = kSystemId;
    props->vendorId = 0;
    std::snprintf(props->systemName, XR_MAX_SYSTEM_NAME_SIZE, "wrsfov simulated HMD (synthetic gaze)");
    props->graphicsProperties.maxSwapchainImageWidth = 8192;
    props->graphicsProperties.maxSwapchainImageHeight = 8192;
    props->graphicsProperties.maxLayerCount = kMaxLayers;
    props->trackingProperties.orientationTracking = XR_TRUE;
    props->trackingProperties.positionTracking = XR_TRUE;
    for (auto* n = static_cast<XrBaseOutStructure*>(props->next); n; n = n->next) {
        if (n->type == XR_TYPE_SYSTEM_EYE_GAZE_INTERACTION_PROPERTIES_EXT) {
            reinterpret_cast<XrSystemEyeGazeInteractionPropertiesEXT*>(n)->supportsEyeGazeInteraction =
                inst->enabled(XR_EXT_EYE_GAZE_INTERACTION_EXTENSION_NAME) ? XR_TRUE : XR_FALSE;
        } else if (n->type == XR_TYPE_SYSTEM_SPACE_WARP_PROPERTIES_FB) {
            auto* sw = reinterpret_cast<XrSystemSpaceWarpPropertiesFB*>(n);
            // The compositor reads motion at the colour's size.
            sw->recommendedMotionVectorImageRectWidth = inst->config.width;
            sw->recommendedMotionVectorImageRectHeight = inst->config.height;
        }
    }
    return XR_SUCCESS;
}

XRAPI_ATTR XrResult XRAPI_CALL xrEnumerateEnvironmentBlendModes(XrInstance h, XrSystemId id,
                                                                XrViewConfigurationType type, uint32_t capacity,
                                                                uint32_t* countOutput, XrEnvironmentBlendMode* modes) {
    std::lock_guard lock(apiMutex());
    if (XrResult r = checkSystem(getInstance(h), id); r != XR_SUCCESS) return r;
    if (XrResult r = checkViewConfiguration(type); r != XR_SUCCESS) return r;
    return fillArray<XrEnvironmentBlendMode>(capacity, countOutput, modes, {XR_ENVIRONMENT_BLEND_MODE_OPAQUE});
}

XRAPI_ATTR XrResult XRAPI_CALL xrEnumerateViewConfigurations(XrInstance h, XrSystemId id, uint32_t capacity,
                                                             uint32_t* countOutput, XrViewConfigurationType* types) {
    std::lock_guard lock(apiMutex());
    if (XrResult r = checkSystem(getInstance(h), id); r != XR_SUCCESS) return r;
    return fillArray<XrViewConfigurationType>(capacity, countOutput, types,
                                              {XR_VIEW_CONFIGURATION_TYPE_PRIMARY_STEREO});
}

XRAPI_ATTR XrResult XRAPI_CALL xrGetViewConfigurationProperties(XrInstance h, XrSystemId id,
                                                                XrViewConfigurationType type,
                                                                XrViewConfigurationProperties* props) {
    std::lock_guard lock(apiMutex());
    if (XrResult r = checkSystem(getInstance(h), id); r != XR_SUCCESS) return r;
    if (!props || props->type != XR_TYPE_VIEW_CONFIGURATION_PROPERTIES) return XR_ERROR_VALIDATION_FAILURE;
    if (XrResult r = checkViewConfiguration(type); r != XR_SUCCESS) return r;
    props->viewConfigurationType = type;
    props->fovMutable = XR_FALSE;
    return XR_SUCCESS;
}

XRAPI_ATTR XrResult XRAPI_CALL xrEnumerateViewConfigurationViews(XrInstance h, XrSystemId id,
                                                                 XrViewConfigurationType type, uint32_t capacity,
                                                                 uint32_t* countOutput,
                                                                 XrViewConfigurationView* views) {
    std::lock_guard lock(apiMutex());
    Instance* inst = getInstance(h);
    if (XrResult r = checkSystem(inst, id); r != XR_SUCCESS) return r;
    if (XrResult r = checkViewConfiguration(type); r != XR_SUCCESS) return r;
    if (!countOutput) return XR_ERROR_VALIDATION_FAILURE;
    *countOutput = 2;
    if (capacity == 0) return XR_SUCCESS;
    if (capacity < 2) return XR_ERROR_SIZE_INSUFFICIENT;
    if (!views) return XR_ERROR_VALIDATION_FAILURE;
    for (int i = 0; i < 2; ++i) {
        if (views[i].type != XR_TYPE_VIEW_CONFIGURATION_VIEW) return XR_ERROR_VALIDATION_FAILURE;
        views[i].recommendedImageRectWidth = inst->config.width;
        views[i].recommendedImageRectHeight = inst->config.height;
        views[i].maxImageRectWidth = 8192;
        views[i].maxImageRectHeight = 8192;
        views[i].recommendedSwapchainSampleCount = 1;
        views[i].maxSwapchainSampleCount = 1;
    }
    return XR_SUCCESS;
}

XRAPI_ATTR XrResult XRAPI_CALL xrStringToPath(XrInstance h, const char* pathString, XrPath* path) {
    std::lock_guard lock(apiMutex());
    Instance* inst = getInstance(h);
    if (!inst) return XR_ERROR_HANDLE_INVALID;
    if (!pathString || !path) return XR_ERROR_VALIDATION_FAILURE;
    if (!wellFormedPath(pathString)) return XR_ERROR_PATH_FORMAT_INVALID;
    *path = inst->path(pathString);
    return XR_SUCCESS;
}

XRAPI_ATTR XrResult XRAPI_CALL xrPathToString(XrInstance h, XrPath path, uint32_t capacity, uint32_t* countOutput,
                                              char* buffer) {
    std::lock_guard lock(apiMutex());
    Instance* inst = getInstance(h);
    if (!inst) return XR_ERROR_HANDLE_INVALID;
    const std::string s = inst->pathString(path);
    if (s.empty()) return XR_ERROR_PATH_INVALID;
    return fillString(capacity, countOutput, buffer, s);
}

// ---------------------------------------------------------------------------------------------
// XR_KHR_vulkan_enable and XR_KHR_vulkan_enable2

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
    std::lock_guard lock(apiMutex());
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

XRAPI_ATTR XrResult XRAPI_CALL xrGetVulkanGraphicsRequirementsKHR(XrInstance h, XrSystemId id,
                                                                  XrGraphicsRequirementsVulkanKHR* req) {
    return graphicsRequirements(h, id, req);
}
XRAPI_ATTR XrResult XRAPI_CALL xrGetVulkanGraphicsRequirements2KHR(XrInstance h, XrSystemId id,
                                                                   XrGraphicsRequirementsVulkanKHR* req) {
    return graphicsRequirements(h, id, req);
}

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

XRAPI_ATTR XrResult XRAPI_CALL xrGetVulkanGraphicsDeviceKHR(XrInstance h, XrSystemId id, VkInstance vkInstance,
                                                            VkPhysicalDevice* device) {
    std::lock_guard lock(apiMutex());
    Instance* inst = getInstance(h);
    if (XrResult r = checkSystem(inst, id); r != XR_SUCCESS) return r;
    if (!inst->enabled(XR_KHR_VULKAN_ENABLE_EXTENSION_NAME)) return XR_ERROR_FUNCTION_UNSUPPORTED;
    return chooseDevice(inst, vkInstance, vkGetInstanceProcAddr, device);
}

XRAPI_ATTR XrResult XRAPI_CALL xrGetVulkanGraphicsDevice2KHR(XrInstance h, const XrVulkanGraphicsDeviceGetInfoKHR* info,
                                                             VkPhysicalDevice* device) {
    std::lock_guard lock(apiMutex());
    Instance* inst = getInstance(h);
    if (!inst) return XR_ERROR_HANDLE_INVALID;
    if (!inst->enabled(XR_KHR_VULKAN_ENABLE2_EXTENSION_NAME)) return XR_ERROR_FUNCTION_UNSUPPORTED;
    if (!info || info->type != XR_TYPE_VULKAN_GRAPHICS_DEVICE_GET_INFO_KHR) return XR_ERROR_VALIDATION_FAILURE;
    if (XrResult r = checkSystem(inst, info->systemId); r != XR_SUCCESS) return r;
    if (inst->vkInstance != VK_NULL_HANDLE && info->vulkanInstance != inst->vkInstance)
        return XR_ERROR_VALIDATION_FAILURE;  // not the instance xrCreateVulkanInstanceKHR made
    return chooseDevice(inst, info->vulkanInstance, vkGetInstanceProcAddr, device);
}

/// The space-separated extension list of xrGetVulkan{Instance,Device}ExtensionsKHR: the passes need
/// none; a window needs the surface extensions and VK_KHR_swapchain.
XrResult extensionList(XrInstance h, XrSystemId id, uint32_t capacity, uint32_t* countOutput, char* buffer,
                       bool device) {
    std::lock_guard lock(apiMutex());
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
    std::lock_guard lock(apiMutex());
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
    std::lock_guard lock(apiMutex());
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

// ---------------------------------------------------------------------------------------------
// Actions

ActionSet* getActionSet(XrActionSet h) { return lookup<ActionSet>(h, ObjectType::ActionSet); }
Action* getAction(XrAction h) { return lookup<Action>(h, ObjectType::Action); }
Session* getSession(XrSession h) { return lookup<Session>(h, ObjectType::Session); }

const char* const kEyeGazeProfile = "/interaction_profiles/ext/eye_gaze_interaction";
const char* const kEyeGazePose = "/user/eyes_ext/input/gaze_ext/pose";

/// One input or output of an interaction profile: its path under the top-level user path, and the
/// one user path that has it where only one does (the Touch controller's buttons).
struct Component {
    const char* path;
    const char* onlyUser = nullptr;
};

/// The interaction profiles of OpenXR 1.0 (and of XR_EXT_eye_gaze_interaction when it is enabled):
/// their top-level user paths and the components 1.0 gives them. Components that later versions or
/// extensions add (grip_surface, palm_ext, dpad, proximity, ...) are not here, so with an OpenXR 1.0
/// instance they are unsupported paths, as the specification requires.
struct Profile {
    const char* path;
    std::vector<const char*> users;
    std::vector<Component> components;
    const char* extension = nullptr;  // needed to use the profile at all
};

const std::vector<Profile>& profiles() {
    static const std::vector<const char*> hands = {"/user/hand/left", "/user/hand/right"};
    constexpr const char* left = "/user/hand/left";
    constexpr const char* right = "/user/hand/right";
    // One profile's components in a few lines rather than one per line.
    // clang-format off
    static const std::vector<Profile> p = {
        {"/interaction_profiles/khr/simple_controller",
         hands,
         {{"/input/select/click"}, {"/input/menu/click"}, {"/input/grip/pose"}, {"/input/aim/pose"},
          {"/output/haptic"}}},
        {"/interaction_profiles/google/daydream_controller",
         hands,
         {{"/input/select/click"}, {"/input/trackpad"}, {"/input/trackpad/x"}, {"/input/trackpad/y"},
          {"/input/trackpad/click"}, {"/input/trackpad/touch"}, {"/input/grip/pose"}, {"/input/aim/pose"}}},
        {"/interaction_profiles/htc/vive_controller",
         hands,
         {{"/input/system/click"}, {"/input/squeeze/click"}, {"/input/menu/click"}, {"/input/trigger/click"},
          {"/input/trigger/value"}, {"/input/trackpad"}, {"/input/trackpad/x"}, {"/input/trackpad/y"},
          {"/input/trackpad/click"}, {"/input/trackpad/touch"}, {"/input/grip/pose"}, {"/input/aim/pose"},
          {"/output/haptic"}}},
        {"/interaction_profiles/htc/vive_pro",
         {"/user/head"},
         {{"/input/system/click"}, {"/input/volume_up/click"}, {"/input/volume_down/click"},
          {"/input/mute_mic/click"}}},
        {"/interaction_profiles/microsoft/motion_controller",
         hands,
         {{"/input/menu/click"}, {"/input/squeeze/click"}, {"/input/trigger/value"}, {"/input/thumbstick"},
          {"/input/thumbstick/x"}, {"/input/thumbstick/y"}, {"/input/thumbstick/click"}, {"/input/trackpad"},
          {"/input/trackpad/x"}, {"/input/trackpad/y"}, {"/input/trackpad/click"}, {"/input/trackpad/touch"},
          {"/input/grip/pose"}, {"/input/aim/pose"}, {"/output/haptic"}}},
        {"/interaction_profiles/microsoft/xbox_controller",
         {"/user/gamepad"},
         {{"/input/menu/click"}, {"/input/view/click"}, {"/input/a/click"}, {"/input/b/click"}, {"/input/x/click"},
          {"/input/y/click"}, {"/input/dpad_down/click"}, {"/input/dpad_right/click"}, {"/input/dpad_up/click"},
          {"/input/dpad_left/click"}, {"/input/shoulder_left/click"}, {"/input/shoulder_right/click"},
          {"/input/thumbstick_left/click"}, {"/input/thumbstick_right/click"}, {"/input/trigger_left/value"},
          {"/input/trigger_right/value"}, {"/input/thumbstick_left"}, {"/input/thumbstick_left/x"},
          {"/input/thumbstick_left/y"}, {"/input/thumbstick_right"}, {"/input/thumbstick_right/x"},
          {"/input/thumbstick_right/y"}, {"/output/haptic_left"}, {"/output/haptic_right"},
          {"/output/haptic_left_trigger"}, {"/output/haptic_right_trigger"}}},
        {"/interaction_profiles/oculus/go_controller",
         hands,
         {{"/input/system/click"}, {"/input/trigger/click"}, {"/input/back/click"}, {"/input/trackpad"},
          {"/input/trackpad/x"}, {"/input/trackpad/y"}, {"/input/trackpad/click"}, {"/input/trackpad/touch"},
          {"/input/grip/pose"}, {"/input/aim/pose"}}},
        {"/interaction_profiles/oculus/touch_controller",
         hands,
         {{"/input/x/click", left}, {"/input/x/touch", left}, {"/input/y/click", left}, {"/input/y/touch", left},
          {"/input/menu/click", left}, {"/input/a/click", right}, {"/input/a/touch", right},
          {"/input/b/click", right}, {"/input/b/touch", right}, {"/input/system/click", right},
          {"/input/squeeze/value"}, {"/input/trigger/value"}, {"/input/trigger/touch"}, {"/input/thumbstick"},
          {"/input/thumbstick/x"}, {"/input/thumbstick/y"}, {"/input/thumbstick/click"},
          {"/input/thumbstick/touch"}, {"/input/thumbrest/touch"}, {"/input/grip/pose"}, {"/input/aim/pose"},
          {"/output/haptic"}}},
        {"/interaction_profiles/valve/index_controller",
         hands,
         {{"/input/system/click"}, {"/input/system/touch"}, {"/input/a/click"}, {"/input/a/touch"},
          {"/input/b/click"}, {"/input/b/touch"}, {"/input/squeeze/value"}, {"/input/squeeze/force"},
          {"/input/trigger/click"}, {"/input/trigger/value"}, {"/input/trigger/touch"}, {"/input/thumbstick"},
          {"/input/thumbstick/x"}, {"/input/thumbstick/y"}, {"/input/thumbstick/click"},
          {"/input/thumbstick/touch"}, {"/input/trackpad"}, {"/input/trackpad/x"}, {"/input/trackpad/y"},
          {"/input/trackpad/force"}, {"/input/trackpad/touch"}, {"/input/grip/pose"}, {"/input/aim/pose"},
          {"/output/haptic"}}},
        {kEyeGazeProfile, {"/user/eyes_ext"}, {{"/input/gaze_ext/pose"}}, XR_EXT_EYE_GAZE_INTERACTION_EXTENSION_NAME},
    };
    // clang-format on
    return p;
}

/// The top-level user paths an instance knows: those of its profiles (/user/eyes_ext only with
/// XR_EXT_eye_gaze_interaction enabled).
bool knownUserPath(const Instance& inst, const std::string& user) {
    for (const Profile& p : profiles())
        if (!p.extension || inst.enabled(p.extension))
            for (const char* u : p.users)
                if (user == u) return true;
    return false;
}

/// Whether `binding` is a source of `profile`: a top-level user path of the profile followed by one
/// of its components for that user path, or by an identifier alone (`/input/trigger`, which the
/// runtime resolves to the identifier's component). The action's type is not checked: the
/// specification lets an application suggest any action for any source (a pose or haptic source for
/// a boolean action, say); a source whose type cannot feed the action is simply never bound to it.
bool bindingFits(const Profile& profile, const std::string& binding) {
    for (const char* user : profile.users) {
        const std::string u = user;
        if (binding.size() <= u.size() || binding.compare(0, u.size(), u) != 0 || binding[u.size()] != '/') continue;
        const std::string rest = binding.substr(u.size());
        const bool identifier = std::count(rest.begin(), rest.end(), '/') == 2;  // "/input/trigger"
        for (const Component& c : profile.components) {
            if (c.onlyUser && u != c.onlyUser) continue;
            const std::string path = c.path;
            if (rest == path) return true;
            if (identifier && path.size() > rest.size() && path.compare(0, rest.size(), rest) == 0 &&
                path[rest.size()] == '/')
                return true;
        }
    }
    return false;
}

XRAPI_ATTR XrResult XRAPI_CALL xrCreateActionSet(XrInstance h, const XrActionSetCreateInfo* info, XrActionSet* out) {
    std::lock_guard lock(apiMutex());
    Instance* inst = getInstance(h);
    if (!inst) return XR_ERROR_HANDLE_INVALID;
    if (!info || !out || info->type != XR_TYPE_ACTION_SET_CREATE_INFO) return XR_ERROR_VALIDATION_FAILURE;
    if (XrResult r = checkName(info->actionSetName, XR_MAX_ACTION_SET_NAME_SIZE); r != XR_SUCCESS) return r;
    if (strnlen(info->localizedActionSetName, XR_MAX_LOCALIZED_ACTION_SET_NAME_SIZE) == 0)
        return XR_ERROR_LOCALIZED_NAME_INVALID;
    for (auto& s : inst->actionSets) {
        if (s->destroyed) continue;  // its names were released with its handle
        if (s->name == info->actionSetName) return XR_ERROR_NAME_DUPLICATED;
        if (s->localizedName == info->localizedActionSetName) return XR_ERROR_LOCALIZED_NAME_DUPLICATED;
    }
    auto set = std::make_unique<ActionSet>();
    set->instance = inst;
    set->name = info->actionSetName;
    set->localizedName = info->localizedActionSetName;
    set->priority = info->priority;
    registerObject(set.get());
    *out = reinterpret_cast<XrActionSet>(set.get());
    inst->actionSets.push_back(std::move(set));
    return XR_SUCCESS;
}

XRAPI_ATTR XrResult XRAPI_CALL xrDestroyActionSet(XrActionSet h) {
    std::lock_guard lock(apiMutex());
    ActionSet* set = getActionSet(h);
    if (!set) return XR_ERROR_HANDLE_INVALID;
    // An attached set lives on in its sessions (the handle is gone; the spec lets the runtime keep it).
    auto& sets = set->instance->actionSets;
    for (auto& a : set->actions) {
        if (!a->destroyed) unregisterObject(a.get());
        a->destroyed = true;
    }
    unregisterObject(set);
    set->destroyed = true;
    if (!set->attached)
        for (auto it = sets.begin(); it != sets.end(); ++it)
            if (it->get() == set) {
                sets.erase(it);
                break;
            }
    return XR_SUCCESS;
}

XRAPI_ATTR XrResult XRAPI_CALL xrCreateAction(XrActionSet h, const XrActionCreateInfo* info, XrAction* out) {
    std::lock_guard lock(apiMutex());
    ActionSet* set = getActionSet(h);
    if (!set) return XR_ERROR_HANDLE_INVALID;
    if (!info || !out || info->type != XR_TYPE_ACTION_CREATE_INFO) return XR_ERROR_VALIDATION_FAILURE;
    if (set->attached) return XR_ERROR_ACTIONSETS_ALREADY_ATTACHED;
    switch (info->actionType) {
        case XR_ACTION_TYPE_BOOLEAN_INPUT:
        case XR_ACTION_TYPE_FLOAT_INPUT:
        case XR_ACTION_TYPE_VECTOR2F_INPUT:
        case XR_ACTION_TYPE_POSE_INPUT:
        case XR_ACTION_TYPE_VIBRATION_OUTPUT:
            break;
        default:
            return XR_ERROR_VALIDATION_FAILURE;
    }
    if (XrResult r = checkName(info->actionName, XR_MAX_ACTION_NAME_SIZE); r != XR_SUCCESS) return r;
    if (strnlen(info->localizedActionName, XR_MAX_LOCALIZED_ACTION_NAME_SIZE) == 0)
        return XR_ERROR_LOCALIZED_NAME_INVALID;
    for (auto& a : set->actions) {
        if (a->destroyed) continue;  // its names were released with its handle
        if (a->name == info->actionName) return XR_ERROR_NAME_DUPLICATED;
        if (a->localizedName == info->localizedActionName) return XR_ERROR_LOCALIZED_NAME_DUPLICATED;
    }
    if (info->countSubactionPaths > 0 && !info->subactionPaths) return XR_ERROR_VALIDATION_FAILURE;
    std::vector<XrPath> sub;
    for (uint32_t i = 0; i < info->countSubactionPaths; ++i) {
        const std::string p = set->instance->pathString(info->subactionPaths[i]);
        if (p.empty()) return XR_ERROR_PATH_INVALID;
        if (!knownUserPath(*set->instance, p)) return XR_ERROR_PATH_UNSUPPORTED;
        for (XrPath q : sub)
            if (q == info->subactionPaths[i]) return XR_ERROR_PATH_UNSUPPORTED;  // duplicated
        sub.push_back(info->subactionPaths[i]);
    }
    auto a = std::make_unique<Action>();
    a->set = set;
    a->name = info->actionName;
    a->localizedName = info->localizedActionName;
    a->actionType = info->actionType;
    a->subactionPaths = std::move(sub);
    registerObject(a.get());
    *out = reinterpret_cast<XrAction>(a.get());
    set->actions.push_back(std::move(a));
    return XR_SUCCESS;
}

XRAPI_ATTR XrResult XRAPI_CALL xrDestroyAction(XrAction h) {
    std::lock_guard lock(apiMutex());
    Action* a = getAction(h);
    if (!a) return XR_ERROR_HANDLE_INVALID;
    unregisterObject(a);  // the object stays with its set (bindings and spaces may refer to it)
    a->destroyed = true;  // its names may be used again
    return XR_SUCCESS;
}

XRAPI_ATTR XrResult XRAPI_CALL xrSuggestInteractionProfileBindings(
    XrInstance h, const XrInteractionProfileSuggestedBinding* suggested) {
    std::lock_guard lock(apiMutex());
    Instance* inst = getInstance(h);
    if (!inst) return XR_ERROR_HANDLE_INVALID;
    if (!suggested || suggested->type != XR_TYPE_INTERACTION_PROFILE_SUGGESTED_BINDING ||
        suggested->countSuggestedBindings == 0 || !suggested->suggestedBindings)
        return XR_ERROR_VALIDATION_FAILURE;
    const std::string profilePath = inst->pathString(suggested->interactionProfile);
    if (profilePath.empty()) return XR_ERROR_PATH_INVALID;
    const Profile* profile = nullptr;
    for (const auto& p : profiles())
        if (profilePath == p.path && (!p.extension || inst->enabled(p.extension))) profile = &p;
    if (!profile) return XR_ERROR_PATH_UNSUPPORTED;
    std::vector<XrActionSuggestedBinding> bindings;
    for (uint32_t i = 0; i < suggested->countSuggestedBindings; ++i) {
        const XrActionSuggestedBinding& b = suggested->suggestedBindings[i];
        Action* a = getAction(b.action);
        if (!a) return XR_ERROR_HANDLE_INVALID;
        if (a->set->attached) return XR_ERROR_ACTIONSETS_ALREADY_ATTACHED;
        const std::string binding = inst->pathString(b.binding);
        if (binding.empty()) return XR_ERROR_PATH_INVALID;
        if (!bindingFits(*profile, binding)) return XR_ERROR_PATH_UNSUPPORTED;
        bindings.push_back(b);
    }
    inst->suggested[suggested->interactionProfile] = std::move(bindings);
    return XR_SUCCESS;
}

XRAPI_ATTR XrResult XRAPI_CALL xrAttachSessionActionSets(XrSession h, const XrSessionActionSetsAttachInfo* info) {
    std::lock_guard lock(apiMutex());
    Session* s = getSession(h);
    if (!s) return XR_ERROR_HANDLE_INVALID;
    if (!info || info->type != XR_TYPE_SESSION_ACTION_SETS_ATTACH_INFO || info->countActionSets == 0 ||
        !info->actionSets)
        return XR_ERROR_VALIDATION_FAILURE;
    if (!s->attachedSets.empty()) return XR_ERROR_ACTIONSETS_ALREADY_ATTACHED;
    std::vector<ActionSet*> sets;
    for (uint32_t i = 0; i < info->countActionSets; ++i) {
        ActionSet* set = getActionSet(info->actionSets[i]);
        if (!set) return XR_ERROR_HANDLE_INVALID;
        sets.push_back(set);
    }
    Instance* inst = s->instance;
    for (ActionSet* set : sets) set->attached = true;
    s->attachedSets = sets;
    // Our simulated HMD has eyes and no controllers: only the eye-gaze profile can become current,
    // and only for a pose action (a binding of another type is suggested but never bound). It becomes
    // current at the next xrSyncActions, the one call in which the specification lets a runtime
    // change interaction profiles (and queue XR_TYPE_EVENT_DATA_INTERACTION_PROFILE_CHANGED).
    auto eyes = inst->pathIds.find(kEyeGazeProfile);
    if (eyes != inst->pathIds.end() && inst->suggested.count(eyes->second))
        for (const auto& b : inst->suggested[eyes->second])
            for (ActionSet* set : sets)
                for (auto& a : set->actions)
                    if (reinterpret_cast<XrAction>(a.get()) == b.action && a->actionType == XR_ACTION_TYPE_POSE_INPUT)
                        s->eyeGazeBound = true;
    return XR_SUCCESS;
}

XRAPI_ATTR XrResult XRAPI_CALL xrGetCurrentInteractionProfile(XrSession h, XrPath topLevelUserPath,
                                                              XrInteractionProfileState* state) {
    std::lock_guard lock(apiMutex());
    Session* s = getSession(h);
    if (!s) return XR_ERROR_HANDLE_INVALID;
    if (!state || state->type != XR_TYPE_INTERACTION_PROFILE_STATE) return XR_ERROR_VALIDATION_FAILURE;
    if (s->attachedSets.empty()) return XR_ERROR_ACTIONSET_NOT_ATTACHED;
    const std::string user = s->instance->pathString(topLevelUserPath);
    if (user.empty()) return XR_ERROR_PATH_INVALID;
    if (!knownUserPath(*s->instance, user)) return XR_ERROR_PATH_UNSUPPORTED;
    state->interactionProfile =
        user == "/user/eyes_ext" && s->eyeGazeCurrent ? s->instance->path(kEyeGazeProfile) : XR_NULL_PATH;
    return XR_SUCCESS;
}

XRAPI_ATTR XrResult XRAPI_CALL xrSyncActions(XrSession h, const XrActionsSyncInfo* info) {
    std::lock_guard lock(apiMutex());
    Session* s = getSession(h);
    if (!s) return XR_ERROR_HANDLE_INVALID;
    if (!info || info->type != XR_TYPE_ACTIONS_SYNC_INFO) return XR_ERROR_VALIDATION_FAILURE;
    if (info->countActiveActionSets > 0 && !info->activeActionSets) return XR_ERROR_VALIDATION_FAILURE;
    for (uint32_t i = 0; i < info->countActiveActionSets; ++i) {
        ActionSet* set = getActionSet(info->activeActionSets[i].actionSet);
        if (!set) return XR_ERROR_HANDLE_INVALID;
        if (std::find(s->attachedSets.begin(), s->attachedSets.end(), set) == s->attachedSets.end())
            return XR_ERROR_ACTIONSET_NOT_ATTACHED;
        const XrPath sub = info->activeActionSets[i].subactionPath;
        if (sub != XR_NULL_PATH) {
            const std::string p = s->instance->pathString(sub);
            if (p.empty()) return XR_ERROR_PATH_INVALID;
            if (!knownUserPath(*s->instance, p)) return XR_ERROR_PATH_UNSUPPORTED;
        }
    }
    if (s->eyeGazeBound && !s->eyeGazeCurrent) {
        s->eyeGazeCurrent = true;
        XrEventDataBuffer e{XR_TYPE_EVENT_DATA_BUFFER};
        auto* changed = reinterpret_cast<XrEventDataInteractionProfileChanged*>(&e);
        changed->type = XR_TYPE_EVENT_DATA_INTERACTION_PROFILE_CHANGED;
        changed->session = h;
        s->instance->pushEvent(e);
    }
    s->synced = sessionFocused(*s);
    return s->synced ? XR_SUCCESS : XR_SESSION_NOT_FOCUSED;
}

/// Shared checks of the xrGetActionState* calls; on success `action` is set.
XrResult actionStateCheck(XrSession h, const XrActionStateGetInfo* info, XrActionType type, void* state,
                          XrStructureType stateType, Session*& session, Action*& action) {
    session = getSession(h);
    if (!session) return XR_ERROR_HANDLE_INVALID;
    if (!info || info->type != XR_TYPE_ACTION_STATE_GET_INFO || !state ||
        static_cast<XrBaseOutStructure*>(state)->type != stateType)
        return XR_ERROR_VALIDATION_FAILURE;
    action = getAction(info->action);
    if (!action) return XR_ERROR_HANDLE_INVALID;
    if (action->actionType != type) return XR_ERROR_ACTION_TYPE_MISMATCH;
    if (std::find(session->attachedSets.begin(), session->attachedSets.end(), action->set) ==
        session->attachedSets.end())
        return XR_ERROR_ACTIONSET_NOT_ATTACHED;
    if (XrResult r = checkSubaction(*action, info->subactionPath); r != XR_SUCCESS) return r;
    return XR_SUCCESS;
}

XRAPI_ATTR XrResult XRAPI_CALL xrGetActionStateBoolean(XrSession h, const XrActionStateGetInfo* info,
                                                       XrActionStateBoolean* state) {
    std::lock_guard lock(apiMutex());
    Session* s;
    Action* a;
    if (XrResult r = actionStateCheck(h, info, XR_ACTION_TYPE_BOOLEAN_INPUT, state, XR_TYPE_ACTION_STATE_BOOLEAN, s, a);
        r != XR_SUCCESS)
        return r;
    state->currentState = XR_FALSE;
    state->changedSinceLastSync = XR_FALSE;
    state->lastChangeTime = 0;
    state->isActive = XR_FALSE;  // no controllers
    return XR_SUCCESS;
}

XRAPI_ATTR XrResult XRAPI_CALL xrGetActionStateFloat(XrSession h, const XrActionStateGetInfo* info,
                                                     XrActionStateFloat* state) {
    std::lock_guard lock(apiMutex());
    Session* s;
    Action* a;
    if (XrResult r = actionStateCheck(h, info, XR_ACTION_TYPE_FLOAT_INPUT, state, XR_TYPE_ACTION_STATE_FLOAT, s, a);
        r != XR_SUCCESS)
        return r;
    state->currentState = 0.0f;
    state->changedSinceLastSync = XR_FALSE;
    state->lastChangeTime = 0;
    state->isActive = XR_FALSE;
    return XR_SUCCESS;
}

XRAPI_ATTR XrResult XRAPI_CALL xrGetActionStateVector2f(XrSession h, const XrActionStateGetInfo* info,
                                                        XrActionStateVector2f* state) {
    std::lock_guard lock(apiMutex());
    Session* s;
    Action* a;
    if (XrResult r =
            actionStateCheck(h, info, XR_ACTION_TYPE_VECTOR2F_INPUT, state, XR_TYPE_ACTION_STATE_VECTOR2F, s, a);
        r != XR_SUCCESS)
        return r;
    state->currentState = {0.0f, 0.0f};
    state->changedSinceLastSync = XR_FALSE;
    state->lastChangeTime = 0;
    state->isActive = XR_FALSE;
    return XR_SUCCESS;
}

XRAPI_ATTR XrResult XRAPI_CALL xrGetActionStatePose(XrSession h, const XrActionStateGetInfo* info,
                                                    XrActionStatePose* state) {
    std::lock_guard lock(apiMutex());
    Session* s;
    Action* a;
    if (XrResult r = actionStateCheck(h, info, XR_ACTION_TYPE_POSE_INPUT, state, XR_TYPE_ACTION_STATE_POSE, s, a);
        r != XR_SUCCESS)
        return r;
    const std::string sub = s->instance->pathString(info->subactionPath);
    state->isActive = s->synced && boundToEyeGaze(*s, a) && (sub.empty() || sub == "/user/eyes_ext");
    return XR_SUCCESS;
}

XRAPI_ATTR XrResult XRAPI_CALL xrEnumerateBoundSourcesForAction(XrSession h,
                                                                const XrBoundSourcesForActionEnumerateInfo* info,
                                                                uint32_t capacity, uint32_t* countOutput,
                                                                XrPath* sources) {
    std::lock_guard lock(apiMutex());
    Session* s = getSession(h);
    if (!s) return XR_ERROR_HANDLE_INVALID;
    if (!info || info->type != XR_TYPE_BOUND_SOURCES_FOR_ACTION_ENUMERATE_INFO) return XR_ERROR_VALIDATION_FAILURE;
    Action* a = getAction(info->action);
    if (!a) return XR_ERROR_HANDLE_INVALID;
    if (s->attachedSets.empty()) return XR_ERROR_ACTIONSET_NOT_ATTACHED;
    std::vector<XrPath> bound;
    if (boundToEyeGaze(*s, a)) bound.push_back(s->instance->path(kEyeGazePose));
    return fillArray(capacity, countOutput, sources, bound);
}

XRAPI_ATTR XrResult XRAPI_CALL xrGetInputSourceLocalizedName(XrSession h, const XrInputSourceLocalizedNameGetInfo* info,
                                                             uint32_t capacity, uint32_t* countOutput, char* buffer) {
    std::lock_guard lock(apiMutex());
    Session* s = getSession(h);
    if (!s) return XR_ERROR_HANDLE_INVALID;
    if (!info || info->type != XR_TYPE_INPUT_SOURCE_LOCALIZED_NAME_GET_INFO || info->whichComponents == 0)
        return XR_ERROR_VALIDATION_FAILURE;
    if (s->attachedSets.empty()) return XR_ERROR_ACTIONSET_NOT_ATTACHED;
    const std::string path = s->instance->pathString(info->sourcePath);
    if (path.empty()) return XR_ERROR_PATH_INVALID;
    if (path != kEyeGazePose) return XR_ERROR_PATH_UNSUPPORTED;
    std::string name;
    auto add = [&](const char* part) { name += (name.empty() ? "" : " ") + std::string(part); };
    if (info->whichComponents & XR_INPUT_SOURCE_LOCALIZED_NAME_USER_PATH_BIT) add("Eyes");
    if (info->whichComponents & XR_INPUT_SOURCE_LOCALIZED_NAME_INTERACTION_PROFILE_BIT) add("Eye Gaze Interaction");
    if (info->whichComponents & XR_INPUT_SOURCE_LOCALIZED_NAME_COMPONENT_BIT) add("Gaze Pose");
    return fillString(capacity, countOutput, buffer, name);
}

XrResult hapticCheck(XrSession h, const XrHapticActionInfo* info) {
    Session* s = getSession(h);
    if (!s) return XR_ERROR_HANDLE_INVALID;
    if (!info || info->type != XR_TYPE_HAPTIC_ACTION_INFO) return XR_ERROR_VALIDATION_FAILURE;
    Action* a = getAction(info->action);
    if (!a) return XR_ERROR_HANDLE_INVALID;
    if (a->actionType != XR_ACTION_TYPE_VIBRATION_OUTPUT) return XR_ERROR_ACTION_TYPE_MISMATCH;
    if (std::find(s->attachedSets.begin(), s->attachedSets.end(), a->set) == s->attachedSets.end())
        return XR_ERROR_ACTIONSET_NOT_ATTACHED;
    if (XrResult r = checkSubaction(*a, info->subactionPath); r != XR_SUCCESS) return r;
    return s->synced ? XR_SUCCESS : XR_SESSION_NOT_FOCUSED;
}

XRAPI_ATTR XrResult XRAPI_CALL xrApplyHapticFeedback(XrSession h, const XrHapticActionInfo* info,
                                                     const XrHapticBaseHeader* feedback) {
    std::lock_guard lock(apiMutex());
    if (!feedback || feedback->type != XR_TYPE_HAPTIC_VIBRATION) return XR_ERROR_VALIDATION_FAILURE;
    return hapticCheck(h, info);  // no actuator: accepted and dropped
}

XRAPI_ATTR XrResult XRAPI_CALL xrStopHapticFeedback(XrSession h, const XrHapticActionInfo* info) {
    std::lock_guard lock(apiMutex());
    return hapticCheck(h, info);
}

// ---------------------------------------------------------------------------------------------
// xrGetInstanceProcAddr

XRAPI_ATTR XrResult XRAPI_CALL xrGetInstanceProcAddr(XrInstance instance, const char* name,
                                                     PFN_xrVoidFunction* function);

struct Entry {
    const char* name;
    PFN_xrVoidFunction fn;
    const char* extension;  // nullptr: core
};
#define WRSFOV_CORE(f) {#f, reinterpret_cast<PFN_xrVoidFunction>(&f), nullptr}
#define WRSFOV_EXT(f, e) {#f, reinterpret_cast<PFN_xrVoidFunction>(&f), e}
const Entry kEntries[] = {
    WRSFOV_CORE(xrGetInstanceProcAddr),
    WRSFOV_CORE(xrEnumerateApiLayerProperties),
    WRSFOV_CORE(xrEnumerateInstanceExtensionProperties),
    WRSFOV_CORE(xrCreateInstance),
    WRSFOV_CORE(xrDestroyInstance),
    WRSFOV_CORE(xrGetInstanceProperties),
    WRSFOV_CORE(xrPollEvent),
    WRSFOV_CORE(xrResultToString),
    WRSFOV_CORE(xrStructureTypeToString),
    WRSFOV_CORE(xrGetSystem),
    WRSFOV_CORE(xrGetSystemProperties),
    WRSFOV_CORE(xrEnumerateEnvironmentBlendModes),
    WRSFOV_CORE(xrCreateSession),
    WRSFOV_CORE(xrDestroySession),
    WRSFOV_CORE(xrEnumerateReferenceSpaces),
    WRSFOV_CORE(xrCreateReferenceSpace),
    WRSFOV_CORE(xrGetReferenceSpaceBoundsRect),
    WRSFOV_CORE(xrCreateActionSpace),
    WRSFOV_CORE(xrLocateSpace),
    WRSFOV_CORE(xrDestroySpace),
    WRSFOV_CORE(xrEnumerateViewConfigurations),
    WRSFOV_CORE(xrGetViewConfigurationProperties),
    WRSFOV_CORE(xrEnumerateViewConfigurationViews),
    WRSFOV_CORE(xrEnumerateSwapchainFormats),
    WRSFOV_CORE(xrCreateSwapchain),
    WRSFOV_CORE(xrDestroySwapchain),
    WRSFOV_CORE(xrEnumerateSwapchainImages),
    WRSFOV_CORE(xrAcquireSwapchainImage),
    WRSFOV_CORE(xrWaitSwapchainImage),
    WRSFOV_CORE(xrReleaseSwapchainImage),
    WRSFOV_CORE(xrBeginSession),
    WRSFOV_CORE(xrEndSession),
    WRSFOV_CORE(xrRequestExitSession),
    WRSFOV_CORE(xrWaitFrame),
    WRSFOV_CORE(xrBeginFrame),
    WRSFOV_CORE(xrEndFrame),
    WRSFOV_CORE(xrLocateViews),
    WRSFOV_CORE(xrStringToPath),
    WRSFOV_CORE(xrPathToString),
    WRSFOV_CORE(xrCreateActionSet),
    WRSFOV_CORE(xrDestroyActionSet),
    WRSFOV_CORE(xrCreateAction),
    WRSFOV_CORE(xrDestroyAction),
    WRSFOV_CORE(xrSuggestInteractionProfileBindings),
    WRSFOV_CORE(xrAttachSessionActionSets),
    WRSFOV_CORE(xrGetCurrentInteractionProfile),
    WRSFOV_CORE(xrGetActionStateBoolean),
    WRSFOV_CORE(xrGetActionStateFloat),
    WRSFOV_CORE(xrGetActionStateVector2f),
    WRSFOV_CORE(xrGetActionStatePose),
    WRSFOV_CORE(xrSyncActions),
    WRSFOV_CORE(xrEnumerateBoundSourcesForAction),
    WRSFOV_CORE(xrGetInputSourceLocalizedName),
    WRSFOV_CORE(xrApplyHapticFeedback),
    WRSFOV_CORE(xrStopHapticFeedback),
    WRSFOV_EXT(xrGetVulkanInstanceExtensionsKHR, XR_KHR_VULKAN_ENABLE_EXTENSION_NAME),
    WRSFOV_EXT(xrGetVulkanDeviceExtensionsKHR, XR_KHR_VULKAN_ENABLE_EXTENSION_NAME),
    WRSFOV_EXT(xrGetVulkanGraphicsDeviceKHR, XR_KHR_VULKAN_ENABLE_EXTENSION_NAME),
    WRSFOV_EXT(xrGetVulkanGraphicsRequirementsKHR, XR_KHR_VULKAN_ENABLE_EXTENSION_NAME),
    WRSFOV_EXT(xrCreateVulkanInstanceKHR, XR_KHR_VULKAN_ENABLE2_EXTENSION_NAME),
    WRSFOV_EXT(xrCreateVulkanDeviceKHR, XR_KHR_VULKAN_ENABLE2_EXTENSION_NAME),
    WRSFOV_EXT(xrGetVulkanGraphicsDevice2KHR, XR_KHR_VULKAN_ENABLE2_EXTENSION_NAME),
    WRSFOV_EXT(xrGetVulkanGraphicsRequirements2KHR, XR_KHR_VULKAN_ENABLE2_EXTENSION_NAME),
};
#undef WRSFOV_CORE
#undef WRSFOV_EXT

XRAPI_ATTR XrResult XRAPI_CALL xrGetInstanceProcAddr(XrInstance instance, const char* name,
                                                     PFN_xrVoidFunction* function) {
    std::lock_guard lock(apiMutex());
    if (!name || !function) return XR_ERROR_VALIDATION_FAILURE;
    *function = nullptr;
    if (instance == XR_NULL_HANDLE) {
        // Without an instance only these three may be asked for.
        for (const char* pre : {"xrEnumerateInstanceExtensionProperties", "xrEnumerateApiLayerProperties",
                                "xrCreateInstance"})
            if (std::strcmp(name, pre) == 0)
                for (const Entry& e : kEntries)
                    if (std::strcmp(e.name, name) == 0) *function = e.fn;
        return *function ? XR_SUCCESS : XR_ERROR_HANDLE_INVALID;
    }
    Instance* inst = getInstance(instance);
    if (!inst) return XR_ERROR_HANDLE_INVALID;
    for (const Entry& e : kEntries)
        if (std::strcmp(e.name, name) == 0) {
            if (e.extension && !inst->enabled(e.extension)) return XR_ERROR_FUNCTION_UNSUPPORTED;
            *function = e.fn;
            return XR_SUCCESS;
        }
    return XR_ERROR_FUNCTION_UNSUPPORTED;
}

}  // namespace

}  // namespace wrsfov::xr

// ---------------------------------------------------------------------------------------------
// The one exported symbol: the loader's entry point.

WRSFOV_XR_EXPORT XrResult xrNegotiateLoaderRuntimeInterface(const XrNegotiateLoaderInfo* loaderInfo,
                                                            XrNegotiateRuntimeRequest* request) {
    if (!loaderInfo || !request || loaderInfo->structType != XR_LOADER_INTERFACE_STRUCT_LOADER_INFO ||
        loaderInfo->structVersion != XR_LOADER_INFO_STRUCT_VERSION ||
        loaderInfo->structSize != sizeof(XrNegotiateLoaderInfo) ||
        request->structType != XR_LOADER_INTERFACE_STRUCT_RUNTIME_REQUEST ||
        request->structVersion != XR_RUNTIME_INFO_STRUCT_VERSION ||
        request->structSize != sizeof(XrNegotiateRuntimeRequest))
        return XR_ERROR_INITIALIZATION_FAILED;
    if (loaderInfo->minInterfaceVersion > XR_CURRENT_LOADER_RUNTIME_VERSION ||
        loaderInfo->maxInterfaceVersion < XR_CURRENT_LOADER_RUNTIME_VERSION)
        return XR_ERROR_INITIALIZATION_FAILED;
    const XrVersion ours = XR_MAKE_VERSION(1, 0, XR_VERSION_PATCH(XR_CURRENT_API_VERSION));
    if (XR_MAKE_VERSION(XR_VERSION_MAJOR(loaderInfo->minApiVersion), XR_VERSION_MINOR(loaderInfo->minApiVersion), 0) >
            XR_MAKE_VERSION(1, 0, 0) ||
        XR_MAKE_VERSION(XR_VERSION_MAJOR(loaderInfo->maxApiVersion), XR_VERSION_MINOR(loaderInfo->maxApiVersion), 0) <
            XR_MAKE_VERSION(1, 0, 0))
        return XR_ERROR_INITIALIZATION_FAILED;
    request->runtimeInterfaceVersion = XR_CURRENT_LOADER_RUNTIME_VERSION;
    request->runtimeApiVersion = ours;
    request->getInstanceProcAddr = &wrsfov::xr::xrGetInstanceProcAddr;
    return XR_SUCCESS;
}
