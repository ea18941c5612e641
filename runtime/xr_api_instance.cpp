// Instance and system: extensions, xrCreateInstance / xrDestroyInstance, instance properties,
// events (xrPollEvent), result and structure-type strings, the system and its view configurations.
#include <cstdio>
#include <cstring>

#include <openxr/openxr_reflection.h>

#include "xr_common/xr_inset.h"
#include "runtime/xr_objects.h"
#include "runtime/xr_verify.h"

namespace wrsfov::xr {

// ---------------------------------------------------------------------------------------------
// Events

void Instance::pushEvent(const XrEventDataBuffer& e) {
    constexpr std::size_t kMaxEvents = 256;
    std::lock_guard lock(eventMutex);
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
    {XR_VARJO_QUAD_VIEWS_EXTENSION_NAME, XR_VARJO_quad_views_SPEC_VERSION},
    {XR_VARJO_FOVEATED_RENDERING_EXTENSION_NAME, XR_VARJO_foveated_rendering_SPEC_VERSION},
};

bool isQuadViewExtension(const char* name) {
    return std::strcmp(name, XR_VARJO_QUAD_VIEWS_EXTENSION_NAME) == 0 ||
           std::strcmp(name, XR_VARJO_FOVEATED_RENDERING_EXTENSION_NAME) == 0;
}

/// The extensions offered: all of kExtensions, less the quad views' where the configuration
/// (`quad_views = 0`) withdraws them. A configuration that does not load offers them all (xrCreateInstance
/// then fails, naming the bad value).
std::vector<ExtensionInfo> offeredExtensions() {
    auto config = loadRuntimeConfig();
    const bool quad = !config || config->quadViews;
    std::vector<ExtensionInfo> out;
    for (const auto& e : kExtensions)
        if (quad || !isQuadViewExtension(e.name)) out.push_back(e);
    return out;
}

}  // namespace

XRAPI_ATTR XrResult XRAPI_CALL xrEnumerateInstanceExtensionProperties(const char* layerName, uint32_t capacity,
                                                                      uint32_t* countOutput,
                                                                      XrExtensionProperties* properties) {
    if (layerName && *layerName) return XR_ERROR_API_LAYER_NOT_PRESENT;
    if (!countOutput) return XR_ERROR_VALIDATION_FAILURE;
    const std::vector<ExtensionInfo> offered = offeredExtensions();
    const uint32_t n = uint32_t(offered.size());
    *countOutput = n;
    if (capacity == 0) return XR_SUCCESS;
    if (capacity < n) return XR_ERROR_SIZE_INSUFFICIENT;
    if (!properties) return XR_ERROR_VALIDATION_FAILURE;
    for (uint32_t i = 0; i < n; ++i) {
        if (properties[i].type != XR_TYPE_EXTENSION_PROPERTIES) return XR_ERROR_VALIDATION_FAILURE;
        std::snprintf(properties[i].extensionName, XR_MAX_EXTENSION_NAME_SIZE, "%s", offered[i].name);
        properties[i].extensionVersion = offered[i].version;
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
    auto config = loadRuntimeConfig();
    if (!config) {
        logLine("configuration: " + config.error().message);
        return XR_ERROR_INITIALIZATION_FAILED;
    }
    for (uint32_t i = 0; i < info->enabledExtensionCount; ++i) {
        const char* e = info->enabledExtensionNames ? info->enabledExtensionNames[i] : nullptr;
        if (!e) return XR_ERROR_VALIDATION_FAILURE;
        bool known = false;
        for (const auto& k : kExtensions) known = known || std::strcmp(k.name, e) == 0;
        if (!known || (!config->quadViews && isQuadViewExtension(e))) return XR_ERROR_EXTENSION_NOT_PRESENT;
        inst->extensions.insert(e);
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

XRAPI_ATTR XrResult XRAPI_CALL xrDestroyInstance(XrInstance h) {
    Instance* inst = getInstance(h);
    if (!inst) return XR_ERROR_HANDLE_INVALID;
    {
        std::lock_guard lock(inst->mutex);
        while (!inst->sessions.empty()) destroySession(inst->sessions.back().get());
        for (auto& set : inst->actionSets) {
            for (auto& a : set->actions) unregisterObject(a.get());
            unregisterObject(set.get());
        }
        destroyMessenger(inst);
        unregisterObject(inst);
    }
    delete inst;  // no other thread may use the instance or its children now (external synchronisation)
    return XR_SUCCESS;
}

XRAPI_ATTR XrResult XRAPI_CALL xrGetInstanceProperties(XrInstance h, XrInstanceProperties* props) {
    std::lock_guard lock(stateMutex(h));
    if (!getInstance(h)) return XR_ERROR_HANDLE_INVALID;
    if (!props || props->type != XR_TYPE_INSTANCE_PROPERTIES) return XR_ERROR_VALIDATION_FAILURE;
    props->runtimeVersion = XR_MAKE_VERSION(0, 1, 0);
    std::snprintf(props->runtimeName, XR_MAX_RUNTIME_NAME_SIZE, "wrsfov simulated HMD");
    return XR_SUCCESS;
}

XRAPI_ATTR XrResult XRAPI_CALL xrPollEvent(XrInstance h, XrEventDataBuffer* event) {
    Instance* inst = getInstance(h);
    if (!inst) return XR_ERROR_HANDLE_INVALID;
    std::lock_guard lock(inst->eventMutex);
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

namespace {

/// A value without a name in our headers is printed as the specification asks:
/// `unknown` followed by the value in decimal (XR_UNKNOWN_SUCCESS_n, XR_UNKNOWN_FAILURE_-n,
/// XR_UNKNOWN_STRUCTURE_TYPE_n).
template <typename Enum>
XrResult enumString(XrInstance h, Enum value, char* buffer, std::size_t size, const char* (*name)(Enum),
                    const char* unknown) {
    std::lock_guard lock(stateMutex(h));
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
const char* structureName(XrStructureType t) {
    switch (t) {
        XR_LIST_ENUM_XrStructureType(WRSFOV_ENUM_CASE) default : return nullptr;
    }
}

}  // namespace

const char* resultName(XrResult r) {
    switch (r) {
        XR_LIST_ENUM_XrResult(WRSFOV_ENUM_CASE) default : return nullptr;
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
    std::lock_guard lock(stateMutex(h));
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
    std::lock_guard lock(stateMutex(h));
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
        } else if (n->type == XR_TYPE_SYSTEM_FOVEATED_RENDERING_PROPERTIES_VARJO) {
            // Rendering gaze is there whenever the runtime has a gaze source (it may still be invalid at
            // times: a blink, a dropout; XR_REFERENCE_SPACE_TYPE_COMBINED_EYE_VARJO says when).
            reinterpret_cast<XrSystemFoveatedRenderingPropertiesVARJO*>(n)->supportsFoveatedRendering =
                inst->enabled(XR_VARJO_FOVEATED_RENDERING_EXTENSION_NAME) && inst->config.gaze != GazeKind::None
                    ? XR_TRUE
                    : XR_FALSE;
        }
    }
    return XR_SUCCESS;
}

XRAPI_ATTR XrResult XRAPI_CALL xrEnumerateEnvironmentBlendModes(XrInstance h, XrSystemId id,
                                                                XrViewConfigurationType type, uint32_t capacity,
                                                                uint32_t* countOutput, XrEnvironmentBlendMode* modes) {
    std::lock_guard lock(stateMutex(h));
    Instance* inst = getInstance(h);
    if (XrResult r = checkSystem(inst, id); r != XR_SUCCESS) return r;
    if (XrResult r = checkViewConfiguration(*inst, type); r != XR_SUCCESS) return r;
    return fillArray<XrEnvironmentBlendMode>(capacity, countOutput, modes, {XR_ENVIRONMENT_BLEND_MODE_OPAQUE});
}

XRAPI_ATTR XrResult XRAPI_CALL xrEnumerateViewConfigurations(XrInstance h, XrSystemId id, uint32_t capacity,
                                                             uint32_t* countOutput, XrViewConfigurationType* types) {
    std::lock_guard lock(stateMutex(h));
    Instance* inst = getInstance(h);
    if (XrResult r = checkSystem(inst, id); r != XR_SUCCESS) return r;
    // In order of preference: an application that enabled quad views gets them first.
    std::vector<XrViewConfigurationType> offered;
    if (inst->enabled(XR_VARJO_QUAD_VIEWS_EXTENSION_NAME))
        offered.push_back(XR_VIEW_CONFIGURATION_TYPE_PRIMARY_QUAD_VARJO);
    offered.push_back(XR_VIEW_CONFIGURATION_TYPE_PRIMARY_STEREO);
    return fillArray<XrViewConfigurationType>(capacity, countOutput, types, offered);
}

XRAPI_ATTR XrResult XRAPI_CALL xrGetViewConfigurationProperties(XrInstance h, XrSystemId id,
                                                                XrViewConfigurationType type,
                                                                XrViewConfigurationProperties* props) {
    std::lock_guard lock(stateMutex(h));
    Instance* inst = getInstance(h);
    if (XrResult r = checkSystem(inst, id); r != XR_SUCCESS) return r;
    if (!props || props->type != XR_TYPE_VIEW_CONFIGURATION_PROPERTIES) return XR_ERROR_VALIDATION_FAILURE;
    if (XrResult r = checkViewConfiguration(*inst, type); r != XR_SUCCESS) return r;
    props->viewConfigurationType = type;
    props->fovMutable = XR_FALSE;
    return XR_SUCCESS;
}

XRAPI_ATTR XrResult XRAPI_CALL xrEnumerateViewConfigurationViews(XrInstance h, XrSystemId id,
                                                                 XrViewConfigurationType type, uint32_t capacity,
                                                                 uint32_t* countOutput,
                                                                 XrViewConfigurationView* views) {
    std::lock_guard lock(stateMutex(h));
    Instance* inst = getInstance(h);
    if (XrResult r = checkSystem(inst, id); r != XR_SUCCESS) return r;
    if (XrResult r = checkViewConfiguration(*inst, type); r != XR_SUCCESS) return r;
    if (!countOutput) return XR_ERROR_VALIDATION_FAILURE;
    const uint32_t n = viewCount(type);
    *countOutput = n;
    if (capacity == 0) return XR_SUCCESS;
    if (capacity < n) return XR_ERROR_SIZE_INSUFFICIENT;
    if (!views) return XR_ERROR_VALIDATION_FAILURE;
    for (uint32_t i = 0; i < n; ++i)
        if (views[i].type != XR_TYPE_VIEW_CONFIGURATION_VIEW) return XR_ERROR_VALIDATION_FAILURE;
    // Quad views: 0, 1 the wide views, 2, 3 the insets. An XrFoveatedViewConfigurationViewVARJO chained
    // asks for the foveated inset's size: the inset keeps its size wherever the gaze puts it, so the
    // answer is the same with the chain or without it.
    const QuadViewSizes quad = quadViewSizes(inst->config);
    for (uint32_t i = 0; i < n; ++i) {
        glm::uvec2 size(inst->config.width, inst->config.height);
        if (n == 4) size = i < 2 ? quad.wide : quad.inset;
        views[i].recommendedImageRectWidth = size.x;
        views[i].recommendedImageRectHeight = size.y;
        views[i].maxImageRectWidth = 8192;
        views[i].maxImageRectHeight = 8192;
        views[i].recommendedSwapchainSampleCount = 1;
        views[i].maxSwapchainSampleCount = 1;
    }
    return XR_SUCCESS;
}

}  // namespace wrsfov::xr
