// XR_APILAYER_WRSFOV_foveation: an OpenXR API layer that runs the wrsfov compositor (foveation and
// WRS) over the stereo projection layer of any Vulkan OpenXR application, on any runtime.
//
// Per session (XR_KHR_vulkan_enable / enable2): the application's Vulkan device and queue are adopted
// (vk::Context::adopt); its swapchains are created with the usage the compositor needs added and
// their images imported (Compositor::importSwapchain); at xrEndFrame the first projection layer's two
// views (and their depth) are composited, the output copied into a swapchain of the layer's own
// made by the runtime, and a patched copy of the frame end (that swapchain in place of the
// application's) goes down the chain. Both are submitted on the application's queue and not waited
// for in xrEndFrame: the compositor's reads of an application swapchain are waited for in
// xrWaitSwapchainImage and before it is destroyed; the application's structures are never modified. Gaze comes
// from the runtime's XR_EXT_eye_gaze_interaction through an action set of the layer's own, else from
// the configured source (WRSFOV_LAYER_*). Anything unsupported passes through with one log line;
// an error inside the layer disables it for the session instead of failing the call.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <span>
#include <string>
#include <vector>

#define XR_USE_GRAPHICS_API_VULKAN
#include <vulkan/vulkan.h>
#include <openxr/openxr.h>
#include <openxr/openxr_platform.h>

#include <glm/gtc/quaternion.hpp>
#define GLM_ENABLE_EXPERIMENTAL
#include <glm/gtx/quaternion.hpp>

#include "compositor/compositor.h"
#include "gaze/frame_gaze.h"
#include "gaze/source.h"
#include "runtime/loader_negotiation.h"
#include "runtime/xr_config.h"
#include "runtime/xr_frame.h"
#include "runtime/xr_inset.h"

#define WRSFOV_LAYER_EXPORT extern "C" __attribute__((visibility("default")))

namespace wrsfov::xrlayer {
namespace {

using xr::findNext;
using xr::loadConfig;
using xr::RuntimeConfig;

constexpr const char* kLayerName = "XR_APILAYER_WRSFOV_foveation";
constexpr const char* kEyeProfile = "/interaction_profiles/ext/eye_gaze_interaction";
constexpr const char* kEyePose = "/user/eyes_ext/input/gaze_ext/pose";

void logLine(const std::string& s) { std::fprintf(stderr, "[wrsfov-layer] %s\n", s.c_str()); }

// The next link's functions the layer calls.
struct Next {
    PFN_xrGetInstanceProcAddr getInstanceProcAddr = nullptr;
    PFN_xrDestroyInstance destroyInstance = nullptr;
    PFN_xrCreateSession createSession = nullptr;
    PFN_xrDestroySession destroySession = nullptr;
    PFN_xrCreateSwapchain createSwapchain = nullptr;
    PFN_xrDestroySwapchain destroySwapchain = nullptr;
    PFN_xrEnumerateSwapchainImages enumerateSwapchainImages = nullptr;
    PFN_xrEnumerateSwapchainFormats enumerateSwapchainFormats = nullptr;
    PFN_xrAcquireSwapchainImage acquireSwapchainImage = nullptr;
    PFN_xrWaitSwapchainImage waitSwapchainImage = nullptr;
    PFN_xrReleaseSwapchainImage releaseSwapchainImage = nullptr;
    PFN_xrEndFrame endFrame = nullptr;
    PFN_xrStringToPath stringToPath = nullptr;
    PFN_xrCreateActionSet createActionSet = nullptr;
    PFN_xrCreateAction createAction = nullptr;
    PFN_xrDestroyActionSet destroyActionSet = nullptr;
    PFN_xrSuggestInteractionProfileBindings suggestInteractionProfileBindings = nullptr;
    PFN_xrAttachSessionActionSets attachSessionActionSets = nullptr;
    PFN_xrSyncActions syncActions = nullptr;
    PFN_xrGetSystemProperties getSystemProperties = nullptr;
    PFN_xrGetCurrentInteractionProfile getCurrentInteractionProfile = nullptr;
    PFN_xrPollEvent pollEvent = nullptr;
    PFN_xrCreateActionSpace createActionSpace = nullptr;
    PFN_xrCreateReferenceSpace createReferenceSpace = nullptr;
    PFN_xrLocateSpace locateSpace = nullptr;
    PFN_xrDestroySpace destroySpace = nullptr;
    // Quad views offered by the layer (XR_VARJO_quad_views on a stereo runtime).
    PFN_xrEnumerateViewConfigurations enumerateViewConfigurations = nullptr;
    PFN_xrGetViewConfigurationProperties getViewConfigurationProperties = nullptr;
    PFN_xrEnumerateViewConfigurationViews enumerateViewConfigurationViews = nullptr;
    PFN_xrEnumerateEnvironmentBlendModes enumerateEnvironmentBlendModes = nullptr;
    PFN_xrBeginSession beginSession = nullptr;
    PFN_xrLocateViews locateViews = nullptr;
    PFN_xrEnumerateReferenceSpaces enumerateReferenceSpaces = nullptr;
};

struct InstanceState {
    Next next;
    bool passThrough = false;  // DISABLE_XR_APILAYER_WRSFOV_foveation: every call goes straight down
    RuntimeConfig config;
    bool eyeGaze = false;  // the runtime's XR_EXT_eye_gaze_interaction is enabled
    // The application enabled XR_EXT_eye_gaze_interaction itself. When only the layer did, the
    // extension must stay invisible: the system properties say no eye-gaze interaction, the profile
    // and its user path are unsupported, and the profile changes it causes are not reported.
    bool appEyeGaze = false;
    XrActionSet gazeSet = XR_NULL_HANDLE;
    XrAction gazeAction = XR_NULL_HANDLE;
    XrPath eyeProfile = XR_NULL_PATH, eyePose = XR_NULL_PATH, eyeUser = XR_NULL_PATH;
    bool appSuggestedEyes = false;  // the application suggested bindings for the eye-gaze profile
    // The top-level user paths of the other OpenXR 1.0 profiles: what the application can see change.
    std::vector<XrPath> otherUsers;

    /// The layer's eye gaze must not show through to the application.
    bool hideEyes() const { return eyeGaze && (!appEyeGaze || !appSuggestedEyes); }
    // XR_VARJO_quad_views (and XR_VARJO_foveated_rendering) enabled by the application on a runtime
    // without them: the layer offers the quad view configuration over the runtime's stereo one and
    // composes the four views into stereo. False where the runtime has them (the layer stays out of
    // the way) or the application did not ask.
    bool quadViews = false, foveatedRendering = false;
};

struct SwapchainState {
    XrSession session = XR_NULL_HANDLE;
    XrSwapchainCreateInfo info{};
    std::vector<VkImage> images;
    std::unique_ptr<layers::Swapchain> imported;  // null: not a format or use the compositor reads
    std::vector<uint32_t> acquired;
};

struct SessionState {
    XrInstance instance = XR_NULL_HANDLE;
    XrSystemId system = XR_NULL_SYSTEM_ID;
    std::unique_ptr<vk::Context> ctx;
    std::unique_ptr<Compositor> comp;
    std::unique_ptr<gaze::GazeSource> source;
    bool disabled = false;
    std::string why;
    XrSpace gazeSpace = XR_NULL_HANDLE;
    bool gazeAttached = false;
    // The interaction profile of each of InstanceState::otherUsers the application last heard of
    // (an XR_TYPE_EVENT_DATA_INTERACTION_PROFILE_CHANGED only the layer's binding caused is dropped).
    std::vector<XrPath> profilesSeen;
    // The layer's output swapchain (2 layers, layer = eye), made by the runtime.
    XrSwapchain out = XR_NULL_HANDLE;
    std::vector<VkImage> outImages;
    uint32_t outWidth = 0, outHeight = 0;
    int64_t outFormat = 0;
    uint64_t frames = 0, processed = 0, gpuFrames = 0, fallbackFrames = 0;
    uint64_t projected = 0;  // frames ended with a projection layer (what there is to foveate)
    double gpuMs = 0;
    // Host time spent in the layer's part of xrEndFrame (recording and submitting, no GPU wait).
    double endFrameMs = 0;
    // The frame's GPU work is submitted, not waited for: the compositor's passes signal `composited`,
    // the copy into the output swapchain waits for it and signals `copied`. The compositor waits for
    // its own last frame when it next needs it (the next frame, a wait on an application swapchain
    // it read, teardown); the copy's command buffer is waited for before it is recorded again.
    VkCommandBuffer copyCb = VK_NULL_HANDLE;
    vk::Fence copied;
    vk::Semaphore composited;
    bool copyInFlight = false;
    bool statsPending = false;  // the last submitted frame's GPU times are not yet counted
    XrTime epoch = 0;
    std::map<int, bool> logged;
    // Quad views the layer offers (InstanceState::quadViews): the session began with them, and the
    // runtime's stereo views' recommended size, the size the four views are composed at.
    bool quad = false;
    uint32_t displayWidth = 0, displayHeight = 0;
};

std::mutex g_mutex;
std::map<XrInstance, InstanceState> g_instances;
std::map<XrSession, SessionState> g_sessions;
std::map<XrSwapchain, SwapchainState> g_swapchains;
std::map<XrActionSet, XrInstance> g_actionSets;  // the application's, for the checks of xrCreateAction
// XR_REFERENCE_SPACE_TYPE_COMBINED_EYE_VARJO spaces the layer offers: a VIEW space of the runtime's
// (at the identity) standing in for each, turned to the gaze and then by the application's pose in
// xrLocateSpace.
struct CombinedEye {
    XrSession session = XR_NULL_HANDLE;
    XrPosef pose{};  // poseInReferenceSpace
};
std::map<XrSpace, CombinedEye> g_combinedEye;

bool isQuadExtension(const char* e) {
    return std::strcmp(e, XR_VARJO_QUAD_VIEWS_EXTENSION_NAME) == 0 ||
           std::strcmp(e, XR_VARJO_FOVEATED_RENDERING_EXTENSION_NAME) == 0;
}

template <typename F>
void load(PFN_xrGetInstanceProcAddr gipa, XrInstance inst, const char* name, F& fn) {
    PFN_xrVoidFunction f = nullptr;
    if (gipa(inst, name, &f) == XR_SUCCESS) fn = reinterpret_cast<F>(f);
}

void disable(SessionState& s, const std::string& why) {
    if (s.disabled) return;
    s.disabled = true;
    s.why = why;
    logLine("disabled for this session: " + why + " (frames pass through untouched)");
}

/// Waits for the compositor's last frame (its reads of the application's swapchains, its output) and
/// counts its GPU times, which the compositor fills in when it waits.
void waitComposited(SessionState& s) {
    if (!s.comp) return;
    if (Status st = s.comp->waitFrame(); !st) disable(s, st.message());
    if (!s.statsPending) return;
    s.statsPending = false;
    const FrameStats& stats = s.comp->stats();
    if (stats.gpu.valid) s.gpuMs += stats.gpu.total, ++s.gpuFrames;
}

/// Waits for the last copy into the output swapchain.
void waitCopied(SessionState& s) {
    if (!s.copyInFlight) return;
    s.copyInFlight = false;
    const VkResult r = s.ctx->waitSubmission(s.copied.get());
    VkFence f = s.copied.get();
    vkResetFences(s.ctx->device(), 1, &f);
    if (r != VK_SUCCESS) disable(s, std::string("copying the output: ") + vk::resultString(r));
}

/// Everything the layer submitted has finished: before a swapchain it used is destroyed, and at the
/// end of the session.
void settle(SessionState& s) {
    waitComposited(s);
    waitCopied(s);
}

std::optional<layers::Format> colorFormat(int64_t f) {
    switch (f) {
        case VK_FORMAT_R8G8B8A8_SRGB:
            return layers::Format::RGBA8_SRGB;
        case VK_FORMAT_R8G8B8A8_UNORM:
            return layers::Format::RGBA8;
        case VK_FORMAT_R16G16B16A16_SFLOAT:
            return layers::Format::RGBA16F;
        case VK_FORMAT_D32_SFLOAT:
            return layers::Format::D32F;
        default:
            return std::nullopt;  // e.g. BGRA, depth-stencil: passed through
    }
}

// ---- Instance ---------------------------------------------------------------------------------

XRAPI_ATTR XrResult XRAPI_CALL layerGetInstanceProcAddr(XrInstance instance, const char* name,
                                                        PFN_xrVoidFunction* function);

XRAPI_ATTR XrResult XRAPI_CALL layerCreateApiLayerInstance(const XrInstanceCreateInfo* info,
                                                           const XrApiLayerCreateInfo* layerInfo, XrInstance* instance) {
    if (!info || !layerInfo || !instance || !layerInfo->nextInfo ||
        layerInfo->structType != XR_LOADER_INTERFACE_STRUCT_API_LAYER_CREATE_INFO ||
        std::strcmp(layerInfo->nextInfo->layerName, kLayerName) != 0)
        return XR_ERROR_INITIALIZATION_FAILED;
    XrApiLayerNextInfo* mine = layerInfo->nextInfo;
    // The loader honours disable_environment for implicit layers only; this explicit layer honours it
    // itself: loaded, it hands every call to the next link untouched.
    if (const char* off = std::getenv("DISABLE_XR_APILAYER_WRSFOV_foveation"); off && *off) {
        XrApiLayerCreateInfo down = *layerInfo;
        down.nextInfo = mine->next;
        XrResult r = mine->nextCreateApiLayerInstance(info, &down, instance);
        if (XR_SUCCEEDED(r)) {
            std::lock_guard lock(g_mutex);
            InstanceState& st = g_instances[*instance];
            st.passThrough = true;
            st.next.getInstanceProcAddr = mine->nextGetInstanceProcAddr;
            load(mine->nextGetInstanceProcAddr, *instance, "xrDestroyInstance", st.next.destroyInstance);
        }
        return r;
    }
    auto config = loadConfig("WRSFOV_LAYER_");
    if (!config) {
        logLine("configuration: " + config.error().message);
        return XR_ERROR_INITIALIZATION_FAILED;
    }
    // Enable the runtime's eye-gaze interaction when the application did not: asked for, and asked
    // again without it when the runtime does not have it (a layer cannot list the runtime's
    // extensions through the layers below it). Quad views the same way: where the runtime refuses
    // them, the layer offers them itself and asks again without them.
    const std::vector<const char*> appExts(info->enabledExtensionNames,
                                           info->enabledExtensionNames + info->enabledExtensionCount);
    bool appEyeGaze = false, appQuad = false, appFoveated = false;
    for (const char* e : appExts) {
        appEyeGaze = appEyeGaze || std::strcmp(e, XR_EXT_EYE_GAZE_INTERACTION_EXTENSION_NAME) == 0;
        appQuad = appQuad || std::strcmp(e, XR_VARJO_QUAD_VIEWS_EXTENSION_NAME) == 0;
        appFoveated = appFoveated || std::strcmp(e, XR_VARJO_FOVEATED_RENDERING_EXTENSION_NAME) == 0;
    }
    XrApiLayerCreateInfo down = *layerInfo;
    down.nextInfo = mine->next;
    XrResult r = XR_ERROR_EXTENSION_NOT_PRESENT;
    bool eyeGaze = false, emulateQuad = false;
    for (const bool withQuad : {true, false}) {
        // Offered by the layer only where the application asked and the configuration lets it.
        if (!withQuad && ((!appQuad && !appFoveated) || !config->quadViews)) break;
        for (const bool withGaze : {true, false}) {
            if (withGaze && appEyeGaze) continue;  // the application's own list has it
            std::vector<const char*> exts;
            for (const char* e : appExts)
                if (withQuad || !isQuadExtension(e)) exts.push_back(e);
            if (withGaze) exts.push_back(XR_EXT_EYE_GAZE_INTERACTION_EXTENSION_NAME);
            XrInstanceCreateInfo ci = *info;
            ci.enabledExtensionCount = uint32_t(exts.size());
            ci.enabledExtensionNames = exts.data();
            r = mine->nextCreateApiLayerInstance(&ci, &down, instance);
            if (r != XR_ERROR_EXTENSION_NOT_PRESENT) {
                eyeGaze = XR_SUCCEEDED(r) && (withGaze || appEyeGaze);
                emulateQuad = XR_SUCCEEDED(r) && !withQuad;
                break;
            }
        }
        if (r != XR_ERROR_EXTENSION_NOT_PRESENT) break;
    }
    if (XR_FAILED(r)) return r;

    std::lock_guard lock(g_mutex);
    InstanceState& st = g_instances[*instance];
    st.config = *config;
    st.eyeGaze = eyeGaze;
    st.appEyeGaze = appEyeGaze;
    st.quadViews = emulateQuad && appQuad;
    st.foveatedRendering = emulateQuad && appQuad && appFoveated;
    Next& n = st.next;
    n.getInstanceProcAddr = mine->nextGetInstanceProcAddr;
    auto gipa = n.getInstanceProcAddr;
    load(gipa, *instance, "xrDestroyInstance", n.destroyInstance);
    load(gipa, *instance, "xrCreateSession", n.createSession);
    load(gipa, *instance, "xrDestroySession", n.destroySession);
    load(gipa, *instance, "xrCreateSwapchain", n.createSwapchain);
    load(gipa, *instance, "xrDestroySwapchain", n.destroySwapchain);
    load(gipa, *instance, "xrEnumerateSwapchainImages", n.enumerateSwapchainImages);
    load(gipa, *instance, "xrEnumerateSwapchainFormats", n.enumerateSwapchainFormats);
    load(gipa, *instance, "xrAcquireSwapchainImage", n.acquireSwapchainImage);
    load(gipa, *instance, "xrWaitSwapchainImage", n.waitSwapchainImage);
    load(gipa, *instance, "xrReleaseSwapchainImage", n.releaseSwapchainImage);
    load(gipa, *instance, "xrEndFrame", n.endFrame);
    load(gipa, *instance, "xrStringToPath", n.stringToPath);
    load(gipa, *instance, "xrCreateActionSet", n.createActionSet);
    load(gipa, *instance, "xrCreateAction", n.createAction);
    load(gipa, *instance, "xrDestroyActionSet", n.destroyActionSet);
    load(gipa, *instance, "xrSuggestInteractionProfileBindings", n.suggestInteractionProfileBindings);
    load(gipa, *instance, "xrAttachSessionActionSets", n.attachSessionActionSets);
    load(gipa, *instance, "xrSyncActions", n.syncActions);
    load(gipa, *instance, "xrGetSystemProperties", n.getSystemProperties);
    load(gipa, *instance, "xrGetCurrentInteractionProfile", n.getCurrentInteractionProfile);
    load(gipa, *instance, "xrPollEvent", n.pollEvent);
    load(gipa, *instance, "xrCreateActionSpace", n.createActionSpace);
    load(gipa, *instance, "xrCreateReferenceSpace", n.createReferenceSpace);
    load(gipa, *instance, "xrLocateSpace", n.locateSpace);
    load(gipa, *instance, "xrDestroySpace", n.destroySpace);
    load(gipa, *instance, "xrEnumerateViewConfigurations", n.enumerateViewConfigurations);
    load(gipa, *instance, "xrGetViewConfigurationProperties", n.getViewConfigurationProperties);
    load(gipa, *instance, "xrEnumerateViewConfigurationViews", n.enumerateViewConfigurationViews);
    load(gipa, *instance, "xrEnumerateEnvironmentBlendModes", n.enumerateEnvironmentBlendModes);
    load(gipa, *instance, "xrBeginSession", n.beginSession);
    load(gipa, *instance, "xrLocateViews", n.locateViews);
    load(gipa, *instance, "xrEnumerateReferenceSpaces", n.enumerateReferenceSpaces);
    if (st.eyeGaze) {
        // The layer's own action set: one pose action bound to the eye gaze.
        XrActionSetCreateInfo asci{XR_TYPE_ACTION_SET_CREATE_INFO};
        std::snprintf(asci.actionSetName, XR_MAX_ACTION_SET_NAME_SIZE, "wrsfov_layer_gaze");
        std::snprintf(asci.localizedActionSetName, XR_MAX_LOCALIZED_ACTION_SET_NAME_SIZE, "wrsfov layer gaze");
        XrActionCreateInfo aci{XR_TYPE_ACTION_CREATE_INFO};
        aci.actionType = XR_ACTION_TYPE_POSE_INPUT;
        std::snprintf(aci.actionName, XR_MAX_ACTION_NAME_SIZE, "gaze");
        std::snprintf(aci.localizedActionName, XR_MAX_LOCALIZED_ACTION_NAME_SIZE, "wrsfov layer gaze");
        if (n.createActionSet(*instance, &asci, &st.gazeSet) != XR_SUCCESS ||
            n.createAction(st.gazeSet, &aci, &st.gazeAction) != XR_SUCCESS ||
            n.stringToPath(*instance, kEyeProfile, &st.eyeProfile) != XR_SUCCESS ||
            n.stringToPath(*instance, kEyePose, &st.eyePose) != XR_SUCCESS ||
            n.stringToPath(*instance, "/user/eyes_ext", &st.eyeUser) != XR_SUCCESS) {
            logLine("eye gaze: the layer's action set could not be made; configured gaze instead");
            st.eyeGaze = false;
        } else {
            XrActionSuggestedBinding b{st.gazeAction, st.eyePose};
            XrInteractionProfileSuggestedBinding s{XR_TYPE_INTERACTION_PROFILE_SUGGESTED_BINDING};
            s.interactionProfile = st.eyeProfile;
            s.countSuggestedBindings = 1;
            s.suggestedBindings = &b;
            if (n.suggestInteractionProfileBindings(*instance, &s) != XR_SUCCESS) st.eyeGaze = false;
        }
        for (const char* u : {"/user/hand/left", "/user/hand/right", "/user/head", "/user/gamepad"}) {
            XrPath p = XR_NULL_PATH;
            if (n.stringToPath(*instance, u, &p) == XR_SUCCESS) st.otherUsers.push_back(p);
        }
    }
    logLine(std::string("on: method ") + std::string(toString(config->compositor.method)) + ", fovea " +
            std::to_string(config->compositor.foveaDeg) + " deg, gaze from " +
            (st.eyeGaze ? "the runtime's eye tracking" : "the configured source") +
            (st.quadViews ? "; quad views offered over the runtime's stereo views" : ""));
    return r;
}

XRAPI_ATTR XrResult XRAPI_CALL layerDestroyInstance(XrInstance instance) {
    PFN_xrDestroyInstance next = nullptr;
    {
        std::lock_guard lock(g_mutex);
        auto it = g_instances.find(instance);
        if (it == g_instances.end()) return XR_ERROR_HANDLE_INVALID;
        next = it->second.next.destroyInstance;
        // Sessions the application did not destroy go with the instance (the runtime destroys its
        // side, the layer's swapchain and space included): free the layer's device objects first.
        for (auto s = g_sessions.begin(); s != g_sessions.end();) {
            if (s->second.instance != instance) {
                ++s;
                continue;
            }
            for (auto sc = g_swapchains.begin(); sc != g_swapchains.end();)
                sc = sc->second.session == s->first ? g_swapchains.erase(sc) : std::next(sc);
            for (auto sp = g_combinedEye.begin(); sp != g_combinedEye.end();)
                sp = sp->second.session == s->first ? g_combinedEye.erase(sp) : std::next(sp);
            s = g_sessions.erase(s);  // compositor before context (member order)
        }
        for (auto a = g_actionSets.begin(); a != g_actionSets.end();)
            a = a->second == instance ? g_actionSets.erase(a) : std::next(a);
        g_instances.erase(it);
    }
    return next(instance);
}

// The application's suggestions for the eye-gaze profile replace the layer's: merge ours back in.
XRAPI_ATTR XrResult XRAPI_CALL layerSuggestInteractionProfileBindings(
    XrInstance instance, const XrInteractionProfileSuggestedBinding* suggested) {
    std::lock_guard lock(g_mutex);
    auto it = g_instances.find(instance);
    if (it == g_instances.end()) return XR_ERROR_HANDLE_INVALID;
    InstanceState& st = it->second;
    if (!st.eyeGaze || !suggested || suggested->interactionProfile != st.eyeProfile || !suggested->suggestedBindings)
        return st.next.suggestInteractionProfileBindings(instance, suggested);
    // The profile of an extension the application did not enable is not one it may use.
    if (!st.appEyeGaze) return XR_ERROR_PATH_UNSUPPORTED;
    std::vector<XrActionSuggestedBinding> b(suggested->suggestedBindings,
                                            suggested->suggestedBindings + suggested->countSuggestedBindings);
    b.push_back({st.gazeAction, st.eyePose});
    XrInteractionProfileSuggestedBinding s = *suggested;
    s.countSuggestedBindings = uint32_t(b.size());
    s.suggestedBindings = b.data();
    XrResult r = st.next.suggestInteractionProfileBindings(instance, &s);
    if (XR_SUCCEEDED(r)) st.appSuggestedEyes = true;
    return r;
}

// Eye-gaze interaction the layer enabled for itself is not the application's: the system does not
// offer it to an application that did not enable it (and the runtime below, asked with it enabled,
// would say it does).
XRAPI_ATTR XrResult XRAPI_CALL layerGetSystemProperties(XrInstance instance, XrSystemId systemId,
                                                        XrSystemProperties* properties) {
    std::lock_guard lock(g_mutex);
    auto it = g_instances.find(instance);
    if (it == g_instances.end()) return XR_ERROR_HANDLE_INVALID;
    const InstanceState& st = it->second;
    XrResult r = st.next.getSystemProperties(instance, systemId, properties);
    if (XR_SUCCEEDED(r) && st.eyeGaze && !st.appEyeGaze && properties)
        for (auto* n = static_cast<XrBaseOutStructure*>(properties->next); n; n = n->next)
            if (n->type == XR_TYPE_SYSTEM_EYE_GAZE_INTERACTION_PROPERTIES_EXT)
                reinterpret_cast<XrSystemEyeGazeInteractionPropertiesEXT*>(n)->supportsEyeGazeInteraction = XR_FALSE;
    // Foveated rendering the layer offers: there is a rendering gaze where the runtime has eye tracking
    // or a source is configured.
    if (XR_SUCCEEDED(r) && st.foveatedRendering && properties)
        for (auto* n = static_cast<XrBaseOutStructure*>(properties->next); n; n = n->next)
            if (n->type == XR_TYPE_SYSTEM_FOVEATED_RENDERING_PROPERTIES_VARJO)
                reinterpret_cast<XrSystemFoveatedRenderingPropertiesVARJO*>(n)->supportsFoveatedRendering =
                    st.eyeGaze || st.config.gaze != xr::GazeKind::None ? XR_TRUE : XR_FALSE;
    return r;
}

// /user/eyes_ext is a top-level user path only with the extension enabled.
XRAPI_ATTR XrResult XRAPI_CALL layerCreateActionSet(XrInstance instance, const XrActionSetCreateInfo* info,
                                                    XrActionSet* actionSet) {
    std::lock_guard lock(g_mutex);
    auto it = g_instances.find(instance);
    if (it == g_instances.end()) return XR_ERROR_HANDLE_INVALID;
    XrResult r = it->second.next.createActionSet(instance, info, actionSet);
    if (XR_SUCCEEDED(r)) g_actionSets[*actionSet] = instance;
    return r;
}

XRAPI_ATTR XrResult XRAPI_CALL layerDestroyActionSet(XrActionSet actionSet) {
    std::lock_guard lock(g_mutex);
    auto it = g_actionSets.find(actionSet);
    if (it == g_actionSets.end()) return XR_ERROR_HANDLE_INVALID;
    const XrInstance instance = it->second;
    g_actionSets.erase(it);
    return g_instances.at(instance).next.destroyActionSet(actionSet);
}

XRAPI_ATTR XrResult XRAPI_CALL layerCreateAction(XrActionSet actionSet, const XrActionCreateInfo* info,
                                                 XrAction* action) {
    std::lock_guard lock(g_mutex);
    auto it = g_actionSets.find(actionSet);
    if (it == g_actionSets.end()) return XR_ERROR_HANDLE_INVALID;
    const InstanceState& st = g_instances.at(it->second);
    if (st.eyeGaze && !st.appEyeGaze && info && info->subactionPaths)
        for (uint32_t i = 0; i < info->countSubactionPaths; ++i)
            if (info->subactionPaths[i] == st.eyeUser) return XR_ERROR_PATH_UNSUPPORTED;
    return st.next.createAction(actionSet, info, action);
}

// /user/eyes_ext has no profile the application may see: unsupported where only the layer enabled the
// extension, none current where the application enabled it but bound nothing of its own to it.
XRAPI_ATTR XrResult XRAPI_CALL layerGetCurrentInteractionProfile(XrSession session, XrPath topLevelUserPath,
                                                                 XrInteractionProfileState* state) {
    std::lock_guard lock(g_mutex);
    auto it = g_sessions.find(session);
    if (it == g_sessions.end()) return XR_ERROR_HANDLE_INVALID;
    const InstanceState& st = g_instances.at(it->second.instance);
    XrResult r = st.next.getCurrentInteractionProfile(session, topLevelUserPath, state);
    if (XR_SUCCEEDED(r) && st.hideEyes() && topLevelUserPath == st.eyeUser) {
        if (!st.appEyeGaze) return XR_ERROR_PATH_UNSUPPORTED;
        state->interactionProfile = XR_NULL_PATH;  // enabled, but bound to nothing of the application's
    }
    return r;
}

// A profile change only the layer's own eye-gaze binding caused is not the application's business:
// delivered only when a profile the application can see (hands, head, gamepad) did change.
XRAPI_ATTR XrResult XRAPI_CALL layerPollEvent(XrInstance instance, XrEventDataBuffer* event) {
    std::lock_guard lock(g_mutex);
    auto it = g_instances.find(instance);
    if (it == g_instances.end()) return XR_ERROR_HANDLE_INVALID;
    const InstanceState& st = it->second;
    const void* next = event ? event->next : nullptr;
    for (;;) {
        XrResult r = st.next.pollEvent(instance, event);
        if (r != XR_SUCCESS || !st.hideEyes() || event->type != XR_TYPE_EVENT_DATA_INTERACTION_PROFILE_CHANGED)
            return r;
        auto s = g_sessions.find(reinterpret_cast<const XrEventDataInteractionProfileChanged*>(event)->session);
        if (s == g_sessions.end() || !s->second.gazeAttached) return r;
        std::vector<XrPath> now;
        for (XrPath user : st.otherUsers) {
            XrInteractionProfileState ps{XR_TYPE_INTERACTION_PROFILE_STATE};
            now.push_back(st.next.getCurrentInteractionProfile(s->first, user, &ps) == XR_SUCCESS
                              ? ps.interactionProfile
                              : XR_NULL_PATH);
        }
        if (s->second.profilesSeen.empty()) s->second.profilesSeen.assign(now.size(), XR_NULL_PATH);
        if (now != s->second.profilesSeen) {
            s->second.profilesSeen = now;
            return r;
        }
        // Only the eyes changed: dropped; the next event, if any, is the application's answer.
        event->type = XR_TYPE_EVENT_DATA_BUFFER;
        event->next = next;
    }
}

// ---- Session ----------------------------------------------------------------------------------

XRAPI_ATTR XrResult XRAPI_CALL layerCreateSession(XrInstance instance, const XrSessionCreateInfo* info,
                                                  XrSession* session) {
    std::lock_guard lock(g_mutex);
    auto it = g_instances.find(instance);
    if (it == g_instances.end()) return XR_ERROR_HANDLE_INVALID;
    InstanceState& st = it->second;
    XrResult r = st.next.createSession(instance, info, session);
    if (XR_FAILED(r)) return r;
    SessionState& s = g_sessions[*session];
    s.instance = instance;
    s.system = info ? info->systemId : XR_NULL_SYSTEM_ID;
    auto* binding = info ? reinterpret_cast<const XrGraphicsBindingVulkanKHR*>(
                               findNext(info->next, XR_TYPE_GRAPHICS_BINDING_VULKAN_KHR))
                         : nullptr;
    if (!binding) {
        disable(s, "not a Vulkan session");
        return r;
    }
    auto ctx = vk::Context::adopt({binding->instance, binding->physicalDevice, binding->device,
                                   binding->queueFamilyIndex, binding->queueIndex});
    if (!ctx) {
        disable(s, ctx.error().message);
        return r;
    }
    s.ctx = std::move(*ctx);
    // Faults for the layer's own device work only (tests: the layer must disable itself, the
    // application must not notice): WRSFOV_LAYER_FAULT, as WRSFOV_FAULT ("alloc:N", "lost:N").
    if (const char* spec = std::getenv("WRSFOV_LAYER_FAULT"); spec && *spec) {
        auto faults = vk::FaultInjection::parse(spec);
        if (!faults) {
            disable(s, "WRSFOV_LAYER_FAULT: " + faults.error().message);
            return r;
        }
        s.ctx->injectFaults(*faults);
    }
    auto comp = Compositor::create(*s.ctx, st.config.compositor);
    if (!comp) {
        disable(s, "compositor: " + comp.error().message);
        return r;
    }
    s.comp = std::move(*comp);
    if (st.eyeGaze) {
        XrActionSpaceCreateInfo asi{XR_TYPE_ACTION_SPACE_CREATE_INFO};
        asi.action = st.gazeAction;
        asi.poseInActionSpace.orientation.w = 1.0f;
        if (st.next.createActionSpace(*session, &asi, &s.gazeSpace) != XR_SUCCESS) s.gazeSpace = XR_NULL_HANDLE;
    }
    // The configured source: used when the runtime has no eye tracking, or the application attaches no
    // action sets (the layer's own goes in with the application's).
    if (auto src = xr::openGazeSource(st.config)) s.source = std::move(*src);
    else logLine(src.error().message + "; the compositor's fallback gaze");
    logLine("session on " + s.ctx->deviceName());
    return r;
}

XRAPI_ATTR XrResult XRAPI_CALL layerDestroySession(XrSession session) {
    std::lock_guard lock(g_mutex);
    auto it = g_sessions.find(session);
    if (it == g_sessions.end()) return XR_ERROR_HANDLE_INVALID;
    SessionState& s = it->second;
    const Next& n = g_instances.at(s.instance).next;
    settle(s);
    // On a CPU device the compositor times a frame by the host, from submission to the wait for it
    // (PassTimes::hostTimed), which here comes a frame later: an upper bound.
    char gpu[64] = "-", host[64] = "-";
    if (s.gpuFrames) std::snprintf(gpu, sizeof gpu, "%.2f ms", s.gpuMs / double(s.gpuFrames));
    if (s.processed) std::snprintf(host, sizeof host, "%.2f ms", s.endFrameMs / double(s.processed));
    // Frames ended without a projection layer (an application that is not visible yet submits none)
    // have nothing to foveate: they are counted apart.
    const uint64_t bare = s.frames - s.projected;
    logLine("session ended: " + std::to_string(s.processed) + " of " + std::to_string(s.projected) +
            " frames foveated" + (bare ? " (" + std::to_string(bare) + " more ended without a projection layer)" : "") +
            ", passes " + gpu + " a frame on average" +
            (s.gpuFrames && s.ctx->isCpuDevice() ? " (host-timed from submission to the wait: an upper bound)" : "") + " (in xrEndFrame " + host +
            "), gaze fallback in " + std::to_string(s.fallbackFrames) +
            (s.disabled ? " (disabled: " + s.why + ")" : ""));
    if (s.out) n.destroySwapchain(s.out);
    if (s.gazeSpace) n.destroySpace(s.gazeSpace);
    for (auto sc = g_swapchains.begin(); sc != g_swapchains.end();)
        sc = sc->second.session == session ? g_swapchains.erase(sc) : std::next(sc);
    for (auto sp = g_combinedEye.begin(); sp != g_combinedEye.end();)
        sp = sp->second.session == session ? g_combinedEye.erase(sp) : std::next(sp);
    s.comp.reset();
    if (s.copyCb) s.ctx->freeCommandBuffer(s.copyCb);
    s.copied.reset();
    s.composited.reset();
    s.ctx.reset();
    g_sessions.erase(it);
    return n.destroySession(session);
}

XRAPI_ATTR XrResult XRAPI_CALL layerAttachSessionActionSets(XrSession session, const XrSessionActionSetsAttachInfo* info) {
    std::lock_guard lock(g_mutex);
    auto it = g_sessions.find(session);
    if (it == g_sessions.end()) return XR_ERROR_HANDLE_INVALID;
    const InstanceState& st = g_instances.at(it->second.instance);
    // An attach the runtime must refuse (no sets, no array, a wrong type) goes down as it is: adding the
    // layer's set would make it valid.
    if (!st.eyeGaze || !info || info->type != XR_TYPE_SESSION_ACTION_SETS_ATTACH_INFO || info->countActionSets == 0 ||
        !info->actionSets)
        return st.next.attachSessionActionSets(session, info);
    std::vector<XrActionSet> sets(info->actionSets, info->actionSets + info->countActionSets);
    sets.push_back(st.gazeSet);
    XrSessionActionSetsAttachInfo a = *info;
    a.countActionSets = uint32_t(sets.size());
    a.actionSets = sets.data();
    XrResult r = st.next.attachSessionActionSets(session, &a);
    it->second.gazeAttached = XR_SUCCEEDED(r);
    return r;
}

XRAPI_ATTR XrResult XRAPI_CALL layerSyncActions(XrSession session, const XrActionsSyncInfo* info) {
    std::lock_guard lock(g_mutex);
    auto it = g_sessions.find(session);
    if (it == g_sessions.end()) return XR_ERROR_HANDLE_INVALID;
    const InstanceState& st = g_instances.at(it->second.instance);
    if (!it->second.gazeAttached || !info) return st.next.syncActions(session, info);
    if (!st.appEyeGaze && info->activeActionSets)
        for (uint32_t i = 0; i < info->countActiveActionSets; ++i)
            if (info->activeActionSets[i].subactionPath == st.eyeUser) return XR_ERROR_PATH_UNSUPPORTED;
    std::vector<XrActiveActionSet> sets(info->activeActionSets, info->activeActionSets + info->countActiveActionSets);
    sets.push_back({st.gazeSet, XR_NULL_PATH});
    XrActionsSyncInfo s = *info;
    s.countActiveActionSets = uint32_t(sets.size());
    s.activeActionSets = sets.data();
    return st.next.syncActions(session, &s);
}

// ---- Swapchains -------------------------------------------------------------------------------

const Next* nextOfSession(XrSession session) {
    auto it = g_sessions.find(session);
    return it == g_sessions.end() ? nullptr : &g_instances.at(it->second.instance).next;
}

XRAPI_ATTR XrResult XRAPI_CALL layerCreateSwapchain(XrSession session, const XrSwapchainCreateInfo* info,
                                                    XrSwapchain* swapchain) {
    std::lock_guard lock(g_mutex);
    const Next* n = nextOfSession(session);
    if (!n) return XR_ERROR_HANDLE_INVALID;
    if (!info) return n->createSwapchain(session, info, swapchain);
    // The compositor samples the images, and does nothing else with them: SAMPLED added, on a copy; the
    // application's structure stays as it gave it. No MUTABLE_FORMAT: a runtime may ignore it (Monado
    // 21 does), so an sRGB image is read through a view of its own format (the device decodes,
    // shaders/wrs_input.h) and never reinterpreted.
    XrSwapchainCreateInfo ci = *info;
    const auto fmt = colorFormat(info->format);
    if (fmt) ci.usageFlags |= XR_SWAPCHAIN_USAGE_SAMPLED_BIT;
    XrResult r = n->createSwapchain(session, &ci, swapchain);
    if (XR_FAILED(r) && fmt && ci.usageFlags != info->usageFlags) {
        // The runtime refused the added usage: the images are made with the application's usage alone,
        // and the layer reads them only if that includes SAMPLED (layerEnumerateSwapchainImages).
        ci = *info;
        r = n->createSwapchain(session, &ci, swapchain);
        if (XR_SUCCEEDED(r))
            logLine("swapchain made without the SAMPLED usage the layer asked for (the runtime refused it): "
                    "frames that use it pass through");
    }
    if (XR_FAILED(r)) return r;
    SwapchainState& s = g_swapchains[*swapchain];
    s.session = session;
    s.info = ci;  // what the images were made with
    return r;
}

XRAPI_ATTR XrResult XRAPI_CALL layerDestroySwapchain(XrSwapchain swapchain) {
    std::lock_guard lock(g_mutex);
    auto it = g_swapchains.find(swapchain);
    if (it == g_swapchains.end()) return XR_ERROR_HANDLE_INVALID;
    const Next* n = nextOfSession(it->second.session);
    // The compositor's last frame may still read it (the application waited for its own work only).
    if (it->second.imported) waitComposited(g_sessions.at(it->second.session));
    g_swapchains.erase(it);
    return n->destroySwapchain(swapchain);
}

XRAPI_ATTR XrResult XRAPI_CALL layerEnumerateSwapchainImages(XrSwapchain swapchain, uint32_t capacity,
                                                             uint32_t* countOutput, XrSwapchainImageBaseHeader* images) {
    std::lock_guard lock(g_mutex);
    auto it = g_swapchains.find(swapchain);
    if (it == g_swapchains.end()) return XR_ERROR_HANDLE_INVALID;
    SwapchainState& sc = it->second;
    XrResult r = nextOfSession(sc.session)->enumerateSwapchainImages(swapchain, capacity, countOutput, images);
    if (r != XR_SUCCESS || capacity == 0 || !images || images->type != XR_TYPE_SWAPCHAIN_IMAGE_VULKAN_KHR ||
        !sc.images.empty())
        return r;
    auto* vkImages = reinterpret_cast<XrSwapchainImageVulkanKHR*>(images);
    for (uint32_t i = 0; i < *countOutput; ++i) sc.images.push_back(vkImages[i].image);
    SessionState& s = g_sessions.at(sc.session);
    const auto fmt = colorFormat(sc.info.format);
    // An sRGB swapchain with UNORDERED_ACCESS usage is not read: its images carry STORAGE usage, which an
    // sRGB view may not inherit, and narrowing a view's usage needs Vulkan 1.1, which the application's
    // device may not have enabled.
    const bool srgbStorage = fmt && *fmt == layers::Format::RGBA8_SRGB &&
                             (sc.info.usageFlags & XR_SWAPCHAIN_USAGE_UNORDERED_ACCESS_BIT);
    const bool usable = fmt && (sc.info.usageFlags & XR_SWAPCHAIN_USAGE_SAMPLED_BIT) && !srgbStorage &&
                        sc.info.faceCount == 1 && sc.info.mipCount == 1 && sc.info.sampleCount == 1 &&
                        sc.images.size() <= 8;
    if (s.comp && usable) {
        layers::SwapchainCreateInfo info;
        info.format = *fmt;
        info.usage = *fmt == layers::Format::D32F ? layers::Usage::Depth : layers::Usage::Color;
        info.anyUse = true;
        info.width = sc.info.width;
        info.height = sc.info.height;
        info.arraySize = sc.info.arraySize;
        info.imageCount = uint32_t(sc.images.size());
        SwapchainImageOptions o;
        o.restingLayout = *fmt == layers::Format::D32F ? VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL
                                                       : VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL;
        auto imp = s.comp->importSwapchain(info, sc.images, o);
        if (imp) sc.imported = std::move(*imp);
        else logLine("swapchain not used: " + imp.error().message);
    }
    return r;
}

XRAPI_ATTR XrResult XRAPI_CALL layerAcquireSwapchainImage(XrSwapchain swapchain, const XrSwapchainImageAcquireInfo* info,
                                                          uint32_t* index) {
    std::lock_guard lock(g_mutex);
    auto it = g_swapchains.find(swapchain);
    if (it == g_swapchains.end()) return XR_ERROR_HANDLE_INVALID;
    XrResult r = nextOfSession(it->second.session)->acquireSwapchainImage(swapchain, info, index);
    if (XR_SUCCEEDED(r) && index) it->second.acquired.push_back(*index);
    return r;
}

// The runtime below knows only its own reads of the image; the compositor's reads of the last frame
// may still be running (the layer does not wait for them in xrEndFrame), and the application may
// render on a queue other than the one the compositor uses. Waiting here keeps the promise of
// xrWaitSwapchainImage: the image is free to write. By then the frame has normally long finished.
XRAPI_ATTR XrResult XRAPI_CALL layerWaitSwapchainImage(XrSwapchain swapchain, const XrSwapchainImageWaitInfo* info) {
    std::lock_guard lock(g_mutex);
    auto it = g_swapchains.find(swapchain);
    if (it == g_swapchains.end()) return XR_ERROR_HANDLE_INVALID;
    XrResult r = nextOfSession(it->second.session)->waitSwapchainImage(swapchain, info);
    if (r == XR_SUCCESS && it->second.imported) waitComposited(g_sessions.at(it->second.session));
    return r;
}

XRAPI_ATTR XrResult XRAPI_CALL layerReleaseSwapchainImage(XrSwapchain swapchain, const XrSwapchainImageReleaseInfo* info) {
    std::lock_guard lock(g_mutex);
    auto it = g_swapchains.find(swapchain);
    if (it == g_swapchains.end()) return XR_ERROR_HANDLE_INVALID;
    SwapchainState& sc = it->second;
    XrResult r = nextOfSession(sc.session)->releaseSwapchainImage(swapchain, info);
    if (XR_SUCCEEDED(r) && !sc.acquired.empty()) {
        if (sc.imported) sc.imported->releasedElsewhere(sc.acquired.front());
        sc.acquired.erase(sc.acquired.begin());
    }
    return r;
}

// ---- Frame end --------------------------------------------------------------------------------

/// The layer's output swapchain of w x h, two layers; made (again) when the size changes.
bool ensureOutput(SessionState& s, const Next& n, XrSession session, uint32_t w, uint32_t h) {
    if (s.out && s.outWidth == w && s.outHeight == h) return true;
    waitCopied(s);
    if (s.out) n.destroySwapchain(s.out);
    s.out = XR_NULL_HANDLE;
    s.outImages.clear();
    uint32_t count = 0;
    n.enumerateSwapchainFormats(session, 0, &count, nullptr);
    std::vector<int64_t> formats(count);
    n.enumerateSwapchainFormats(session, count, &count, formats.data());
    // The output holds sRGB-encoded bytes: an sRGB swapchain shows them as meant.
    s.outFormat = 0;
    for (int64_t f : {int64_t(VK_FORMAT_R8G8B8A8_SRGB), int64_t(VK_FORMAT_R8G8B8A8_UNORM)})
        if (!s.outFormat && std::find(formats.begin(), formats.end(), f) != formats.end()) s.outFormat = f;
    if (!s.outFormat) return false;
    XrSwapchainCreateInfo ci{XR_TYPE_SWAPCHAIN_CREATE_INFO};
    ci.usageFlags = XR_SWAPCHAIN_USAGE_COLOR_ATTACHMENT_BIT | XR_SWAPCHAIN_USAGE_TRANSFER_DST_BIT;
    ci.format = s.outFormat;
    ci.sampleCount = 1;
    ci.width = w;
    ci.height = h;
    ci.faceCount = 1;
    ci.arraySize = 2;
    ci.mipCount = 1;
    if (n.createSwapchain(session, &ci, &s.out) != XR_SUCCESS) return false;
    n.enumerateSwapchainImages(s.out, 0, &count, nullptr);
    std::vector<XrSwapchainImageVulkanKHR> imgs(count, {XR_TYPE_SWAPCHAIN_IMAGE_VULKAN_KHR});
    if (n.enumerateSwapchainImages(s.out, count, &count, reinterpret_cast<XrSwapchainImageBaseHeader*>(imgs.data())) !=
        XR_SUCCESS)
        return false;
    for (auto& i : imgs) s.outImages.push_back(i.image);
    s.outWidth = w;
    s.outHeight = h;
    return true;
}

/// Per-eye gaze for views at `poses` in `space`: the runtime's eye gaze located there (the direction
/// of the cyclopean gaze in each eye's space), else the configured source; invalid gives the
/// compositor's fallback.
std::array<layers::EyeGaze, 2> eyeGaze(SessionState& s, const Next& n, XrSpace space, const XrPosef (&poses)[2],
                                       XrTime time) {
    std::array<layers::EyeGaze, 2> g{};
    if (s.gazeSpace && s.gazeAttached) {
        XrSpaceLocation loc{XR_TYPE_SPACE_LOCATION};
        if (n.locateSpace(s.gazeSpace, space, time, &loc) == XR_SUCCESS &&
            (loc.locationFlags & XR_SPACE_LOCATION_ORIENTATION_VALID_BIT)) {
            const XrQuaternionf q = loc.pose.orientation;
            const glm::vec3 dir = glm::quat(q.w, q.x, q.y, q.z) * glm::vec3(0, 0, -1);  // in the layer's space
            for (int e = 0; e < 2; ++e) {
                const XrQuaternionf v = poses[e].orientation;
                g[e].dir = glm::conjugate(glm::quat(v.w, v.x, v.y, v.z)) * dir;
                g[e].valid = true;
                g[e].confidence = 1.0f;
            }
        }
        return g;
    }
    if (!s.epoch) s.epoch = time;
    return gaze::frame_gaze(s.source.get(), double(time - s.epoch) * 1e-9);
}

std::array<layers::EyeGaze, 2> eyeGaze(SessionState& s, const Next& n, const XrCompositionLayerProjection& proj,
                                       XrTime time) {
    const XrPosef poses[2] = {proj.views[0].pose, proj.views[1].pose};
    return eyeGaze(s, n, proj.space, poses, time);
}

// ---- Quad views on a runtime without them ------------------------------------------------------
// XR_VARJO_quad_views and XR_VARJO_foveated_rendering, where the application enabled them and the
// runtime refused them (InstanceState::quadViews): the quad configuration over the runtime's stereo
// one, its four views from the runtime's two and the gaze, the combined-eye space from a VIEW space
// and the gaze, and at xrEndFrame the four views composed into the layer's stereo swapchain.

constexpr XrViewConfigurationType kQuad = XR_VIEW_CONFIGURATION_TYPE_PRIMARY_QUAD_VARJO;
constexpr XrViewConfigurationType kStereo = XR_VIEW_CONFIGURATION_TYPE_PRIMARY_STEREO;

/// The runtime's stereo views (their recommended size is the size the four views are composed at).
XrResult stereoViews(const Next& n, XrInstance instance, XrSystemId system, XrViewConfigurationView (&v)[2]) {
    v[0] = v[1] = {XR_TYPE_VIEW_CONFIGURATION_VIEW};
    uint32_t count = 0;
    return n.enumerateViewConfigurationViews(instance, system, kStereo, 2, &count, v);
}

/// The quad views' recommended sizes over stereo views of `size`: the wide views at 1/2.5 of their
/// density, the inset of inset_deg across at it. The runtime's field of view is known only once a
/// session locates its views: the density is taken over 90 degrees.
xr::QuadViewSizes quadSizes(const RuntimeConfig& config, uint32_t width, uint32_t height) {
    RuntimeConfig c = config;
    c.width = width;
    c.height = height;
    c.fov[0] = c.fov[1] = layers::Fov{};  // +-45 degrees
    return xr::quadViewSizes(c);
}

XRAPI_ATTR XrResult XRAPI_CALL layerEnumerateViewConfigurations(XrInstance instance, XrSystemId system,
                                                                uint32_t capacity, uint32_t* countOutput,
                                                                XrViewConfigurationType* types) {
    std::lock_guard lock(g_mutex);
    auto it = g_instances.find(instance);
    if (it == g_instances.end()) return XR_ERROR_HANDLE_INVALID;
    const InstanceState& st = it->second;
    if (!st.quadViews) return st.next.enumerateViewConfigurations(instance, system, capacity, countOutput, types);
    uint32_t n = 0;
    if (XrResult r = st.next.enumerateViewConfigurations(instance, system, 0, &n, nullptr); XR_FAILED(r)) return r;
    std::vector<XrViewConfigurationType> all(n);
    if (XrResult r = st.next.enumerateViewConfigurations(instance, system, n, &n, all.data()); XR_FAILED(r)) return r;
    all.insert(all.begin(), kQuad);  // first: the application asked for quad views
    if (!countOutput) return XR_ERROR_VALIDATION_FAILURE;
    *countOutput = uint32_t(all.size());
    if (capacity == 0) return XR_SUCCESS;
    if (capacity < all.size()) return XR_ERROR_SIZE_INSUFFICIENT;
    if (!types) return XR_ERROR_VALIDATION_FAILURE;
    std::copy(all.begin(), all.end(), types);
    return XR_SUCCESS;
}

XRAPI_ATTR XrResult XRAPI_CALL layerGetViewConfigurationProperties(XrInstance instance, XrSystemId system,
                                                                   XrViewConfigurationType type,
                                                                   XrViewConfigurationProperties* properties) {
    std::lock_guard lock(g_mutex);
    auto it = g_instances.find(instance);
    if (it == g_instances.end()) return XR_ERROR_HANDLE_INVALID;
    const InstanceState& st = it->second;
    if (!st.quadViews || type != kQuad)
        return st.next.getViewConfigurationProperties(instance, system, type, properties);
    XrResult r = st.next.getViewConfigurationProperties(instance, system, kStereo, properties);
    if (XR_SUCCEEDED(r)) properties->viewConfigurationType = kQuad;
    return r;
}

XRAPI_ATTR XrResult XRAPI_CALL layerEnumerateViewConfigurationViews(XrInstance instance, XrSystemId system,
                                                                    XrViewConfigurationType type, uint32_t capacity,
                                                                    uint32_t* countOutput,
                                                                    XrViewConfigurationView* views) {
    std::lock_guard lock(g_mutex);
    auto it = g_instances.find(instance);
    if (it == g_instances.end()) return XR_ERROR_HANDLE_INVALID;
    const InstanceState& st = it->second;
    if (!st.quadViews || type != kQuad)
        return st.next.enumerateViewConfigurationViews(instance, system, type, capacity, countOutput, views);
    XrViewConfigurationView sv[2];
    if (XrResult r = stereoViews(st.next, instance, system, sv); XR_FAILED(r)) return r;
    if (!countOutput) return XR_ERROR_VALIDATION_FAILURE;
    *countOutput = 4;
    if (capacity == 0) return XR_SUCCESS;
    if (capacity < 4) return XR_ERROR_SIZE_INSUFFICIENT;
    if (!views) return XR_ERROR_VALIDATION_FAILURE;
    for (uint32_t i = 0; i < 4; ++i)
        if (views[i].type != XR_TYPE_VIEW_CONFIGURATION_VIEW) return XR_ERROR_VALIDATION_FAILURE;
    const xr::QuadViewSizes q = quadSizes(st.config, sv[0].recommendedImageRectWidth, sv[0].recommendedImageRectHeight);
    for (uint32_t i = 0; i < 4; ++i) {
        const glm::uvec2 size = i < 2 ? q.wide : q.inset;
        void* next = views[i].next;  // XrFoveatedViewConfigurationViewVARJO: the same size either way
        views[i] = sv[i % 2];
        views[i].next = next;
        views[i].recommendedImageRectWidth = std::min(size.x, sv[i % 2].maxImageRectWidth);
        views[i].recommendedImageRectHeight = std::min(size.y, sv[i % 2].maxImageRectHeight);
    }
    return XR_SUCCESS;
}

XRAPI_ATTR XrResult XRAPI_CALL layerEnumerateEnvironmentBlendModes(XrInstance instance, XrSystemId system,
                                                                   XrViewConfigurationType type, uint32_t capacity,
                                                                   uint32_t* countOutput,
                                                                   XrEnvironmentBlendMode* modes) {
    std::lock_guard lock(g_mutex);
    auto it = g_instances.find(instance);
    if (it == g_instances.end()) return XR_ERROR_HANDLE_INVALID;
    const InstanceState& st = it->second;
    if (st.quadViews && type == kQuad) type = kStereo;
    return st.next.enumerateEnvironmentBlendModes(instance, system, type, capacity, countOutput, modes);
}

XRAPI_ATTR XrResult XRAPI_CALL layerBeginSession(XrSession session, const XrSessionBeginInfo* info) {
    std::lock_guard lock(g_mutex);
    auto it = g_sessions.find(session);
    if (it == g_sessions.end()) return XR_ERROR_HANDLE_INVALID;
    SessionState& s = it->second;
    const InstanceState& st = g_instances.at(s.instance);
    if (!st.quadViews || !info || info->type != XR_TYPE_SESSION_BEGIN_INFO ||
        info->primaryViewConfigurationType != kQuad)
        return st.next.beginSession(session, info);
    XrViewConfigurationView sv[2];
    if (XrResult r = stereoViews(st.next, s.instance, s.system, sv); XR_FAILED(r)) return r;
    XrSessionBeginInfo b = *info;
    b.primaryViewConfigurationType = kStereo;
    XrResult r = st.next.beginSession(session, &b);
    if (XR_SUCCEEDED(r)) {
        s.quad = true;
        s.displayWidth = sv[0].recommendedImageRectWidth;
        s.displayHeight = sv[0].recommendedImageRectHeight;
    }
    return r;
}

XRAPI_ATTR XrResult XRAPI_CALL layerLocateViews(XrSession session, const XrViewLocateInfo* info, XrViewState* viewState,
                                                uint32_t capacity, uint32_t* countOutput, XrView* views) {
    std::lock_guard lock(g_mutex);
    auto it = g_sessions.find(session);
    if (it == g_sessions.end()) return XR_ERROR_HANDLE_INVALID;
    SessionState& s = it->second;
    const InstanceState& st = g_instances.at(s.instance);
    if (!st.quadViews || !info || info->type != XR_TYPE_VIEW_LOCATE_INFO || info->viewConfigurationType != kQuad)
        return st.next.locateViews(session, info, viewState, capacity, countOutput, views);
    // The runtime's stereo views; the foveated-rendering request is the layer's, not the runtime's.
    XrViewLocateInfo li = *info;
    li.next = nullptr;
    li.viewConfigurationType = kStereo;
    if (!countOutput || !viewState || viewState->type != XR_TYPE_VIEW_STATE) return XR_ERROR_VALIDATION_FAILURE;
    uint32_t n = 0;
    XrView sv[2] = {{XR_TYPE_VIEW}, {XR_TYPE_VIEW}};
    if (capacity == 0) {
        // The count alone. The stereo views are located all the same, into the layer's own views and
        // view state, so that the call is checked below as it would be (session, space, time); never as a
        // count query with no views and the application's view state: a layer below may read views
        // through that state's flags (the Khronos CTS's conformance layer does, and crashed on it).
        XrViewState vs{XR_TYPE_VIEW_STATE};
        if (XrResult r = st.next.locateViews(session, &li, &vs, 2, &n, sv); XR_FAILED(r)) return r;
        *countOutput = 4;
        return XR_SUCCESS;
    }
    *countOutput = 4;
    if (capacity < 4) return XR_ERROR_SIZE_INSUFFICIENT;
    if (!views) return XR_ERROR_VALIDATION_FAILURE;
    for (uint32_t i = 0; i < 4; ++i)
        if (views[i].type != XR_TYPE_VIEW) return XR_ERROR_VALIDATION_FAILURE;
    if (XrResult r = st.next.locateViews(session, &li, viewState, 2, &n, sv); XR_FAILED(r)) return r;
    auto* fr = reinterpret_cast<const XrViewLocateFoveatedRenderingVARJO*>(
        findNext(info->next, XR_TYPE_VIEW_LOCATE_FOVEATED_RENDERING_VARJO));
    std::array<layers::EyeGaze, 2> gaze{};
    if (st.foveatedRendering && fr && fr->foveatedRenderingActive) {
        const XrPosef poses[2] = {sv[0].pose, sv[1].pose};
        gaze = eyeGaze(s, st.next, info->space, poses, info->displayTime);
    }
    for (uint32_t i = 0; i < 4; ++i) {
        const XrView& v = sv[i % 2];
        views[i].pose = v.pose;  // an inset at its eye's pose
        views[i].fov = v.fov;
        if (i < 2) continue;
        std::optional<glm::vec3> dir;
        if (gaze[i - 2].valid) dir = gaze[i - 2].dir;
        const layers::Fov f =
            xr::insetFov({v.fov.angleLeft, v.fov.angleRight, v.fov.angleUp, v.fov.angleDown}, st.config.insetDeg, dir);
        views[i].fov = {f.angleLeft, f.angleRight, f.angleUp, f.angleDown};
    }
    return XR_SUCCESS;
}

XRAPI_ATTR XrResult XRAPI_CALL layerEnumerateReferenceSpaces(XrSession session, uint32_t capacity,
                                                             uint32_t* countOutput, XrReferenceSpaceType* spaces) {
    std::lock_guard lock(g_mutex);
    auto it = g_sessions.find(session);
    if (it == g_sessions.end()) return XR_ERROR_HANDLE_INVALID;
    const InstanceState& st = g_instances.at(it->second.instance);
    if (!st.foveatedRendering) return st.next.enumerateReferenceSpaces(session, capacity, countOutput, spaces);
    uint32_t n = 0;
    if (XrResult r = st.next.enumerateReferenceSpaces(session, 0, &n, nullptr); XR_FAILED(r)) return r;
    std::vector<XrReferenceSpaceType> all(n);
    if (XrResult r = st.next.enumerateReferenceSpaces(session, n, &n, all.data()); XR_FAILED(r)) return r;
    all.push_back(XR_REFERENCE_SPACE_TYPE_COMBINED_EYE_VARJO);
    if (!countOutput) return XR_ERROR_VALIDATION_FAILURE;
    *countOutput = uint32_t(all.size());
    if (capacity == 0) return XR_SUCCESS;
    if (capacity < all.size()) return XR_ERROR_SIZE_INSUFFICIENT;
    if (!spaces) return XR_ERROR_VALIDATION_FAILURE;
    std::copy(all.begin(), all.end(), spaces);
    return XR_SUCCESS;
}

XRAPI_ATTR XrResult XRAPI_CALL layerCreateReferenceSpace(XrSession session, const XrReferenceSpaceCreateInfo* info,
                                                         XrSpace* space) {
    std::lock_guard lock(g_mutex);
    auto it = g_sessions.find(session);
    if (it == g_sessions.end()) return XR_ERROR_HANDLE_INVALID;
    const InstanceState& st = g_instances.at(it->second.instance);
    if (!st.foveatedRendering || !info || info->type != XR_TYPE_REFERENCE_SPACE_CREATE_INFO ||
        info->referenceSpaceType != XR_REFERENCE_SPACE_TYPE_COMBINED_EYE_VARJO)
        return st.next.createReferenceSpace(session, info, space);
    const XrPosef& pose = info->poseInReferenceSpace;
    const float v[7] = {pose.orientation.x, pose.orientation.y, pose.orientation.z, pose.orientation.w,
                        pose.position.x,    pose.position.y,    pose.position.z};
    for (float x : v)
        if (!std::isfinite(x)) return XR_ERROR_POSE_INVALID;
    if (std::abs(std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2] + v[3] * v[3]) - 1.0f) > 1e-3f)
        return XR_ERROR_POSE_INVALID;
    XrReferenceSpaceCreateInfo ci = *info;
    ci.referenceSpaceType = XR_REFERENCE_SPACE_TYPE_VIEW;
    ci.poseInReferenceSpace = {{0, 0, 0, 1}, {0, 0, 0}};  // the layer applies the application's pose
    XrResult r = st.next.createReferenceSpace(session, &ci, space);
    if (XR_SUCCEEDED(r)) g_combinedEye[*space] = {session, info->poseInReferenceSpace};
    return r;
}

/// The next link of an instance that offers the combined-eye space, for the calls on spaces (a space
/// does not name its instance; the next link's functions are the same for every instance of a
/// process). The layer intercepts them only for such instances.
const Next& anyNext() {
    static const Next none;
    for (const auto& [h, st] : g_instances)
        if (st.foveatedRendering) return st.next;
    return none;
}

XRAPI_ATTR XrResult XRAPI_CALL layerDestroySpace(XrSpace space) {
    PFN_xrDestroySpace next = nullptr;
    {
        std::lock_guard lock(g_mutex);
        auto sp = g_combinedEye.find(space);
        if (sp != g_combinedEye.end()) {
            auto s = g_sessions.find(sp->second.session);
            if (s != g_sessions.end()) next = g_instances.at(s->second.instance).next.destroySpace;
            g_combinedEye.erase(sp);
        }
        if (!next) next = anyNext().destroySpace;
    }
    return next ? next(space) : XR_ERROR_HANDLE_INVALID;
}

/// The rendering gaze of a combined-eye space's session at `time`: its orientation in the VIEW space
/// (the cyclopean gaze, looking along -Z), or nullopt while the gaze is invalid.
std::optional<glm::quat> renderingGaze(SessionState& s, const Next& n, XrSpace view, XrTime time) {
    const XrPosef identity{{0, 0, 0, 1}, {0, 0, 0}};
    const XrPosef poses[2] = {identity, identity};
    const std::array<layers::EyeGaze, 2> g = eyeGaze(s, n, view, poses, time);
    glm::vec3 sum(0.0f);
    for (const auto& e : g)
        if (e.valid && std::isfinite(e.dir.x) && std::isfinite(e.dir.y) && std::isfinite(e.dir.z) &&
            glm::length(e.dir) > 0.0f)
            sum += glm::normalize(e.dir);
    if (!(glm::length(sum) > 0.0f)) return std::nullopt;
    return glm::rotation(glm::vec3(0, 0, -1), glm::normalize(sum));
}

XRAPI_ATTR XrResult XRAPI_CALL layerLocateSpace(XrSpace space, XrSpace base, XrTime time, XrSpaceLocation* location) {
    std::lock_guard lock(g_mutex);
    auto a = g_combinedEye.find(space), b = g_combinedEye.find(base);
    const CombinedEye* ce = a != g_combinedEye.end() ? &a->second : b != g_combinedEye.end() ? &b->second : nullptr;
    if (!ce)
        return anyNext().locateSpace ? anyNext().locateSpace(space, base, time, location) : XR_ERROR_HANDLE_INVALID;
    auto sit = g_sessions.find(ce->session);
    if (sit == g_sessions.end()) return XR_ERROR_HANDLE_INVALID;
    SessionState& s = sit->second;
    const Next& n = g_instances.at(s.instance).next;
    XrResult r = n.locateSpace(space, base, time, location);
    if (XR_FAILED(r) || !location || !(location->locationFlags & XR_SPACE_LOCATION_ORIENTATION_VALID_BIT)) return r;
    auto toQuat = [](const XrQuaternionf& q) { return glm::quat(q.w, q.x, q.y, q.z); };
    auto toVec = [](const XrVector3f& v) { return glm::vec3(v.x, v.y, v.z); };
    // A combined-eye space's frame in its VIEW stand-in: the gaze's rotation, then the application's pose.
    bool tracked = true;
    auto frameOf = [&](const CombinedEye& c, XrSpace view, glm::quat& q, glm::vec3& p) {
        const std::optional<glm::quat> g = renderingGaze(s, n, view, time);
        tracked = tracked && g.has_value();
        const glm::quat gq = g ? *g : glm::quat(1, 0, 0, 0);
        q = gq * toQuat(c.pose.orientation);
        p = gq * toVec(c.pose.position);
    };
    glm::quat q = toQuat(location->pose.orientation);
    glm::vec3 p = toVec(location->pose.position);
    if (a != g_combinedEye.end()) {  // pose = located * frame
        glm::quat fq;
        glm::vec3 fp;
        frameOf(a->second, space, fq, fp);
        p = p + q * fp;
        q = q * fq;
    }
    if (b != g_combinedEye.end()) {  // pose = inverse(frame) * located
        glm::quat fq;
        glm::vec3 fp;
        frameOf(b->second, base, fq, fp);
        const glm::quat inv = glm::conjugate(fq);
        p = inv * (p - fp);
        q = inv * q;
    }
    q = glm::normalize(q);
    location->pose = {{q.x, q.y, q.z, q.w}, {p.x, p.y, p.z}};
    if (!tracked) location->locationFlags &= ~XrSpaceLocationFlags(XR_SPACE_LOCATION_ORIENTATION_TRACKED_BIT);
    return r;
}

/// Composites the projection layer and copies the output into the layer's swapchain; false when the
/// frame must pass through (logged once per reason).
bool process(SessionState& s, const Next& n, XrSession session, const XrFrameEndInfo& info,
             const XrCompositionLayerProjection& proj, XrCompositionLayerProjection& patched,
             std::array<XrCompositionLayerProjectionView, 2>& views) {
    auto once = [&](int code, const std::string& why) {
        if (!s.logged[code]) logLine("frame passed through: " + why);
        s.logged[code] = true;
        return false;
    };
    const bool quad = s.quad && proj.viewCount == 4 && proj.views;
    if (!quad && (proj.viewCount != 2 || !proj.views)) return once(1, "not a stereo projection layer");
    layers::FrameEndInfo fe;
    fe.frameIndex = s.frames;
    fe.time_s = double(info.displayTime) * 1e-9;
    layers::ProjectionLayer layer;
    // One view of the application's: its colour, depth and motion where the compositor reads them.
    // An imported sub-image of the application's, or null (xr::projectionView, the runtime's conversion).
    auto imported = [](const XrSwapchainSubImage& x) -> std::optional<layers::SubImage> {
        auto it = g_swapchains.find(x.swapchain);
        if (it == g_swapchains.end() || !it->second.imported) return std::nullopt;
        return layers::SubImage{it->second.imported.get(),
                                {x.imageRect.offset.x, x.imageRect.offset.y, uint32_t(x.imageRect.extent.width),
                                 uint32_t(x.imageRect.extent.height)},
                                x.imageArrayIndex};
    };
    auto viewOf = [&](const XrCompositionLayerProjectionView& v) -> std::optional<layers::ProjectionView> {
        xr::ViewExtras ex;
        std::optional<layers::ProjectionView> pv = xr::projectionView(v, imported, true, true, &ex);
        if (pv && ex.locomotion) s.comp->resetHistory();
        return pv;
    };
    if (quad) {
        // Quad views: each wide view with its inset, composed at the runtime's stereo size. Depth and
        // motion where all four views have them (one depth range per eye), as the runtime does.
        std::array<layers::ProjectionView, 4> v;
        for (uint32_t i = 0; i < 4; ++i) {
            auto pv = viewOf(proj.views[i]);
            if (!pv) return once(2, "a view's swapchain is not one the compositor reads");
            v[i] = *pv;
        }
        // Wide views rendered jittered (the runtime's located stereo field of view shifted by under
        // half a pixel) are composed on the located grid with their samples where they were taken
        // (xr::placeJitter); the insets are placed by the field of view they were rendered with.
        XrViewLocateInfo li{XR_TYPE_VIEW_LOCATE_INFO};
        li.viewConfigurationType = kStereo;
        li.displayTime = info.displayTime;
        li.space = proj.space;
        XrViewState vs{XR_TYPE_VIEW_STATE};
        XrView located[2] = {{XR_TYPE_VIEW}, {XR_TYPE_VIEW}};
        uint32_t count = 0;
        if (n.locateViews(session, &li, &vs, 2, &count, located) == XR_SUCCESS && count == 2)
            for (uint32_t e = 0; e < 2; ++e) {
                const XrFovf& f = located[e].fov;
                xr::placeJitter(v[e], layers::Fov{f.angleLeft, f.angleRight, f.angleUp, f.angleDown});
            }
        layer = layers::quadLayer(v, s.displayWidth, s.displayHeight);
    } else {
        for (uint32_t e = 0; e < 2; ++e) {
            auto pv = viewOf(proj.views[e]);
            if (!pv) return once(2, "a view's swapchain is not one the compositor reads");
            layer.views.push_back(*pv);
        }
    }
    fe.layers.push_back(layer);
    const auto g = eyeGaze(s, n, proj, info.displayTime);
    fe.gaze[0] = g[0];
    fe.gaze[1] = g[1];
    // The last frame's GPU times (its work has normally finished by now; endFrame waits for it anyway).
    waitComposited(s);
    if (s.disabled) return false;
    if (!s.composited) {
        VkSemaphoreCreateInfo sci{VK_STRUCTURE_TYPE_SEMAPHORE_CREATE_INFO};
        VkFenceCreateInfo fci{VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
        VkSemaphore sem = VK_NULL_HANDLE;
        VkFence fence = VK_NULL_HANDLE;
        const VkDevice dev = s.ctx->device();
        if (vkCreateSemaphore(dev, &sci, nullptr, &sem) != VK_SUCCESS ||
            vkCreateFence(dev, &fci, nullptr, &fence) != VK_SUCCESS) {
            if (sem) vkDestroySemaphore(dev, sem, nullptr);
            disable(s, "no semaphore or fence for the frame's work");
            return false;
        }
        s.composited = vk::Semaphore(dev, sem);
        s.copied = vk::Fence(dev, fence);
        auto cb = s.ctx->allocateCommandBuffer();
        if (!cb) {
            disable(s, "no command buffer for the frame's copies: " + cb.error().message);
            return false;
        }
        s.copyCb = *cb;
    }
    FrameSubmission submission;
    submission.mode = FrameSubmission::Mode::Submit;
    const VkSemaphore composited = s.composited.get();
    submission.signalSemaphores = {&composited, 1};
    if (Status st = s.comp->endFrame(fe, submission); !st) {
        if (st.error().code == int(layers::SubmitError::DeviceFailure)) disable(s, st.message());
        return once(100 + st.error().code, st.message());
    }
    s.statsPending = true;
    const FrameStats& stats = s.comp->stats();
    if (stats.gazeFallback[0] || stats.gazeFallback[1]) ++s.fallbackFrames;
    if (s.frames % 300 == 0) {
        char line[160];
        std::snprintf(line, sizeof line, "frame %llu: passes %.2f ms a frame so far, gaze %s",
                      (unsigned long long)s.frames, s.gpuFrames ? s.gpuMs / double(s.gpuFrames) : 0.0,
                      stats.gazeFallback[0] || stats.gazeFallback[1] ? "fallback (view centre)" : "tracked");
        logLine(line);
    }
    const uint32_t w = s.comp->width(), h = s.comp->height();
    // The copy waits for the semaphore the compositor signalled: from here on this frame's
    // semaphore signal must be consumed, so every failure below still submits or waits it out.
    auto abandon = [&](const std::string& why) {
        waitComposited(s);  // the semaphore stays signalled: no later frame uses it
        s.composited.reset();
        disable(s, why);
        return false;
    };
    waitCopied(s);  // the last frame's copy, before its command buffer is recorded again
    if (s.disabled) return abandon(s.why);
    if (!ensureOutput(s, n, session, w, h)) return abandon("the runtime made no RGBA8 swapchain for the output");
    uint32_t index = 0;
    XrSwapchainImageWaitInfo wi{XR_TYPE_SWAPCHAIN_IMAGE_WAIT_INFO};
    wi.timeout = XR_INFINITE_DURATION;
    if (n.acquireSwapchainImage(s.out, nullptr, &index) != XR_SUCCESS || n.waitSwapchainImage(s.out, &wi) != XR_SUCCESS)
        return abandon("the output swapchain could not be acquired");
    const VkImage dst = s.outImages.at(index);
    VkCommandBufferBeginInfo bi{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
    bi.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
    VkResult rec = vkBeginCommandBuffer(s.copyCb, &bi);
    if (rec == VK_SUCCESS) {
        VkCommandBuffer cb = s.copyCb;
        vk::layoutTransition(cb, dst, VK_IMAGE_ASPECT_COLOR_BIT, 2, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL,
                             VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL);
        VkImageCopy c{};
        c.srcSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 2};
        c.dstSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 2};
        c.extent = {w, h, 1};
        // The compositor's output rests in GENERAL; it is copied from TRANSFER_SRC_OPTIMAL and put back.
        const VkImage src = s.comp->outputImage().handle();
        vk::layoutTransition(cb, src, VK_IMAGE_ASPECT_COLOR_BIT, 2, VK_IMAGE_LAYOUT_GENERAL,
                             VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL);
        vkCmdCopyImage(cb, src, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, dst, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1, &c);
        vk::layoutTransition(cb, src, VK_IMAGE_ASPECT_COLOR_BIT, 2, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL,
                             VK_IMAGE_LAYOUT_GENERAL);
        // Back to the layout the runtime expects at release, visible to whatever it runs next on the queue.
        vk::layoutTransition(cb, dst, VK_IMAGE_ASPECT_COLOR_BIT, 2, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL,
                             VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL);
        rec = vkEndCommandBuffer(cb);
    }
    if (rec == VK_SUCCESS) {
        const VkPipelineStageFlags stage = VK_PIPELINE_STAGE_TRANSFER_BIT;
        VkSubmitInfo si{VK_STRUCTURE_TYPE_SUBMIT_INFO};
        si.waitSemaphoreCount = 1;
        si.pWaitSemaphores = &composited;
        si.pWaitDstStageMask = &stage;
        si.commandBufferCount = 1;
        si.pCommandBuffers = &s.copyCb;
        rec = s.ctx->submitNoWait(si, s.copied.get());
        s.copyInFlight = rec == VK_SUCCESS;
    }
    // Released without waiting: the copy is on the session's queue, ahead of anything the runtime
    // submits there to read the image (XR_KHR_vulkan_enable: images are released to that queue).
    n.releaseSwapchainImage(s.out, nullptr);
    if (rec != VK_SUCCESS) return abandon(std::string("copying the output: ") + vk::resultString(rec));
    patched = proj;
    for (uint32_t e = 0; e < 2; ++e) {
        views[e] = proj.views[e];  // pose, fov and the chained depth info stay the application's
        // ... except a jittered wide view's field of view: the output was composed on the located grid
        // (xr::placeJitter), and the runtime places the image by the field of view it is given.
        if (quad) {
            const layers::Fov& f = layer.views[e].fov;
            views[e].fov = {f.angleLeft, f.angleRight, f.angleUp, f.angleDown};
        }
        views[e].subImage.swapchain = s.out;
        views[e].subImage.imageRect = {{0, 0}, {int32_t(w), int32_t(h)}};
        views[e].subImage.imageArrayIndex = e;
        if (quad) views[e].next = nullptr;  // the wide views' depth is not the output's size
    }
    patched.viewCount = 2;
    patched.views = views.data();
    return true;
}

/// A frame end the layer does not composite, down the chain. In a session with the quad views the
/// layer offers, each four-view projection layer goes down as its two wide views (the runtime's
/// session is stereo): the application's frame is still shown, at the wide views' density.
XrResult endDown(const SessionState& s, const Next& n, XrSession session, const XrFrameEndInfo* info) {
    if (!s.quad || !info || info->type != XR_TYPE_FRAME_END_INFO || !info->layers) return n.endFrame(session, info);
    std::vector<const XrCompositionLayerBaseHeader*> layers(info->layers, info->layers + info->layerCount);
    std::vector<XrCompositionLayerProjection> wide;
    wide.reserve(layers.size());
    for (auto& l : layers)
        if (l && l->type == XR_TYPE_COMPOSITION_LAYER_PROJECTION) {
            wide.push_back(*reinterpret_cast<const XrCompositionLayerProjection*>(l));
            if (wide.back().viewCount == 4) wide.back().viewCount = 2;
            l = reinterpret_cast<const XrCompositionLayerBaseHeader*>(&wide.back());
        }
    XrFrameEndInfo fe = *info;
    fe.layers = layers.data();
    return n.endFrame(session, &fe);
}

XRAPI_ATTR XrResult XRAPI_CALL layerEndFrame(XrSession session, const XrFrameEndInfo* info) {
    std::lock_guard lock(g_mutex);
    auto it = g_sessions.find(session);
    if (it == g_sessions.end()) return XR_ERROR_HANDLE_INVALID;
    SessionState& s = it->second;
    const Next& n = g_instances.at(s.instance).next;
    // Quad views the layer offers: a projection layer has the configuration's four views (the runtime
    // below would count them against its stereo configuration). A refused frame end is no frame.
    if (s.quad && info && info->type == XR_TYPE_FRAME_END_INFO && info->layers)
        for (uint32_t i = 0; i < info->layerCount; ++i)
            if (info->layers[i] && info->layers[i]->type == XR_TYPE_COMPOSITION_LAYER_PROJECTION) {
                const auto* p = reinterpret_cast<const XrCompositionLayerProjection*>(info->layers[i]);
                if (p->viewCount != 4) {
                    logLine("xrEndFrame: XR_ERROR_VALIDATION_FAILURE: (frameEndInfo->layers[" + std::to_string(i) +
                            "]->viewCount == " + std::to_string(p->viewCount) +
                            ") is not the 4 views of XR_VIEW_CONFIGURATION_TYPE_PRIMARY_QUAD_VARJO");
                    return XR_ERROR_VALIDATION_FAILURE;
                }
            }
    if (info && info->type == XR_TYPE_FRAME_END_INFO) ++s.frames;
    if (!info || info->type != XR_TYPE_FRAME_END_INFO || !info->layers) return endDown(s, n, session, info);
    uint32_t projIndex = info->layerCount;
    for (uint32_t i = 0; i < info->layerCount; ++i)
        if (info->layers[i] && info->layers[i]->type == XR_TYPE_COMPOSITION_LAYER_PROJECTION) {
            projIndex = i;
            break;
        }
    if (projIndex == info->layerCount) return n.endFrame(session, info);  // nothing to foveate
    ++s.projected;
    if (s.disabled) return endDown(s, n, session, info);
    XrCompositionLayerProjection patched{};
    std::array<XrCompositionLayerProjectionView, 2> views{};
    const auto& proj = *reinterpret_cast<const XrCompositionLayerProjection*>(info->layers[projIndex]);
    const auto t0 = std::chrono::steady_clock::now();
    if (!process(s, n, session, *info, proj, patched, views)) return endDown(s, n, session, info);
    s.endFrameMs += std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    ++s.processed;
    std::vector<const XrCompositionLayerBaseHeader*> layers(info->layers, info->layers + info->layerCount);
    layers[projIndex] = reinterpret_cast<const XrCompositionLayerBaseHeader*>(&patched);
    XrFrameEndInfo fe = *info;
    fe.layers = layers.data();
    return endDown(s, n, session, &fe);
}

// ---- Dispatch ---------------------------------------------------------------------------------

struct Entry {
    const char* name;
    PFN_xrVoidFunction fn;
};
#define WRSFOV_ENTRY(api, ours) {#api, reinterpret_cast<PFN_xrVoidFunction>(&ours)}
const Entry kEntries[] = {
    WRSFOV_ENTRY(xrGetInstanceProcAddr, layerGetInstanceProcAddr),
    WRSFOV_ENTRY(xrDestroyInstance, layerDestroyInstance),
    WRSFOV_ENTRY(xrSuggestInteractionProfileBindings, layerSuggestInteractionProfileBindings),
    WRSFOV_ENTRY(xrCreateSession, layerCreateSession),
    WRSFOV_ENTRY(xrDestroySession, layerDestroySession),
    WRSFOV_ENTRY(xrAttachSessionActionSets, layerAttachSessionActionSets),
    WRSFOV_ENTRY(xrSyncActions, layerSyncActions),
    WRSFOV_ENTRY(xrGetSystemProperties, layerGetSystemProperties),
    WRSFOV_ENTRY(xrGetCurrentInteractionProfile, layerGetCurrentInteractionProfile),
    WRSFOV_ENTRY(xrCreateActionSet, layerCreateActionSet),
    WRSFOV_ENTRY(xrDestroyActionSet, layerDestroyActionSet),
    WRSFOV_ENTRY(xrCreateAction, layerCreateAction),
    WRSFOV_ENTRY(xrPollEvent, layerPollEvent),
    WRSFOV_ENTRY(xrCreateSwapchain, layerCreateSwapchain),
    WRSFOV_ENTRY(xrDestroySwapchain, layerDestroySwapchain),
    WRSFOV_ENTRY(xrEnumerateSwapchainImages, layerEnumerateSwapchainImages),
    WRSFOV_ENTRY(xrAcquireSwapchainImage, layerAcquireSwapchainImage),
    WRSFOV_ENTRY(xrWaitSwapchainImage, layerWaitSwapchainImage),
    WRSFOV_ENTRY(xrReleaseSwapchainImage, layerReleaseSwapchainImage),
    WRSFOV_ENTRY(xrEndFrame, layerEndFrame),
};
// Quad views on a runtime without them: intercepted only for an instance where the layer offers them
// (InstanceState::quadViews; the spaces' calls for foveatedRendering).
const Entry kQuadEntries[] = {
    WRSFOV_ENTRY(xrEnumerateViewConfigurations, layerEnumerateViewConfigurations),
    WRSFOV_ENTRY(xrGetViewConfigurationProperties, layerGetViewConfigurationProperties),
    WRSFOV_ENTRY(xrEnumerateViewConfigurationViews, layerEnumerateViewConfigurationViews),
    WRSFOV_ENTRY(xrEnumerateEnvironmentBlendModes, layerEnumerateEnvironmentBlendModes),
    WRSFOV_ENTRY(xrBeginSession, layerBeginSession),
    WRSFOV_ENTRY(xrLocateViews, layerLocateViews),
};
const Entry kFoveatedEntries[] = {
    WRSFOV_ENTRY(xrEnumerateReferenceSpaces, layerEnumerateReferenceSpaces),
    WRSFOV_ENTRY(xrCreateReferenceSpace, layerCreateReferenceSpace),
    WRSFOV_ENTRY(xrLocateSpace, layerLocateSpace),
    WRSFOV_ENTRY(xrDestroySpace, layerDestroySpace),
};
#undef WRSFOV_ENTRY

XRAPI_ATTR XrResult XRAPI_CALL layerGetInstanceProcAddr(XrInstance instance, const char* name,
                                                        PFN_xrVoidFunction* function) {
    if (!name || !function) return XR_ERROR_VALIDATION_FAILURE;
    PFN_xrGetInstanceProcAddr next = nullptr;
    bool passThrough = false, quad = false, foveated = false;
    {
        std::lock_guard lock(g_mutex);
        auto it = g_instances.find(instance);
        if (it == g_instances.end()) return XR_ERROR_HANDLE_INVALID;
        next = it->second.next.getInstanceProcAddr;
        passThrough = it->second.passThrough;
        quad = it->second.quadViews;
        foveated = it->second.foveatedRendering;
    }
    if (passThrough && std::strcmp(name, "xrDestroyInstance") != 0) return next(instance, name, function);
    auto find = [&](std::span<const Entry> entries) -> const Entry* {
        for (const Entry& e : entries)
            if (std::strcmp(e.name, name) == 0) return &e;
        return nullptr;
    };
    const Entry* e = find(kEntries);
    if (!e && quad) e = find(kQuadEntries);
    if (!e && foveated) e = find(kFoveatedEntries);
    if (e) {
        XrResult r = next(instance, name, function);  // unsupported below: unsupported here too
        if (XR_FAILED(r)) return r;
        *function = e->fn;
        return XR_SUCCESS;
    }
    return next(instance, name, function);
}

}  // namespace
}  // namespace wrsfov::xrlayer

WRSFOV_LAYER_EXPORT XrResult xrNegotiateLoaderApiLayerInterface(const XrNegotiateLoaderInfo* loaderInfo,
                                                                const char* layerName,
                                                                XrNegotiateApiLayerRequest* request) {
    if (!loaderInfo || !request || !layerName || std::strcmp(layerName, wrsfov::xrlayer::kLayerName) != 0 ||
        loaderInfo->structType != XR_LOADER_INTERFACE_STRUCT_LOADER_INFO ||
        loaderInfo->structVersion != XR_LOADER_INFO_STRUCT_VERSION ||
        loaderInfo->structSize != sizeof(XrNegotiateLoaderInfo) ||
        request->structType != XR_LOADER_INTERFACE_STRUCT_API_LAYER_REQUEST ||
        request->structVersion != XR_API_LAYER_INFO_STRUCT_VERSION ||
        request->structSize != sizeof(XrNegotiateApiLayerRequest) ||
        loaderInfo->minInterfaceVersion > XR_CURRENT_LOADER_API_LAYER_VERSION ||
        loaderInfo->maxInterfaceVersion < XR_CURRENT_LOADER_API_LAYER_VERSION)
        return XR_ERROR_INITIALIZATION_FAILED;
    request->layerInterfaceVersion = XR_CURRENT_LOADER_API_LAYER_VERSION;
    request->layerApiVersion = XR_MAKE_VERSION(1, 0, XR_VERSION_PATCH(XR_CURRENT_API_VERSION));
    request->getInstanceProcAddr = &wrsfov::xrlayer::layerGetInstanceProcAddr;
    request->createApiLayerInstance = &wrsfov::xrlayer::layerCreateApiLayerInstance;
    return XR_SUCCESS;
}
