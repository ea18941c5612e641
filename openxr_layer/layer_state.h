// The API layer XR_APILAYER_WRSFOV_foveation: the state its API areas share (one file each: layer_instance.cpp,
// layer_session.cpp, layer_swapchain.cpp, layer_views.cpp, layer_frame.cpp; the state and helpers in
// layer_state.cpp; what the whole layer does is said
// in layer_instance.cpp) and the functions one area calls in another.
#pragma once

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
#include "xr_common/loader_negotiation.h"
#include "xr_common/xr_config.h"
#include "xr_common/xr_frame.h"
#include "xr_common/xr_inset.h"

namespace wrsfov::xrlayer {

using xr::findNext;
using xr::loadConfig;
using xr::RuntimeConfig;

constexpr const char* kLayerName = "XR_APILAYER_WRSFOV_foveation";
constexpr const char* kEyeProfile = "/interaction_profiles/ext/eye_gaze_interaction";
constexpr const char* kEyePose = "/user/eyes_ext/input/gaze_ext/pose";

/// One line of the layer's log (stderr, "[wrsfov-layer] ...").
void logLine(const std::string& s);

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

extern std::mutex g_mutex;
extern std::map<XrInstance, InstanceState> g_instances;
extern std::map<XrSession, SessionState> g_sessions;
extern std::map<XrSwapchain, SwapchainState> g_swapchains;
extern std::map<XrActionSet, XrInstance> g_actionSets;  // the application's, for the checks of xrCreateAction
// XR_REFERENCE_SPACE_TYPE_COMBINED_EYE_VARJO spaces the layer offers: a VIEW space of the runtime's
// (at the identity) standing in for each, turned to the gaze and then by the application's pose in
// xrLocateSpace.
struct CombinedEye {
    XrSession session = XR_NULL_HANDLE;
    XrPosef pose{};  // poseInReferenceSpace
};
extern std::map<XrSpace, CombinedEye> g_combinedEye;

/// The quad view configuration the layer offers, over the runtime's stereo one.
constexpr XrViewConfigurationType kQuad = XR_VIEW_CONFIGURATION_TYPE_PRIMARY_QUAD_VARJO;
constexpr XrViewConfigurationType kStereo = XR_VIEW_CONFIGURATION_TYPE_PRIMARY_STEREO;

template <typename F>
void load(PFN_xrGetInstanceProcAddr gipa, XrInstance inst, const char* name, F& fn) {
    PFN_xrVoidFunction f = nullptr;
    if (gipa(inst, name, &f) == XR_SUCCESS) fn = reinterpret_cast<F>(f);
}

XRAPI_ATTR XrResult XRAPI_CALL layerCreateSession(XrInstance instance, const XrSessionCreateInfo* info,
                                                  XrSession* session);
XRAPI_ATTR XrResult XRAPI_CALL layerDestroySession(XrSession session);
XRAPI_ATTR XrResult XRAPI_CALL layerAttachSessionActionSets(XrSession session, const XrSessionActionSetsAttachInfo* info);
XRAPI_ATTR XrResult XRAPI_CALL layerSyncActions(XrSession session, const XrActionsSyncInfo* info);
XRAPI_ATTR XrResult XRAPI_CALL layerCreateSwapchain(XrSession session, const XrSwapchainCreateInfo* info,
                                                    XrSwapchain* swapchain);
XRAPI_ATTR XrResult XRAPI_CALL layerDestroySwapchain(XrSwapchain swapchain);
XRAPI_ATTR XrResult XRAPI_CALL layerEnumerateSwapchainImages(XrSwapchain swapchain, uint32_t capacity,
                                                             uint32_t* countOutput, XrSwapchainImageBaseHeader* images);
XRAPI_ATTR XrResult XRAPI_CALL layerAcquireSwapchainImage(XrSwapchain swapchain, const XrSwapchainImageAcquireInfo* info,
                                                          uint32_t* index);
XRAPI_ATTR XrResult XRAPI_CALL layerWaitSwapchainImage(XrSwapchain swapchain, const XrSwapchainImageWaitInfo* info);
XRAPI_ATTR XrResult XRAPI_CALL layerReleaseSwapchainImage(XrSwapchain swapchain, const XrSwapchainImageReleaseInfo* info);
std::array<layers::EyeGaze, 2> eyeGaze(SessionState& s, const Next& n, XrSpace space, const XrPosef (&poses)[2],
                                       XrTime time);
std::array<layers::EyeGaze, 2> eyeGaze(SessionState& s, const Next& n, const XrCompositionLayerProjection& proj,
                                       XrTime time);
XRAPI_ATTR XrResult XRAPI_CALL layerEnumerateViewConfigurations(XrInstance instance, XrSystemId system,
                                                                uint32_t capacity, uint32_t* countOutput,
                                                                XrViewConfigurationType* types);
XRAPI_ATTR XrResult XRAPI_CALL layerGetViewConfigurationProperties(XrInstance instance, XrSystemId system,
                                                                   XrViewConfigurationType type,
                                                                   XrViewConfigurationProperties* properties);
XRAPI_ATTR XrResult XRAPI_CALL layerEnumerateViewConfigurationViews(XrInstance instance, XrSystemId system,
                                                                    XrViewConfigurationType type, uint32_t capacity,
                                                                    uint32_t* countOutput,
                                                                    XrViewConfigurationView* views);
XRAPI_ATTR XrResult XRAPI_CALL layerEnumerateEnvironmentBlendModes(XrInstance instance, XrSystemId system,
                                                                   XrViewConfigurationType type, uint32_t capacity,
                                                                   uint32_t* countOutput,
                                                                   XrEnvironmentBlendMode* modes);
XRAPI_ATTR XrResult XRAPI_CALL layerBeginSession(XrSession session, const XrSessionBeginInfo* info);
XRAPI_ATTR XrResult XRAPI_CALL layerLocateViews(XrSession session, const XrViewLocateInfo* info, XrViewState* viewState,
                                                uint32_t capacity, uint32_t* countOutput, XrView* views);
XRAPI_ATTR XrResult XRAPI_CALL layerEnumerateReferenceSpaces(XrSession session, uint32_t capacity,
                                                             uint32_t* countOutput, XrReferenceSpaceType* spaces);
XRAPI_ATTR XrResult XRAPI_CALL layerCreateReferenceSpace(XrSession session, const XrReferenceSpaceCreateInfo* info,
                                                         XrSpace* space);
XRAPI_ATTR XrResult XRAPI_CALL layerDestroySpace(XrSpace space);
XRAPI_ATTR XrResult XRAPI_CALL layerLocateSpace(XrSpace space, XrSpace base, XrTime time, XrSpaceLocation* location);
bool process(SessionState& s, const Next& n, XrSession session, const XrFrameEndInfo& info,
             const XrCompositionLayerProjection& proj, XrCompositionLayerProjection& patched,
             std::array<XrCompositionLayerProjectionView, 2>& views);
XRAPI_ATTR XrResult XRAPI_CALL layerEndFrame(XrSession session, const XrFrameEndInfo* info);
bool isQuadExtension(const char* e);
void disable(SessionState& s, const std::string& why);
void waitComposited(SessionState& s);
void waitCopied(SessionState& s);
void settle(SessionState& s);
std::optional<layers::Format> colorFormat(int64_t f);
XRAPI_ATTR XrResult XRAPI_CALL layerGetInstanceProcAddr(XrInstance instance, const char* name,
                                                        PFN_xrVoidFunction* function);
XRAPI_ATTR XrResult XRAPI_CALL layerCreateApiLayerInstance(const XrInstanceCreateInfo* info,
                                                           const XrApiLayerCreateInfo* layerInfo, XrInstance* instance);

}  // namespace wrsfov::xrlayer
