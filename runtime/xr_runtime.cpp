// The runtime's core: the live-object registry, logging, pose math, xrGetInstanceProcAddr's
// dispatch table and the loader's entry point. The OpenXR calls are in one file per API area:
// xr_api_instance.cpp (instance, system, events, view configurations), xr_api_paths.cpp,
// xr_api_vulkan.cpp (XR_KHR_vulkan_enable / enable2), xr_api_actions.cpp and xr_session.cpp
// (sessions, spaces, swapchains, frames); their shared checks are in xr_verify.cpp.
#include <cmath>
#include <cstdio>
#include <cstring>
#include <ctime>
#include <new>

#include "xr_common/loader_negotiation.h"
#include "runtime/xr_objects.h"
#include "runtime/xr_verify.h"

#define WRSFOV_XR_EXPORT extern "C" __attribute__((visibility("default")))

namespace wrsfov::xr {

// ---------------------------------------------------------------------------------------------
// Registry, logging, pose math

namespace {
std::mutex& registryMutex() {
    static std::mutex m;
    return m;
}
std::unordered_map<const void*, ObjectType>& registry() {
    static std::unordered_map<const void*, ObjectType> r;
    return r;
}
}  // namespace

void registerObject(Object* o) {
    std::lock_guard lock(registryMutex());
    registry()[o] = o->type;
}
void unregisterObject(Object* o) {
    std::lock_guard lock(registryMutex());
    registry().erase(o);
}
Object* findObject(const void* handle, ObjectType type) {
    std::lock_guard lock(registryMutex());
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
// xrGetInstanceProcAddr

namespace {

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
    // No lock: the table is constant and an instance's extensions do not change after creation.
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
