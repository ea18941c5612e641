// Objects behind the runtime's OpenXR handles (internal to runtime/). Every handle is the address
// of one of these objects, checked against the live-object registry before use, so a stale,
// foreign or made-up handle is XR_ERROR_HANDLE_INVALID rather than a crash.
//
// Locking is per object. The locks, in the order in which they may nest (outer first):
//   Instance::mutex      the instance's state: paths, action sets, actions and bindings, its sessions'
//                        spaces, action-set attachments and interaction profiles;
//   Session::gpuMutex    Vulkan work on the session's device and queue (compositor, quad pass,
//                        window, swapchain images made, prepared or read back) and its swapchain list;
//   Swapchain::mutex     the images' acquire / wait / release state and which frame reads them;
//   Session::frameMutex  the session state and the frame loop (waited and begun frames, display
//                        times, frames handed to the compositor and completed), with frameCv;
//   Session::gazeMutex   the gaze source;
//   Instance::eventMutex the event queue;
//   the registry's lock (xr_runtime.cpp).
// No lock is held while the passes run: xrEndFrame submits them and returns, the session's
// compositor thread waits for them (holding nothing) and then marks the frame complete under
// frameMutex; the calls that wait for a frame (xrWaitSwapchainImage, xrEndFrame for the frame before,
// xrDestroySwapchain, xrDestroySession), and xrWaitFrame for its display slot and for the frame before
// to be begun, wait on frameCv, which releases frameMutex.
// A handle being destroyed may not be in use on another thread (the specification's external
// synchronisation of xrDestroy*), so a pointer found in the registry stays valid for the call.
#pragma once

#define XR_USE_GRAPHICS_API_VULKAN
#include <vulkan/vulkan.h>
#include <openxr/openxr.h>
#include <openxr/openxr_platform.h>

#include <algorithm>
#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <map>
#include <memory>
#include <mutex>
#include <set>
#include <string>
#include <thread>
#include <unordered_map>
#include <vector>

#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>

#include "compositor/compositor.h"
#include "eval/sequence.h"
#include "gaze/source.h"
#include "xr_common/xr_config.h"
#include "runtime/xr_quad.h"
#include "runtime/xr_window.h"

namespace wrsfov::xr {

enum class ObjectType : uint8_t { Instance, Session, Space, Swapchain, ActionSet, Action };

struct Object {
    explicit Object(ObjectType t) : type(t) {}
    virtual ~Object() = default;
    const ObjectType type;
};

/// A rigid transform: p' = q * p + t.
struct Pose {
    glm::quat q{1.0f, 0.0f, 0.0f, 0.0f};
    glm::vec3 p{0.0f};
};
Pose operator*(const Pose& a, const Pose& b);
Pose inverse(const Pose& a);
Pose fromXr(const XrPosef& p);
XrPosef toXr(const Pose& p);
/// Orientation is a unit quaternion (within 1e-3) and every component finite.
bool isValidPose(const XrPosef& p);

struct Instance;
struct Session;
struct ActionSet;

struct Action final : Object {
    Action() : Object(ObjectType::Action) {}
    ActionSet* set = nullptr;
    std::string name, localizedName;
    XrActionType actionType = XR_ACTION_TYPE_BOOLEAN_INPUT;
    std::vector<XrPath> subactionPaths;
    bool destroyed = false;  // the handle is gone, its names free again; bindings may still refer to it
};

struct ActionSet final : Object {
    ActionSet() : Object(ObjectType::ActionSet) {}
    Instance* instance = nullptr;
    std::string name, localizedName;
    uint32_t priority = 0;
    bool attached = false;
    bool destroyed = false;  // the handle is gone (an attached set lives on in its sessions), its names free
    std::vector<std::unique_ptr<Action>> actions;
};

struct Space final : Object {
    Space() : Object(ObjectType::Space) {}
    Session* session = nullptr;
    bool isAction = false;
    XrReferenceSpaceType reference = XR_REFERENCE_SPACE_TYPE_LOCAL;
    Action* action = nullptr;
    XrPath subaction = XR_NULL_PATH;
    Pose poseInSpace;
};

struct Swapchain final : Object {
    Swapchain() : Object(ObjectType::Swapchain) {}
    Session* session = nullptr;
    XrSwapchainCreateInfo info{};
    layers::Format format = layers::Format::RGBA8;
    std::unique_ptr<layers::Swapchain> images;
    uint32_t acquiredEver = 0;  // a static swapchain may be acquired once
    std::mutex mutex;
    std::deque<uint32_t> acquiredOrder;  // acquired and not yet waited, oldest first
    std::vector<uint64_t> readByFrame;   // per image: the last frame (serial) whose composition reads it
};

/// The eye-gaze pose of one instant in head space (the cyclopean eye at the origin).
struct GazeState {
    bool valid = false;
    glm::vec3 dir{0.0f, 0.0f, -1.0f};  // cyclopean direction, head space
    double t_s = 0.0;                  // sample time, seconds on the runtime clock
};

struct Session final : Object {
    Session() : Object(ObjectType::Session) {}
    Instance* instance = nullptr;
    // Session state, under frameMutex.
    XrSessionState state = XR_SESSION_STATE_UNKNOWN;
    bool running = false;
    bool stopRequested = false;  // by the application or after `frames`
    XrViewConfigurationType viewConfiguration = XR_VIEW_CONFIGURATION_TYPE_PRIMARY_STEREO;  // xrBeginSession's

    // Under gpuMutex.
    std::mutex gpuMutex;
    std::unique_ptr<vk::Context> context;
    std::unique_ptr<Compositor> compositor;
    std::unique_ptr<QuadPass> quads;
    std::unique_ptr<XrWindow> window;
    std::vector<std::unique_ptr<Swapchain>> swapchains;
    VkFence frameFence = VK_NULL_HANDLE;  // signalled when all of a frame's GPU work is done
    std::unique_ptr<eval::SequenceWriter> recorder;
    bool recordingStopped = false;
    uint64_t vergenceFromDepth = 0;  // frames whose fixated point came from the depth
    std::set<int> refusalsLogged;

    // Under gazeMutex.
    std::mutex gazeMutex;
    std::unique_ptr<gaze::GazeSource> gazeSource;
    std::array<layers::EyeGaze, 2> lastGaze{};  // the last frame's, for the mouse

    // Under the instance's mutex.
    std::vector<std::unique_ptr<Space>> spaces;
    std::vector<ActionSet*> attachedSets;
    bool eyeGazeBound = false;    // an attached pose action is bound to the eye-gaze pose
    bool eyeGazeCurrent = false;  // ... and the eye-gaze profile became current (at an xrSyncActions)
    bool synced = false;        // xrSyncActions ran while focused

    // Frame loop, under frameMutex.
    mutable std::mutex frameMutex;
    std::condition_variable frameCv;  // a frame completed, a frame was handed over or begun, shutdown
    XrTime nextDisplayTime = 0;
    XrTime lastDisplayTime = 0;  // of the last frame waited (realtime pacing)
    uint32_t waited = 0;  // xrWaitFrame returns not yet matched by xrBeginFrame
    bool begun = false;
    std::deque<XrTime> waitedDisplayTimes;  // of the frames waited and not yet begun, oldest first
    XrTime frameDisplayTime = 0;            // predicted display time of the begun frame
    uint64_t framesEnded = 0, framesComposited = 0, framesPassed = 0, framesRefused = 0, framesDiscarded = 0;
    uint64_t pipelinesMade = 0;  ///< FrameStats::pipelinesMade over the composited frames
    double pipelineMs = 0.0;
    // The compositor thread: frames are numbered from 1 as they are handed over; at most one is in
    // flight (handed over and not completed).
    uint64_t framesHandedOver = 0, framesCompleted = 0;
    XrTime handedOverAt = 0;      // when the frame in flight was handed over
    XrDuration compositeNs = 0;   // how long the last frames took from hand-over to completion (smoothed)
    XrDuration compositeTotalNs = 0;  // summed over the session's frames
    bool holdFrames = false;      // test hook (WRSFOV_XR_TEST_HOLD_FRAMES): completion waits for a waiter
    bool holdOpen = false;        // a call is waiting for the frame in flight
    bool shutdown = false;        // the compositor thread stops
    std::thread compositorThread;
};

struct Instance final : Object {
    Instance() : Object(ObjectType::Instance) {}
    RuntimeConfig config;
    std::set<std::string> extensions;
    std::string applicationName;
    XrTime epoch = 0;  // the runtime clock's zero (instance creation)
    // pace = free: the last display time handed out. A session's first frame is one period after it
    // (after the epoch for the first session), not after the wall clock, so that a free-paced run
    // sees the same display times, head poses and gaze whatever the machine's speed.
    mutable std::atomic<XrTime> freeDisplayTime{0};

    std::recursive_mutex mutex;  // the instance's state (see the top of this file)

    std::vector<std::string> paths;  // XrPath i + 1
    std::unordered_map<std::string, XrPath> pathIds;

    std::mutex eventMutex;  // the event queue
    std::deque<XrEventDataBuffer> events;
    bool eventsLost = false;
    uint32_t lostCount = 0;

    bool window = false;                       // a window will be made (output, display, GLFW)
    std::vector<std::string> windowExtensions;  // the instance extensions its surface needs
    bool graphicsRequirementsQueried = false;
    VkPhysicalDevice graphicsDevice = VK_NULL_HANDLE;  // what xrGetVulkanGraphicsDevice*KHR returned
    VkInstance vkInstance = VK_NULL_HANDLE;            // made by xrCreateVulkanInstanceKHR
    VkDebugUtilsMessengerEXT messenger = VK_NULL_HANDLE;
    std::atomic<uint32_t> vkErrors{0}, vkWarnings{0};

    std::vector<std::unique_ptr<Session>> sessions;
    std::vector<std::unique_ptr<ActionSet>> actionSets;
    // Suggested bindings per interaction profile (the last suggestion of a profile replaces the earlier).
    std::map<XrPath, std::vector<XrActionSuggestedBinding>> suggested;

    bool enabled(const char* ext) const { return extensions.count(ext) != 0; }
    XrPath path(const std::string& s);  // interns a well-formed path
    std::string pathString(XrPath p) const;
    void pushEvent(const XrEventDataBuffer& e);
    double seconds(XrTime t) const { return double(t - epoch) * 1e-9; }
};

// ---- Registry and logging ----
void registerObject(Object* o);
void unregisterObject(Object* o);
/// The live object of type T behind a handle, or nullptr.
Object* findObject(const void* handle, ObjectType type);
template <typename T, typename H>
T* lookup(H handle, ObjectType type) {
    return static_cast<T*>(findObject(reinterpret_cast<const void*>(handle), type));
}
/// One line on stderr, prefixed "[wrsfov-xr] ".
void logLine(const std::string& line);
XrTime nowXrTime();

// ---- Entry points shared between the files (the dispatch table lives in xr_runtime.cpp) ----
/// Ends and frees a session and everything it owns (xrDestroySession, xrDestroyInstance).
XrResult destroySession(Session* s);
/// Destroys the validation messenger of xrCreateVulkanInstanceKHR, if any (xrDestroyInstance).
void destroyMessenger(Instance* inst);

// Instance, system, events and view configurations, implemented in xr_api_instance.cpp.
XRAPI_ATTR XrResult XRAPI_CALL xrEnumerateInstanceExtensionProperties(const char*, uint32_t, uint32_t*,
                                                                      XrExtensionProperties*);
XRAPI_ATTR XrResult XRAPI_CALL xrEnumerateApiLayerProperties(uint32_t, uint32_t*, XrApiLayerProperties*);
XRAPI_ATTR XrResult XRAPI_CALL xrCreateInstance(const XrInstanceCreateInfo*, XrInstance*);
XRAPI_ATTR XrResult XRAPI_CALL xrDestroyInstance(XrInstance);
XRAPI_ATTR XrResult XRAPI_CALL xrGetInstanceProperties(XrInstance, XrInstanceProperties*);
XRAPI_ATTR XrResult XRAPI_CALL xrPollEvent(XrInstance, XrEventDataBuffer*);
XRAPI_ATTR XrResult XRAPI_CALL xrResultToString(XrInstance, XrResult, char[XR_MAX_RESULT_STRING_SIZE]);
XRAPI_ATTR XrResult XRAPI_CALL xrStructureTypeToString(XrInstance, XrStructureType, char[XR_MAX_STRUCTURE_NAME_SIZE]);
XRAPI_ATTR XrResult XRAPI_CALL xrGetSystem(XrInstance, const XrSystemGetInfo*, XrSystemId*);
XRAPI_ATTR XrResult XRAPI_CALL xrGetSystemProperties(XrInstance, XrSystemId, XrSystemProperties*);
XRAPI_ATTR XrResult XRAPI_CALL xrEnumerateEnvironmentBlendModes(XrInstance, XrSystemId, XrViewConfigurationType,
                                                                uint32_t, uint32_t*, XrEnvironmentBlendMode*);
XRAPI_ATTR XrResult XRAPI_CALL xrEnumerateViewConfigurations(XrInstance, XrSystemId, uint32_t, uint32_t*,
                                                             XrViewConfigurationType*);
XRAPI_ATTR XrResult XRAPI_CALL xrGetViewConfigurationProperties(XrInstance, XrSystemId, XrViewConfigurationType,
                                                                XrViewConfigurationProperties*);
XRAPI_ATTR XrResult XRAPI_CALL xrEnumerateViewConfigurationViews(XrInstance, XrSystemId, XrViewConfigurationType,
                                                                 uint32_t, uint32_t*, XrViewConfigurationView*);
// Paths, implemented in xr_api_paths.cpp.
XRAPI_ATTR XrResult XRAPI_CALL xrStringToPath(XrInstance, const char*, XrPath*);
XRAPI_ATTR XrResult XRAPI_CALL xrPathToString(XrInstance, XrPath, uint32_t, uint32_t*, char*);
// XR_KHR_vulkan_enable and XR_KHR_vulkan_enable2, implemented in xr_api_vulkan.cpp.
XRAPI_ATTR XrResult XRAPI_CALL xrGetVulkanGraphicsRequirementsKHR(XrInstance, XrSystemId,
                                                                  XrGraphicsRequirementsVulkanKHR*);
XRAPI_ATTR XrResult XRAPI_CALL xrGetVulkanGraphicsRequirements2KHR(XrInstance, XrSystemId,
                                                                   XrGraphicsRequirementsVulkanKHR*);
XRAPI_ATTR XrResult XRAPI_CALL xrGetVulkanGraphicsDeviceKHR(XrInstance, XrSystemId, VkInstance, VkPhysicalDevice*);
XRAPI_ATTR XrResult XRAPI_CALL xrGetVulkanGraphicsDevice2KHR(XrInstance, const XrVulkanGraphicsDeviceGetInfoKHR*,
                                                             VkPhysicalDevice*);
XRAPI_ATTR XrResult XRAPI_CALL xrGetVulkanInstanceExtensionsKHR(XrInstance, XrSystemId, uint32_t, uint32_t*, char*);
XRAPI_ATTR XrResult XRAPI_CALL xrGetVulkanDeviceExtensionsKHR(XrInstance, XrSystemId, uint32_t, uint32_t*, char*);
XRAPI_ATTR XrResult XRAPI_CALL xrCreateVulkanInstanceKHR(XrInstance, const XrVulkanInstanceCreateInfoKHR*, VkInstance*,
                                                         VkResult*);
XRAPI_ATTR XrResult XRAPI_CALL xrCreateVulkanDeviceKHR(XrInstance, const XrVulkanDeviceCreateInfoKHR*, VkDevice*,
                                                       VkResult*);
// The action system, implemented in xr_api_actions.cpp.
XRAPI_ATTR XrResult XRAPI_CALL xrCreateActionSet(XrInstance, const XrActionSetCreateInfo*, XrActionSet*);
XRAPI_ATTR XrResult XRAPI_CALL xrDestroyActionSet(XrActionSet);
XRAPI_ATTR XrResult XRAPI_CALL xrCreateAction(XrActionSet, const XrActionCreateInfo*, XrAction*);
XRAPI_ATTR XrResult XRAPI_CALL xrDestroyAction(XrAction);
XRAPI_ATTR XrResult XRAPI_CALL xrSuggestInteractionProfileBindings(XrInstance,
                                                                   const XrInteractionProfileSuggestedBinding*);
XRAPI_ATTR XrResult XRAPI_CALL xrAttachSessionActionSets(XrSession, const XrSessionActionSetsAttachInfo*);
XRAPI_ATTR XrResult XRAPI_CALL xrGetCurrentInteractionProfile(XrSession, XrPath, XrInteractionProfileState*);
XRAPI_ATTR XrResult XRAPI_CALL xrSyncActions(XrSession, const XrActionsSyncInfo*);
XRAPI_ATTR XrResult XRAPI_CALL xrGetActionStateBoolean(XrSession, const XrActionStateGetInfo*, XrActionStateBoolean*);
XRAPI_ATTR XrResult XRAPI_CALL xrGetActionStateFloat(XrSession, const XrActionStateGetInfo*, XrActionStateFloat*);
XRAPI_ATTR XrResult XRAPI_CALL xrGetActionStateVector2f(XrSession, const XrActionStateGetInfo*, XrActionStateVector2f*);
XRAPI_ATTR XrResult XRAPI_CALL xrGetActionStatePose(XrSession, const XrActionStateGetInfo*, XrActionStatePose*);
XRAPI_ATTR XrResult XRAPI_CALL xrEnumerateBoundSourcesForAction(XrSession, const XrBoundSourcesForActionEnumerateInfo*,
                                                                uint32_t, uint32_t*, XrPath*);
XRAPI_ATTR XrResult XRAPI_CALL xrGetInputSourceLocalizedName(XrSession, const XrInputSourceLocalizedNameGetInfo*,
                                                             uint32_t, uint32_t*, char*);
XRAPI_ATTR XrResult XRAPI_CALL xrApplyHapticFeedback(XrSession, const XrHapticActionInfo*, const XrHapticBaseHeader*);
XRAPI_ATTR XrResult XRAPI_CALL xrStopHapticFeedback(XrSession, const XrHapticActionInfo*);

// Session-level calls, implemented in xr_session.cpp.
XRAPI_ATTR XrResult XRAPI_CALL xrCreateSession(XrInstance, const XrSessionCreateInfo*, XrSession*);
XRAPI_ATTR XrResult XRAPI_CALL xrDestroySession(XrSession);
XRAPI_ATTR XrResult XRAPI_CALL xrBeginSession(XrSession, const XrSessionBeginInfo*);
XRAPI_ATTR XrResult XRAPI_CALL xrEndSession(XrSession);
XRAPI_ATTR XrResult XRAPI_CALL xrRequestExitSession(XrSession);
XRAPI_ATTR XrResult XRAPI_CALL xrEnumerateReferenceSpaces(XrSession, uint32_t, uint32_t*, XrReferenceSpaceType*);
XRAPI_ATTR XrResult XRAPI_CALL xrCreateReferenceSpace(XrSession, const XrReferenceSpaceCreateInfo*, XrSpace*);
XRAPI_ATTR XrResult XRAPI_CALL xrGetReferenceSpaceBoundsRect(XrSession, XrReferenceSpaceType, XrExtent2Df*);
XRAPI_ATTR XrResult XRAPI_CALL xrCreateActionSpace(XrSession, const XrActionSpaceCreateInfo*, XrSpace*);
XRAPI_ATTR XrResult XRAPI_CALL xrLocateSpace(XrSpace, XrSpace, XrTime, XrSpaceLocation*);
XRAPI_ATTR XrResult XRAPI_CALL xrDestroySpace(XrSpace);
XRAPI_ATTR XrResult XRAPI_CALL xrEnumerateSwapchainFormats(XrSession, uint32_t, uint32_t*, int64_t*);
XRAPI_ATTR XrResult XRAPI_CALL xrCreateSwapchain(XrSession, const XrSwapchainCreateInfo*, XrSwapchain*);
XRAPI_ATTR XrResult XRAPI_CALL xrDestroySwapchain(XrSwapchain);
XRAPI_ATTR XrResult XRAPI_CALL xrEnumerateSwapchainImages(XrSwapchain, uint32_t, uint32_t*,
                                                          XrSwapchainImageBaseHeader*);
XRAPI_ATTR XrResult XRAPI_CALL xrAcquireSwapchainImage(XrSwapchain, const XrSwapchainImageAcquireInfo*, uint32_t*);
XRAPI_ATTR XrResult XRAPI_CALL xrWaitSwapchainImage(XrSwapchain, const XrSwapchainImageWaitInfo*);
XRAPI_ATTR XrResult XRAPI_CALL xrReleaseSwapchainImage(XrSwapchain, const XrSwapchainImageReleaseInfo*);
XRAPI_ATTR XrResult XRAPI_CALL xrWaitFrame(XrSession, const XrFrameWaitInfo*, XrFrameState*);
XRAPI_ATTR XrResult XRAPI_CALL xrBeginFrame(XrSession, const XrFrameBeginInfo*);
XRAPI_ATTR XrResult XRAPI_CALL xrEndFrame(XrSession, const XrFrameEndInfo*);
XRAPI_ATTR XrResult XRAPI_CALL xrLocateViews(XrSession, const XrViewLocateInfo*, XrViewState*, uint32_t, uint32_t*,
                                             XrView*);
// Shared with the action calls.
/// Pose of a space in stage coordinates at `time`; false where it cannot be located.
bool spacePose(const Space& space, XrTime time, Pose& out, GazeState* gaze = nullptr);
GazeState gazeAt(Session& s, XrTime time);
/// Whether `action` is bound to the eye-gaze pose in the session's current interaction profile.
bool boundToEyeGaze(const Session& s, const Action* action);
/// A call's subaction path: XR_NULL_PATH or one the action was created with; PATH_INVALID for a
/// value that is no path of the instance (never made by xrStringToPath), PATH_UNSUPPORTED for another.
XrResult checkSubaction(const Action& a, XrPath subaction);
bool sessionFocused(const Session& s);

/// Primary stereo, and primary quad (XR_VARJO_quad_views) where the instance enabled that extension,
/// are the view configurations; primary mono, the other one OpenXR 1.0 defines, is
/// VIEW_CONFIGURATION_TYPE_UNSUPPORTED. Any other value is not a valid enum for the application: an
/// extension's that it did not enable (quad views without XR_VARJO_quad_views, the first-person
/// observer, which is not offered), and OpenXR 1.1's stereo with foveated inset (the quad views'
/// value) is not 1.0: VALIDATION_FAILURE, as the conformance suite prefers for a value whose extension
/// is not enabled.
inline XrResult checkViewConfiguration(const Instance& inst, XrViewConfigurationType t) {
    if (t == XR_VIEW_CONFIGURATION_TYPE_PRIMARY_STEREO) return XR_SUCCESS;
    if (t == XR_VIEW_CONFIGURATION_TYPE_PRIMARY_QUAD_VARJO && inst.enabled(XR_VARJO_QUAD_VIEWS_EXTENSION_NAME))
        return XR_SUCCESS;
    if (t == XR_VIEW_CONFIGURATION_TYPE_PRIMARY_MONO) return XR_ERROR_VIEW_CONFIGURATION_TYPE_UNSUPPORTED;
    return XR_ERROR_VALIDATION_FAILURE;
}
/// The number of views of a view configuration checkViewConfiguration accepts.
inline uint32_t viewCount(XrViewConfigurationType t) {
    return t == XR_VIEW_CONFIGURATION_TYPE_PRIMARY_QUAD_VARJO ? 4 : 2;
}
/// The name the specification gives a result, or nullptr for a value our headers do not know.
const char* resultName(XrResult r);

// Two-call idiom: capacity 0 asks for the count.
template <typename T>
XrResult fillArray(uint32_t capacity, uint32_t* countOutput, T* out, const std::vector<T>& values) {
    if (!countOutput) return XR_ERROR_VALIDATION_FAILURE;
    *countOutput = uint32_t(values.size());
    if (capacity == 0) return XR_SUCCESS;
    if (capacity < values.size()) return XR_ERROR_SIZE_INSUFFICIENT;
    if (!out) return XR_ERROR_VALIDATION_FAILURE;
    for (std::size_t i = 0; i < values.size(); ++i) out[i] = values[i];
    return XR_SUCCESS;
}
XrResult fillString(uint32_t capacity, uint32_t* countOutput, char* out, const std::string& value);

}  // namespace wrsfov::xr
