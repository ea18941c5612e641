// The runtime's session-level half: session state machine, simulated head and eyes, reference
// and action spaces, swapchains on the application's device, frame timing, xrEndFrame's checks,
// composition through the wrsfov compositor, and recording.
#include <chrono>
#include <cmath>
#include <cstring>
#include <thread>

#define GLM_ENABLE_EXPERIMENTAL
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtx/quaternion.hpp>

#include "compositor/host_app.h"
#include "compositor/input.h"
#include "compositor/reference.h"
#include "compositor/swapchain_vk.h"
#include "gaze/frame_gaze.h"
#include "preview/gaze_input.h"
#include "scenes/png.h"

#include <opencv2/imgcodecs.hpp>
#include "xr_common/xr_frame.h"
#include "xr_common/xr_inset.h"
#include "runtime/xr_objects.h"
#include "runtime/xr_verify.h"

namespace wrsfov::xr {

namespace {

constexpr float kStandingHeight = 1.6f;  // LOCAL's origin above STAGE's (scenes::HeadPose)
constexpr uint32_t kMaxSize = 8192;

/// With the session's frameMutex held.
void setState(Session* s, XrSessionState state) {
    s->state = state;
    XrEventDataBuffer e{XR_TYPE_EVENT_DATA_BUFFER};
    auto* c = reinterpret_cast<XrEventDataSessionStateChanged*>(&e);
    c->type = XR_TYPE_EVENT_DATA_SESSION_STATE_CHANGED;
    c->next = nullptr;
    c->session = reinterpret_cast<XrSession>(s);
    c->state = state;
    c->time = nowXrTime();
    s->instance->pushEvent(e);
    if (s->instance->config.verbose) logLine("session state " + std::to_string(int(state)));
}

/// Walks the states down to STOPPING (FOCUSED -> VISIBLE -> SYNCHRONIZED -> STOPPING); with the
/// session's frameMutex held.
void beginStopping(Session* s) {
    if (s->stopRequested) return;
    s->stopRequested = true;
    if (s->state == XR_SESSION_STATE_FOCUSED) setState(s, XR_SESSION_STATE_VISIBLE);
    if (s->state == XR_SESSION_STATE_VISIBLE) setState(s, XR_SESSION_STATE_SYNCHRONIZED);
    if (s->state == XR_SESSION_STATE_READY) setState(s, XR_SESSION_STATE_SYNCHRONIZED);
    setState(s, XR_SESSION_STATE_STOPPING);
}

XrDuration period(const Instance& inst) { return XrDuration(std::llround(1e9 / inst.config.displayHz)); }

Pose headAt(const Session& s, XrTime t) {
    const scenes::HeadPose h = scenes::headPose(s.instance->config.head, s.instance->seconds(t));
    return {glm::angleAxis(h.yaw, glm::vec3(0, 1, 0)), h.position};
}

Pose eyeAt(const Session& s, XrTime t, int eye) {
    return headAt(s, t) * Pose{glm::quat(1, 0, 0, 0), {(eye == 0 ? -0.5f : 0.5f) * s.instance->config.ipd_m, 0, 0}};
}

/// Rotation taking -Z to `dir` (unit).
glm::quat lookRotation(const glm::vec3& dir) { return glm::rotation(glm::vec3(0, 0, -1), glm::normalize(dir)); }

/// Where the left eye's ray towards `target` (head space) meets the submitted depth: the fixated
/// point, or nullopt without depth there (no depth, off the image, or an unknown depth value).
std::optional<glm::vec3> depthAlong(const Session& s, const layers::ProjectionView& left, const glm::vec3& target) {
    if (!left.depth) return std::nullopt;
    const RuntimeConfig& c = s.instance->config;
    const glm::vec3 eye(-0.5f * c.ipd_m, 0.0f, 0.0f);
    const glm::vec3 d = glm::normalize(target - eye);
    if (!(d.z < -1e-3f)) return std::nullopt;
    const layers::Fov& f = left.fov;
    const float tl = std::tan(f.angleLeft), tr = std::tan(f.angleRight), tu = std::tan(f.angleUp),
                td = std::tan(f.angleDown);
    const layers::SubImage& sub = left.depth->subImage;
    const float u = (d.x / -d.z - tl) / (tr - tl), v = (tu - d.y / -d.z) / (tu - td);
    if (!(u >= 0.0f && u < 1.0f && v >= 0.0f && v < 1.0f)) return std::nullopt;
    auto* sc = static_cast<VulkanSwapchain*>(sub.swapchain);
    auto texel = sc->readTexel(uint32_t(sc->lastReleased()), sub.arrayIndex,
                               uint32_t(sub.rect.x) + uint32_t(u * float(sub.rect.width)),
                               uint32_t(sub.rect.y) + uint32_t(v * float(sub.rect.height)));
    if (!texel || texel->size() != 4) return std::nullopt;
    float value;
    std::memcpy(&value, texel->data(), 4);
    // The compositor's own linearisation (shaders/wrs_common.h): 0 means unknown.
    const float z = gpu::wrs_linear_depth(value, left.depth->nearZ, left.depth->farZ, left.depth->reversedZ);
    if (!(z > 0.0f)) return std::nullopt;
    return eye + d * (z / -d.z);
}

/// Both eyes' gaze for a frame shown at `t`, in each eye's space. The generator is cyclopean: both
/// eyes turn to one point (binocular vergence, so the left and right directions differ as in a real
/// HMD): where the left eye's ray along the generator's direction meets the submitted depth, or
/// `vergence_distance` along that direction without depth. A file or a tracker gives each eye as
/// measured; the mouse gives each eye the ray through the cursor's pixel.
std::array<layers::EyeGaze, 2> frameGaze(Session& s, XrTime t, const layers::ProjectionView& left) {
    const RuntimeConfig& c = s.instance->config;
    if (c.gaze == GazeKind::Mouse) {
        if (!s.window) return {};
        const layers::Fov fov[2] = {c.fov[0], c.fov[1]};
        return preview::gazeFromCursor(fov, c.width, c.height, s.window->cursor());
    }
    std::array<layers::EyeGaze, 2> g;
    {
        std::lock_guard lock(s.gazeMutex);
        g = gaze::frame_gaze(s.gazeSource.get(), s.instance->seconds(t));
    }
    if (c.gaze != GazeKind::Generator || !g[0].valid) return g;
    glm::vec3 fixated = glm::normalize(g[0].dir) * c.vergenceDistance_m;
    if (auto p = depthAlong(s, left, fixated)) {
        fixated = *p;
        ++s.vergenceFromDepth;
    }
    for (int e = 0; e < 2; ++e) {
        if (!g[e].valid) continue;
        const glm::vec3 eyePos((e == 0 ? -0.5f : 0.5f) * c.ipd_m, 0.0f, 0.0f);
        g[e].dir = glm::normalize(fixated - eyePos);
    }
    return g;
}

/// The gaze xrLocateViews puts the insets on: frameGaze's without depth (the frame is not rendered
/// yet), or with the mouse the last frame's (the window is xrEndFrame's).
std::array<layers::EyeGaze, 2> locateGaze(Session& s, XrTime t) {
    if (s.instance->config.gaze == GazeKind::Mouse) {
        std::lock_guard lock(s.gazeMutex);
        return s.lastGaze;
    }
    return frameGaze(s, t, layers::ProjectionView{});
}

}  // namespace

bool boundToEyeGaze(const Session& s, const Action* a) {
    if (!s.eyeGazeCurrent || !a || a->actionType != XR_ACTION_TYPE_POSE_INPUT) return false;
    const Instance& inst = *s.instance;
    auto profile = inst.pathIds.find("/interaction_profiles/ext/eye_gaze_interaction");
    if (profile == inst.pathIds.end()) return false;
    auto it = inst.suggested.find(profile->second);
    if (it == inst.suggested.end()) return false;
    for (const auto& b : it->second)
        if (reinterpret_cast<const Action*>(b.action) == a) return true;
    return false;
}

GazeState gazeAt(Session& s, XrTime time) {
    GazeState out;
    const double t = s.instance->seconds(time);
    gaze::GazeSample sample;
    sample.t_s = t;
    std::unique_lock lock(s.gazeMutex);
    if (s.instance->config.gaze == GazeKind::Mouse) {  // the cursor of the last frame shown
        for (int e = 0; e < 2; ++e) sample.eye[e] = {s.lastGaze[e].dir, s.lastGaze[e].valid, s.lastGaze[e].confidence};
    } else if (s.gazeSource) {
        sample = s.gazeSource->sample(t);
    } else {
        return out;
    }
    lock.unlock();
    glm::vec3 sum(0.0f);
    for (const auto& e : sample.eye)
        if (e.valid && std::isfinite(e.dir.x) && std::isfinite(e.dir.y) && std::isfinite(e.dir.z) &&
            glm::length(e.dir) > 0.0f)
            sum += glm::normalize(e.dir);
    if (glm::length(sum) <= 0.0f) return out;
    out.valid = true;
    out.dir = glm::normalize(sum);
    out.t_s = std::isfinite(sample.t_s) ? sample.t_s : t;
    return out;
}

bool sessionFocused(const Session& s) {
    std::lock_guard lock(s.frameMutex);
    return s.running && s.state == XR_SESSION_STATE_FOCUSED;
}

bool spacePose(const Space& space, XrTime time, Pose& out, GazeState* gazeOut) {
    Session& s = *space.session;
    if (space.isAction) {
        if (!s.synced || !boundToEyeGaze(s, space.action)) return false;
        const GazeState g = gazeAt(s, time);
        if (!g.valid) return false;
        if (gazeOut) *gazeOut = g;
        out = headAt(s, time) * Pose{lookRotation(g.dir), glm::vec3(0.0f)} * space.poseInSpace;
        return true;
    }
    switch (space.reference) {
        case XR_REFERENCE_SPACE_TYPE_VIEW:
            out = headAt(s, time) * space.poseInSpace;
            return true;
        case XR_REFERENCE_SPACE_TYPE_LOCAL:
            out = Pose{glm::quat(1, 0, 0, 0), {0, kStandingHeight, 0}} * space.poseInSpace;
            return true;
        case XR_REFERENCE_SPACE_TYPE_COMBINED_EYE_VARJO: {
            // The rendering gaze: between the eyes, looking along the cyclopean gaze; straight ahead
            // while the gaze is invalid (xrLocateSpace then clears the orientation's tracked bit).
            const GazeState g = gazeAt(s, time);
            if (gazeOut) *gazeOut = g;
            out = headAt(s, time) * Pose{g.valid ? lookRotation(g.dir) : glm::quat(1, 0, 0, 0), glm::vec3(0.0f)} *
                  space.poseInSpace;
            return true;
        }
        default:
            out = space.poseInSpace;  // STAGE: the world frame
            return true;
    }
}

// ---------------------------------------------------------------------------------------------
// The compositor thread

namespace {

/// The session's compositor thread: waits for each frame's GPU work (the passes, the quads, the
/// window's copy) and marks the frame complete, which frees the swapchain images it read and lets
/// xrWaitFrame hand out the next frame. It makes no other Vulkan call and never touches the queue.
void compositorThread(Session* s) {
    const VkDevice device = s->context->device();
    std::unique_lock lock(s->frameMutex);
    for (;;) {
        s->frameCv.wait(lock, [s] { return s->shutdown || s->framesHandedOver > s->framesCompleted; });
        if (s->framesHandedOver == s->framesCompleted) return;  // shut down, nothing in flight
        const uint64_t frame = s->framesHandedOver;
        const VkFence fence = s->frameFence;
        lock.unlock();
        const VkResult r = vkWaitForFences(device, 1, &fence, VK_TRUE, UINT64_MAX);
        lock.lock();
        if (r != VK_SUCCESS)  // a lost device: the frame still completes
            logLine(std::string("compositor thread: waiting for frame ") + std::to_string(frame) + ": " +
                    vk::resultString(r));
        if (s->holdFrames) s->frameCv.wait(lock, [s] { return s->holdOpen || s->shutdown; });
        s->holdOpen = false;
        const XrDuration took = nowXrTime() - s->handedOverAt;
        s->compositeNs = s->compositeNs == 0 ? took : (7 * s->compositeNs + took) / 8;
        s->compositeTotalNs += took;
        s->framesCompleted = frame;
        s->frameCv.notify_all();
    }
}

/// With the session's frameMutex held (by `lock`): waits until frame `serial` is complete, at most
/// `timeout` (XR_INFINITE_DURATION: no limit). False when the time ran out. A wait of no time only
/// looks (and so never opens a held frame, see Session::holdFrames).
bool waitForFrame(Session* s, std::unique_lock<std::mutex>& lock, uint64_t serial, XrDuration timeout) {
    auto done = [s, serial] { return s->framesCompleted >= serial; };
    if (done()) return true;
    if (timeout <= 0) return false;
    s->holdOpen = true;
    s->frameCv.notify_all();
    if (timeout == XR_INFINITE_DURATION) {
        s->frameCv.wait(lock, done);
        return true;
    }
    return s->frameCv.wait_for(lock, std::chrono::nanoseconds(timeout), done);
}

}  // namespace

// ---------------------------------------------------------------------------------------------
// Session

XrResult destroySession(Session* s) {
    Instance* inst = s->instance;
    // The frame in flight first: its GPU work must be done before anything it reads goes.
    if (s->compositorThread.joinable()) {
        {
            std::unique_lock lock(s->frameMutex);
            waitForFrame(s, lock, s->framesHandedOver, XR_INFINITE_DURATION);
            s->shutdown = true;
            s->frameCv.notify_all();
        }
        s->compositorThread.join();
    }
    std::unique_lock gpu(s->gpuMutex);
    if (s->compositor) (void)s->compositor->waitFrame();
    if (s->recorder) {
        if (Status st = s->recorder->close(); !st) logLine("recording: " + st.message());
        else logLine("recorded " + std::to_string(s->recorder->written()) + " frames to " + inst->config.record);
        s->recorder.reset();
    }
    std::unique_lock frameLock(s->frameMutex);
    logLine("session ended: " + std::to_string(s->framesEnded) + " frames ended, " +
            std::to_string(s->framesComposited) + " composited, " + std::to_string(s->framesPassed) +
            " shown as submitted, " + std::to_string(s->framesRefused) +
            " not composited, " + std::to_string(s->framesDiscarded) + " discarded, vergence from depth in " +
            std::to_string(s->vergenceFromDepth) + "; compositor " +
            (s->framesCompleted ? std::to_string(double(s->compositeTotalNs) * 1e-6 / double(s->framesCompleted))
                                : std::string("-")) +
            " ms per frame from xrEndFrame to completion; pipelines made while compositing " +
            std::to_string(s->pipelinesMade) + " (" + std::to_string(s->pipelineMs) + " ms, the first frames' hitch)" +
            "; Vulkan validation: " +
            std::to_string(inst->vkErrors.load()) + " errors, " + std::to_string(inst->vkWarnings.load()) +
            " warnings" + (inst->messenger ? "" : " (not counted: validation off or the application's instance)"));
    frameLock.unlock();
    for (auto& sc : s->swapchains) unregisterObject(sc.get());
    for (auto& sp : s->spaces) unregisterObject(sp.get());
    s->swapchains.clear();
    s->spaces.clear();
    if (s->window && !inst->config.screenshot.empty()) {
        auto img = s->window->lastImage();
        if (!img) logLine("screenshot: " + img.error().message);
        else if (!cv::imwrite(inst->config.screenshot, *img)) logLine("screenshot: cannot write " + inst->config.screenshot);
        else logLine("screenshot written to " + inst->config.screenshot);
    }
    s->window.reset();
    s->quads.reset();
    s->compositor.reset();
    if (s->frameFence) vkDestroyFence(s->context->device(), s->frameFence, nullptr);
    s->frameFence = VK_NULL_HANDLE;
    s->context.reset();
    gpu.unlock();
    unregisterObject(s);
    // Events of the session still queued go with it: an application must never receive a handle it
    // has destroyed (a later session may even reuse the address).
    const XrSession handle = reinterpret_cast<XrSession>(s);
    std::unique_lock events(inst->eventMutex);
    std::erase_if(inst->events, [handle](const XrEventDataBuffer& e) {
        switch (e.type) {
            case XR_TYPE_EVENT_DATA_SESSION_STATE_CHANGED:
                return reinterpret_cast<const XrEventDataSessionStateChanged&>(e).session == handle;
            case XR_TYPE_EVENT_DATA_INTERACTION_PROFILE_CHANGED:
                return reinterpret_cast<const XrEventDataInteractionProfileChanged&>(e).session == handle;
            case XR_TYPE_EVENT_DATA_REFERENCE_SPACE_CHANGE_PENDING:
                return reinterpret_cast<const XrEventDataReferenceSpaceChangePending&>(e).session == handle;
            default:
                return false;
        }
    });
    events.unlock();
    // The messenger goes with the session: the application may destroy its VkInstance right after.
    if (inst->messenger) {
        auto fn = reinterpret_cast<PFN_vkDestroyDebugUtilsMessengerEXT>(
            vkGetInstanceProcAddr(inst->vkInstance, "vkDestroyDebugUtilsMessengerEXT"));
        if (fn) fn(inst->vkInstance, inst->messenger, nullptr);
        inst->messenger = VK_NULL_HANDLE;
    }
    for (auto it = inst->sessions.begin(); it != inst->sessions.end(); ++it)
        if (it->get() == s) {
            inst->sessions.erase(it);
            break;
        }
    return XR_SUCCESS;
}

XRAPI_ATTR XrResult XRAPI_CALL xrCreateSession(XrInstance h, const XrSessionCreateInfo* info, XrSession* out) {
    std::lock_guard lock(stateMutex(h));
    Instance* inst = getInstance(h);
    if (!inst) return XR_ERROR_HANDLE_INVALID;
    if (!info || !out || info->type != XR_TYPE_SESSION_CREATE_INFO || info->createFlags != 0)
        return XR_ERROR_VALIDATION_FAILURE;
    if (info->systemId != 1) return XR_ERROR_SYSTEM_INVALID;
    auto* binding = reinterpret_cast<const XrGraphicsBindingVulkanKHR*>(
        findNext(info->next, XR_TYPE_GRAPHICS_BINDING_VULKAN_KHR));
    if (!binding) return XR_ERROR_GRAPHICS_DEVICE_INVALID;  // only Vulkan sessions
    if (!inst->graphicsRequirementsQueried) return XR_ERROR_GRAPHICS_REQUIREMENTS_CALL_MISSING;
    if (!binding->instance || !binding->physicalDevice || !binding->device ||
        binding->physicalDevice != inst->graphicsDevice)
        return XR_ERROR_GRAPHICS_DEVICE_INVALID;
    if (!inst->sessions.empty()) return XR_ERROR_LIMIT_REACHED;  // one HMD, one session

    auto s = std::make_unique<Session>();
    s->instance = inst;
    vk::AdoptedDevice dev{binding->instance, binding->physicalDevice, binding->device, binding->queueFamilyIndex,
                          binding->queueIndex};
    auto ctx = vk::Context::adopt(dev);
    if (!ctx) {
        logLine("session: " + ctx.error().message);
        return XR_ERROR_GRAPHICS_DEVICE_INVALID;
    }
    s->context = std::move(*ctx);
    auto comp = Compositor::create(*s->context, inst->config.compositor);
    if (!comp) {
        logLine("session: compositor: " + comp.error().message);
        return XR_ERROR_RUNTIME_FAILURE;
    }
    s->compositor = std::move(*comp);
    auto quads = QuadPass::create(*s->context);
    if (!quads) {
        logLine("session: quad layers: " + quads.error().message);
        return XR_ERROR_RUNTIME_FAILURE;
    }
    s->quads = std::move(*quads);
    VkFenceCreateInfo fci{VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
    if (VkResult r = vkCreateFence(s->context->device(), &fci, nullptr, &s->frameFence); r != VK_SUCCESS) {
        logLine(std::string("session: vkCreateFence: ") + vk::resultString(r));
        return XR_ERROR_RUNTIME_FAILURE;
    }
    // Test hook: each frame's completion waits until a call waits for it (see Session::holdFrames).
    if (const char* hold = std::getenv("WRSFOV_XR_TEST_HOLD_FRAMES"); hold && std::strcmp(hold, "1") == 0)
        s->holdFrames = true;

    const RuntimeConfig& c = inst->config;
    if (inst->window) {
        if (!XrWindow::canPresent(binding->instance, binding->physicalDevice, binding->queueFamilyIndex)) {
            logLine("no window: the session's queue family cannot present; headless");
        } else {
            auto w = XrWindow::create(*s->context, c.width, c.height, "wrsfov simulated HMD: " + inst->applicationName);
            if (!w) logLine("no window (" + w.error().message + "): headless");
            else s->window = std::move(*w);
        }
    }
    if (auto src = openGazeSource(c)) s->gazeSource = std::move(*src);
    else logLine(src.error().message + "; gaze falls back to the view centre");
    std::string gazeName = "none (view centre)";
    if (s->gazeSource)
        gazeName = c.gaze == GazeKind::Generator ? "generator (" + std::string(gaze::mode_name(c.gazeMode)) + ")"
                   : c.gaze == GazeKind::File    ? "file"
                                                 : "HID";
    if (c.gaze == GazeKind::Mouse) gazeName = s->window ? "mouse" : "mouse, but no window: none (view centre)";
    logLine("session on " + s->context->deviceName() + ", gaze " + gazeName + ", " +
            (s->window ? "window" : "headless"));
    registerObject(s.get());
    *out = reinterpret_cast<XrSession>(s.get());
    Session* raw = s.get();
    raw->compositorThread = std::thread(compositorThread, raw);
    inst->sessions.push_back(std::move(s));
    std::lock_guard frame(raw->frameMutex);
    setState(raw, XR_SESSION_STATE_IDLE);
    setState(raw, XR_SESSION_STATE_READY);
    return XR_SUCCESS;
}

XRAPI_ATTR XrResult XRAPI_CALL xrDestroySession(XrSession h) {
    std::lock_guard lock(stateMutex(h));
    Session* s = getSession(h);
    if (!s) return XR_ERROR_HANDLE_INVALID;
    return destroySession(s);
}

XRAPI_ATTR XrResult XRAPI_CALL xrBeginSession(XrSession h, const XrSessionBeginInfo* info) {
    std::lock_guard lock(stateMutex(h));
    Session* s = getSession(h);
    if (!s) return XR_ERROR_HANDLE_INVALID;
    if (!info || info->type != XR_TYPE_SESSION_BEGIN_INFO) return XR_ERROR_VALIDATION_FAILURE;
    std::lock_guard frame(s->frameMutex);
    if (s->running) return XR_ERROR_SESSION_RUNNING;
    if (XrResult r = checkViewConfiguration(*s->instance, info->primaryViewConfigurationType); r != XR_SUCCESS)
        return r;
    if (s->state != XR_SESSION_STATE_READY) return XR_ERROR_SESSION_NOT_READY;
    s->running = true;
    s->viewConfiguration = info->primaryViewConfigurationType;
    s->nextDisplayTime = 0;
    s->lastDisplayTime = 0;
    s->waited = 0;
    s->waitedDisplayTimes.clear();
    s->begun = false;
    return XR_SUCCESS;
}

XRAPI_ATTR XrResult XRAPI_CALL xrEndSession(XrSession h) {
    std::lock_guard lock(stateMutex(h));
    Session* s = getSession(h);
    if (!s) return XR_ERROR_HANDLE_INVALID;
    std::lock_guard frame(s->frameMutex);
    if (!s->running) return XR_ERROR_SESSION_NOT_RUNNING;
    if (s->state != XR_SESSION_STATE_STOPPING) return XR_ERROR_SESSION_NOT_STOPPING;
    s->running = false;
    s->synced = false;
    s->frameCv.notify_all();  // an xrWaitFrame on another thread returns SESSION_NOT_RUNNING
    setState(s, XR_SESSION_STATE_IDLE);
    // Stopping is only ever asked for to end the session (xrRequestExitSession, `frames`).
    setState(s, XR_SESSION_STATE_EXITING);
    return XR_SUCCESS;
}

XRAPI_ATTR XrResult XRAPI_CALL xrRequestExitSession(XrSession h) {
    std::lock_guard lock(stateMutex(h));
    Session* s = getSession(h);
    if (!s) return XR_ERROR_HANDLE_INVALID;
    std::lock_guard frame(s->frameMutex);
    if (!s->running) return XR_ERROR_SESSION_NOT_RUNNING;
    beginStopping(s);
    return XR_SUCCESS;
}

// ---------------------------------------------------------------------------------------------
// Spaces

XRAPI_ATTR XrResult XRAPI_CALL xrEnumerateReferenceSpaces(XrSession h, uint32_t capacity, uint32_t* countOutput,
                                                          XrReferenceSpaceType* spaces) {
    std::lock_guard lock(stateMutex(h));
    Session* s = getSession(h);
    if (!s) return XR_ERROR_HANDLE_INVALID;
    std::vector<XrReferenceSpaceType> types = {XR_REFERENCE_SPACE_TYPE_VIEW, XR_REFERENCE_SPACE_TYPE_LOCAL,
                                               XR_REFERENCE_SPACE_TYPE_STAGE};
    if (s->instance->enabled(XR_VARJO_FOVEATED_RENDERING_EXTENSION_NAME))
        types.push_back(XR_REFERENCE_SPACE_TYPE_COMBINED_EYE_VARJO);
    return fillArray<XrReferenceSpaceType>(capacity, countOutput, spaces, types);
}

XrResult checkReferenceType(const Session& s, XrReferenceSpaceType t) {
    if (t == XR_REFERENCE_SPACE_TYPE_VIEW || t == XR_REFERENCE_SPACE_TYPE_LOCAL || t == XR_REFERENCE_SPACE_TYPE_STAGE)
        return XR_SUCCESS;
    if (t == XR_REFERENCE_SPACE_TYPE_COMBINED_EYE_VARJO &&
        s.instance->enabled(XR_VARJO_FOVEATED_RENDERING_EXTENSION_NAME))
        return XR_SUCCESS;
    return t > 0 && t < XR_REFERENCE_SPACE_TYPE_MAX_ENUM ? XR_ERROR_REFERENCE_SPACE_UNSUPPORTED
                                                         : XR_ERROR_VALIDATION_FAILURE;
}

XrSpace addSpace(Session* s, std::unique_ptr<Space> sp) {
    registerObject(sp.get());
    XrSpace h = reinterpret_cast<XrSpace>(sp.get());
    s->spaces.push_back(std::move(sp));
    return h;
}

XRAPI_ATTR XrResult XRAPI_CALL xrCreateReferenceSpace(XrSession h, const XrReferenceSpaceCreateInfo* info,
                                                      XrSpace* out) {
    std::lock_guard lock(stateMutex(h));
    Session* s = getSession(h);
    if (!s) return XR_ERROR_HANDLE_INVALID;
    if (!info || !out || info->type != XR_TYPE_REFERENCE_SPACE_CREATE_INFO) return XR_ERROR_VALIDATION_FAILURE;
    // Any type the session does not offer, a value no specification defines included
    // (XR_REFERENCE_SPACE_TYPE_MAX_ENUM), cannot be created: REFERENCE_SPACE_UNSUPPORTED, as the
    // specification words it for this call (xrGetReferenceSpaceBoundsRect calls a made-up value a
    // validation failure).
    if (checkReferenceType(*s, info->referenceSpaceType) != XR_SUCCESS) return XR_ERROR_REFERENCE_SPACE_UNSUPPORTED;
    if (!isValidPose(info->poseInReferenceSpace)) return XR_ERROR_POSE_INVALID;
    auto sp = std::make_unique<Space>();
    sp->session = s;
    sp->reference = info->referenceSpaceType;
    sp->poseInSpace = fromXr(info->poseInReferenceSpace);
    *out = addSpace(s, std::move(sp));
    return XR_SUCCESS;
}

XRAPI_ATTR XrResult XRAPI_CALL xrGetReferenceSpaceBoundsRect(XrSession h, XrReferenceSpaceType type,
                                                             XrExtent2Df* bounds) {
    std::lock_guard lock(stateMutex(h));
    Session* s = getSession(h);
    if (!s) return XR_ERROR_HANDLE_INVALID;
    if (!bounds) return XR_ERROR_VALIDATION_FAILURE;
    if (XrResult r = checkReferenceType(*s, type); r != XR_SUCCESS) return r;
    if (type == XR_REFERENCE_SPACE_TYPE_STAGE) {
        *bounds = {4.0f, 4.0f};  // a 4 m x 4 m play area around the stage origin
        return XR_SUCCESS;
    }
    *bounds = {0.0f, 0.0f};
    return XR_SPACE_BOUNDS_UNAVAILABLE;
}

XRAPI_ATTR XrResult XRAPI_CALL xrCreateActionSpace(XrSession h, const XrActionSpaceCreateInfo* info, XrSpace* out) {
    std::lock_guard lock(stateMutex(h));
    Session* s = getSession(h);
    if (!s) return XR_ERROR_HANDLE_INVALID;
    if (!info || !out || info->type != XR_TYPE_ACTION_SPACE_CREATE_INFO) return XR_ERROR_VALIDATION_FAILURE;
    Action* a = getAction(info->action);
    if (!a) return XR_ERROR_HANDLE_INVALID;
    if (a->actionType != XR_ACTION_TYPE_POSE_INPUT) return XR_ERROR_ACTION_TYPE_MISMATCH;
    if (XrResult r = checkSubaction(*a, info->subactionPath); r != XR_SUCCESS) return r;
    if (!isValidPose(info->poseInActionSpace)) return XR_ERROR_POSE_INVALID;
    auto sp = std::make_unique<Space>();
    sp->session = s;
    sp->isAction = true;
    sp->action = a;
    sp->subaction = info->subactionPath;
    sp->poseInSpace = fromXr(info->poseInActionSpace);
    *out = addSpace(s, std::move(sp));
    return XR_SUCCESS;
}

XRAPI_ATTR XrResult XRAPI_CALL xrLocateSpace(XrSpace spaceH, XrSpace baseH, XrTime time, XrSpaceLocation* location) {
    std::lock_guard lock(stateMutex(spaceH));
    Space* space = getSpace(spaceH);
    Space* base = getSpace(baseH);
    if (!space || !base || space->session != base->session) return XR_ERROR_HANDLE_INVALID;
    if (!location || location->type != XR_TYPE_SPACE_LOCATION) return XR_ERROR_VALIDATION_FAILURE;
    if (time <= 0) return XR_ERROR_TIME_INVALID;
    Pose a, b;
    GazeState gaze, baseGaze;
    const bool ok = spacePose(*space, time, a, &gaze) && spacePose(*base, time, b, &baseGaze);
    location->locationFlags = 0;
    location->pose = toXr(Pose{});
    if (ok) {
        location->pose = toXr(inverse(b) * a);
        location->locationFlags = XR_SPACE_LOCATION_ORIENTATION_VALID_BIT | XR_SPACE_LOCATION_POSITION_VALID_BIT |
                                  XR_SPACE_LOCATION_ORIENTATION_TRACKED_BIT | XR_SPACE_LOCATION_POSITION_TRACKED_BIT;
        // XR_VARJO_foveated_rendering: the combined-eye space's orientation is tracked only while the
        // rendering gaze is valid.
        auto untracked = [](const Space& sp, const GazeState& g) {
            return !sp.isAction && sp.reference == XR_REFERENCE_SPACE_TYPE_COMBINED_EYE_VARJO && !g.valid;
        };
        if (untracked(*space, gaze) || untracked(*base, baseGaze))
            location->locationFlags &= ~XrSpaceLocationFlags(XR_SPACE_LOCATION_ORIENTATION_TRACKED_BIT);
    }
    for (auto* n = static_cast<XrBaseOutStructure*>(location->next); n; n = n->next) {
        if (n->type == XR_TYPE_SPACE_VELOCITY) {
            auto* v = reinterpret_cast<XrSpaceVelocity*>(n);
            v->velocityFlags = 0;  // not simulated
            v->linearVelocity = {0, 0, 0};
            v->angularVelocity = {0, 0, 0};
        } else if (n->type == XR_TYPE_EYE_GAZE_SAMPLE_TIME_EXT) {
            reinterpret_cast<XrEyeGazeSampleTimeEXT*>(n)->time =
                ok && space->isAction ? space->session->instance->epoch + XrTime(gaze.t_s * 1e9) : 0;
        }
    }
    return XR_SUCCESS;
}

XRAPI_ATTR XrResult XRAPI_CALL xrDestroySpace(XrSpace h) {
    std::lock_guard lock(stateMutex(h));
    Space* sp = getSpace(h);
    if (!sp) return XR_ERROR_HANDLE_INVALID;
    unregisterObject(sp);
    auto& v = sp->session->spaces;
    for (auto it = v.begin(); it != v.end(); ++it)
        if (it->get() == sp) {
            v.erase(it);
            break;
        }
    return XR_SUCCESS;
}

// ---------------------------------------------------------------------------------------------
// Swapchains

namespace {

struct FormatEntry {
    VkFormat vk;
    layers::Format format;
    layers::Usage usage;
};
// In order of preference (applications take the first they know).
constexpr FormatEntry kFormats[] = {
    {VK_FORMAT_R8G8B8A8_SRGB, layers::Format::RGBA8_SRGB, layers::Usage::Color},
    {VK_FORMAT_R8G8B8A8_UNORM, layers::Format::RGBA8, layers::Usage::Color},
    {VK_FORMAT_R16G16B16A16_SFLOAT, layers::Format::RGBA16F, layers::Usage::Color},
    {VK_FORMAT_D32_SFLOAT, layers::Format::D32F, layers::Usage::Depth},
    {VK_FORMAT_R32_SFLOAT, layers::Format::R32F, layers::Usage::Depth},
    {VK_FORMAT_R16G16_SFLOAT, layers::Format::RG16F, layers::Usage::Motion},
};

// The strict setting offers 8-bit colour as sRGB only (RuntimeConfig::strictSwapchains).
bool offered(const Session& s, const FormatEntry& f) {
    return !(s.instance->config.strictSwapchains && f.format == layers::Format::RGBA8);
}

}  // namespace

XRAPI_ATTR XrResult XRAPI_CALL xrEnumerateSwapchainFormats(XrSession h, uint32_t capacity, uint32_t* countOutput,
                                                           int64_t* formats) {
    if (!getSession(h)) return XR_ERROR_HANDLE_INVALID;
    std::vector<int64_t> v;
    for (const auto& f : kFormats)
        if (offered(*getSession(h), f)) v.push_back(int64_t(f.vk));
    return fillArray(capacity, countOutput, formats, v);
}

XRAPI_ATTR XrResult XRAPI_CALL xrCreateSwapchain(XrSession h, const XrSwapchainCreateInfo* info, XrSwapchain* out) {
    Session* s = getSession(h);
    if (!s) return XR_ERROR_HANDLE_INVALID;
    std::lock_guard gpu(s->gpuMutex);
    if (!info || !out || info->type != XR_TYPE_SWAPCHAIN_CREATE_INFO) return XR_ERROR_VALIDATION_FAILURE;
    const XrSwapchainCreateFlags knownFlags =
        XR_SWAPCHAIN_CREATE_PROTECTED_CONTENT_BIT | XR_SWAPCHAIN_CREATE_STATIC_IMAGE_BIT;
    if (info->createFlags & ~knownFlags) return XR_ERROR_VALIDATION_FAILURE;
    if (info->createFlags & XR_SWAPCHAIN_CREATE_PROTECTED_CONTENT_BIT) return XR_ERROR_FEATURE_UNSUPPORTED;
    const FormatEntry* fmt = nullptr;
    for (const auto& f : kFormats)
        if (int64_t(f.vk) == info->format && offered(*s, f)) fmt = &f;
    if (!fmt) return XR_ERROR_SWAPCHAIN_FORMAT_UNSUPPORTED;
    if (info->width == 0 || info->height == 0 || info->width > kMaxSize || info->height > kMaxSize ||
        info->arraySize == 0 || info->faceCount == 0 || info->mipCount == 0 || info->sampleCount == 0)
        return XR_ERROR_VALIDATION_FAILURE;
    if (info->sampleCount != 1 || info->mipCount != 1 || info->faceCount != 1 || info->arraySize > 16)
        return XR_ERROR_FEATURE_UNSUPPORTED;  // single-sampled, one mip level, 2D (array) images
    const bool depth = fmt->format == layers::Format::D32F;
    if ((depth && (info->usageFlags & XR_SWAPCHAIN_USAGE_COLOR_ATTACHMENT_BIT)) ||
        (!depth && (info->usageFlags & XR_SWAPCHAIN_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT)))
        return XR_ERROR_FEATURE_UNSUPPORTED;

    SwapchainImageOptions options;
    if (info->usageFlags & XR_SWAPCHAIN_USAGE_UNORDERED_ACCESS_BIT) options.usage |= VK_IMAGE_USAGE_STORAGE_BIT;
    // The strict setting ignores MUTABLE_FORMAT, as Monado 21 does: its sRGB images are read through
    // sRGB views (the compositor adds MUTABLE_FORMAT to its own otherwise).
    const bool strict = s->instance->config.strictSwapchains;
    if ((info->usageFlags & XR_SWAPCHAIN_USAGE_MUTABLE_FORMAT_BIT) && !strict)
        options.flags |= VK_IMAGE_CREATE_MUTABLE_FORMAT_BIT;
    options.exactFlags = strict;
    options.restingLayout =
        depth ? VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL : VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL;
    options.deferInitialization = true;  // cleared at the first acquire: xrCreateSwapchain may not use the queue
    // What the images will be made with (swapchain_vk.cpp adds sampled, transfer and the attachment).
    VkImageUsageFlags usage = options.usage | VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT |
                              VK_IMAGE_USAGE_TRANSFER_DST_BIT |
                              (depth ? VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT : VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT);
    VkImageCreateFlags flags =
        options.flags |
        (fmt->format == layers::Format::RGBA8_SRGB && !strict ? VK_IMAGE_CREATE_MUTABLE_FORMAT_BIT : 0);
    VkImageFormatProperties props;
    if (vkGetPhysicalDeviceImageFormatProperties(s->context->physicalDevice(), fmt->vk, VK_IMAGE_TYPE_2D,
                                                 VK_IMAGE_TILING_OPTIMAL, usage, flags, &props) != VK_SUCCESS ||
        props.maxArrayLayers < info->arraySize || props.maxExtent.width < info->width ||
        props.maxExtent.height < info->height)
        return XR_ERROR_FEATURE_UNSUPPORTED;

    layers::SwapchainCreateInfo ci;
    ci.usage = fmt->usage;
    ci.format = fmt->format;
    ci.width = info->width;
    ci.height = info->height;
    ci.arraySize = info->arraySize;
    ci.imageCount = (info->createFlags & XR_SWAPCHAIN_CREATE_STATIC_IMAGE_BIT) ? 1 : strict ? 4 : 3;
    ci.anyUse = true;  // an RGBA16F swapchain may carry colour or space-warp motion
    auto images = s->compositor->createSwapchain(ci, options);
    if (!images) {
        logLine("xrCreateSwapchain: " + images.error().message);
        return images.error().code == int(layers::SwapchainError::DeviceFailure) ? XR_ERROR_OUT_OF_MEMORY
                                                                                  : XR_ERROR_VALIDATION_FAILURE;
    }
    auto sc = std::make_unique<Swapchain>();
    sc->session = s;
    sc->info = *info;
    sc->info.next = nullptr;
    sc->format = fmt->format;
    sc->images = std::move(*images);
    sc->readByFrame.assign(ci.imageCount, 0);
    registerObject(sc.get());
    *out = reinterpret_cast<XrSwapchain>(sc.get());
    s->swapchains.push_back(std::move(sc));
    return XR_SUCCESS;
}

XRAPI_ATTR XrResult XRAPI_CALL xrDestroySwapchain(XrSwapchain h) {
    Swapchain* sc = getSwapchain(h);
    if (!sc) return XR_ERROR_HANDLE_INVALID;
    Session* s = sc->session;
    // A frame handed to the compositor may still read the images: they go once it is complete.
    uint64_t lastReader = 0;
    {
        std::lock_guard lock(sc->mutex);
        for (uint64_t f : sc->readByFrame) lastReader = std::max(lastReader, f);
    }
    {
        std::unique_lock frame(s->frameMutex);
        waitForFrame(s, frame, lastReader, XR_INFINITE_DURATION);
    }
    std::lock_guard gpu(s->gpuMutex);
    unregisterObject(sc);
    auto& v = s->swapchains;
    for (auto it = v.begin(); it != v.end(); ++it)
        if (it->get() == sc) {
            v.erase(it);
            break;
        }
    return XR_SUCCESS;
}

XRAPI_ATTR XrResult XRAPI_CALL xrEnumerateSwapchainImages(XrSwapchain h, uint32_t capacity, uint32_t* countOutput,
                                                          XrSwapchainImageBaseHeader* images) {
    Swapchain* sc = getSwapchain(h);
    if (!sc) return XR_ERROR_HANDLE_INVALID;
    std::lock_guard lock(sc->mutex);
    if (!countOutput) return XR_ERROR_VALIDATION_FAILURE;
    const uint32_t n = sc->images->info().imageCount;
    *countOutput = n;
    if (capacity == 0) return XR_SUCCESS;
    if (capacity < n) return XR_ERROR_SIZE_INSUFFICIENT;
    if (!images) return XR_ERROR_VALIDATION_FAILURE;
    auto* vkImages = reinterpret_cast<XrSwapchainImageVulkanKHR*>(images);
    for (uint32_t i = 0; i < n; ++i)
        if (vkImages[i].type != XR_TYPE_SWAPCHAIN_IMAGE_VULKAN_KHR) return XR_ERROR_VALIDATION_FAILURE;
    for (uint32_t i = 0; i < n; ++i) vkImages[i].image = sc->images->image(i);
    return XR_SUCCESS;
}

XRAPI_ATTR XrResult XRAPI_CALL xrAcquireSwapchainImage(XrSwapchain h, const XrSwapchainImageAcquireInfo* info,
                                                       uint32_t* index) {
    Swapchain* sc = getSwapchain(h);
    if (!sc) return XR_ERROR_HANDLE_INVALID;
    if (!index || (info && info->type != XR_TYPE_SWAPCHAIN_IMAGE_ACQUIRE_INFO)) return XR_ERROR_VALIDATION_FAILURE;
    std::lock_guard gpu(sc->session->gpuMutex);  // prepare() may use the queue (allowed in this call)
    std::lock_guard lock(sc->mutex);
    if ((sc->info.createFlags & XR_SWAPCHAIN_CREATE_STATIC_IMAGE_BIT) && sc->acquiredEver > 0)
        return XR_ERROR_CALL_ORDER_INVALID;
    // First use: clear the images and put them in the layout the application expects (the queue may
    // be used here).
    if (Status p = static_cast<VulkanSwapchain*>(sc->images.get())->prepare(); !p) {
        logLine("xrAcquireSwapchainImage: " + p.message());
        return XR_ERROR_RUNTIME_FAILURE;
    }
    auto r = sc->images->acquire();
    if (!r) return XR_ERROR_CALL_ORDER_INVALID;  // every image acquired and not released
    ++sc->acquiredEver;
    sc->acquiredOrder.push_back(*r);
    *index = *r;
    return XR_SUCCESS;
}

XRAPI_ATTR XrResult XRAPI_CALL xrWaitSwapchainImage(XrSwapchain h, const XrSwapchainImageWaitInfo* info) {
    Swapchain* sc = getSwapchain(h);
    if (!sc) return XR_ERROR_HANDLE_INVALID;
    if (!info || info->type != XR_TYPE_SWAPCHAIN_IMAGE_WAIT_INFO) return XR_ERROR_VALIDATION_FAILURE;
    uint64_t reader = 0;
    {
        std::lock_guard lock(sc->mutex);
        // One image at a time is waited for: a second wait before its release is out of order, and
        // changes nothing (the images stay acquired for later legitimate waits).
        for (uint32_t i = 0; i < sc->images->info().imageCount; ++i)
            if (sc->images->isWaited(i)) return XR_ERROR_CALL_ORDER_INVALID;
        if (sc->acquiredOrder.empty()) return XR_ERROR_CALL_ORDER_INVALID;  // nothing acquired
        reader = sc->readByFrame[sc->acquiredOrder.front()];
    }
    // The image is the application's again once the last frame that reads it is complete (its GPU
    // work done: the compositor thread saw its fence). Usually long ago: three images rotate.
    {
        Session* s = sc->session;
        std::unique_lock frame(s->frameMutex);
        if (!waitForFrame(s, frame, reader, info->timeout)) return XR_TIMEOUT_EXPIRED;
    }
    std::lock_guard lock(sc->mutex);
    if (!sc->images->wait()) return XR_ERROR_CALL_ORDER_INVALID;
    sc->acquiredOrder.pop_front();
    return XR_SUCCESS;
}

XRAPI_ATTR XrResult XRAPI_CALL xrReleaseSwapchainImage(XrSwapchain h, const XrSwapchainImageReleaseInfo* info) {
    Swapchain* sc = getSwapchain(h);
    if (!sc) return XR_ERROR_HANDLE_INVALID;
    std::lock_guard lock(sc->mutex);
    if (info && info->type != XR_TYPE_SWAPCHAIN_IMAGE_RELEASE_INFO) return XR_ERROR_VALIDATION_FAILURE;
    return sc->images->release() ? XR_SUCCESS : XR_ERROR_CALL_ORDER_INVALID;  // released twice, or not waited
}

// ---------------------------------------------------------------------------------------------
// Frames

XRAPI_ATTR XrResult XRAPI_CALL xrWaitFrame(XrSession h, const XrFrameWaitInfo* info, XrFrameState* state) {
    Session* s = getSession(h);
    if (!s) return XR_ERROR_HANDLE_INVALID;
    if ((info && info->type != XR_TYPE_FRAME_WAIT_INFO) || !state || state->type != XR_TYPE_FRAME_STATE)
        return XR_ERROR_VALIDATION_FAILURE;
    std::unique_lock lock(s->frameMutex);
    if (!s->running) return XR_ERROR_SESSION_NOT_RUNNING;
    // A second xrWaitFrame waits until the frame before has been begun (the specification's order;
    // a pipelined application waits at most one frame ahead).
    s->frameCv.wait(lock, [s] { return s->waited == 0 || !s->running; });
    if (!s->running) return XR_ERROR_SESSION_NOT_RUNNING;
    const Instance& inst = *s->instance;
    const XrDuration p = period(inst);
    XrTime now = nowXrTime();
    if (s->nextDisplayTime == 0)
        s->nextDisplayTime = inst.config.pace ? now + p : std::max(inst.freeDisplayTime.load(), inst.epoch) + p;
    XrTime display;
    if (inst.config.pace) {
        // Paced by the display and by the compositor: consecutive frames are at least the
        // compositor's time apart (hand-over to completion, measured and smoothed; rounded up to
        // whole periods), so a compositor slower than the display slows the loop instead of queueing
        // frames, and xrEndFrame rarely finds the frame before still in flight (which it then waits
        // for: one frame in flight at most). The frame is shown at the first such slot at least half a
        // period away; a late application skips slots. Display times stay on the slot grid and
        // increase; the application is woken one period before its slot.
        const XrDuration composite = std::min<XrDuration>(s->compositeNs, 1000000000);  // a second at most
        const XrDuration interval = std::max<XrDuration>(1, (composite + p - 1) / p) * p;
        if (s->lastDisplayTime != 0) s->nextDisplayTime = std::max(s->nextDisplayTime, s->lastDisplayTime + interval);
        const XrTime earliest = now + p / 2;
        if (s->nextDisplayTime < earliest) s->nextDisplayTime += ((earliest - s->nextDisplayTime) / p + 1) * p;
        display = s->nextDisplayTime;
        s->nextDisplayTime += p;
        s->lastDisplayTime = display;
        const XrTime wake = display - p;
        if (wake > now) {
            // Sleeps with the frame lock released: xrBeginFrame / xrEndFrame of the frame before go on.
            s->frameCv.wait_for(lock, std::chrono::nanoseconds(wake - now),
                                [s] { return !s->running || s->shutdown; });
            if (!s->running) return XR_ERROR_SESSION_NOT_RUNNING;
        }
    } else {
        display = s->nextDisplayTime;
        s->nextDisplayTime += p;
        inst.freeDisplayTime = display;
    }
    ++s->waited;
    s->waitedDisplayTimes.push_back(display);
    if (s->state == XR_SESSION_STATE_READY && !s->stopRequested) {
        setState(s, XR_SESSION_STATE_SYNCHRONIZED);
        setState(s, XR_SESSION_STATE_VISIBLE);
        setState(s, XR_SESSION_STATE_FOCUSED);
    }
    state->predictedDisplayTime = display;
    state->predictedDisplayPeriod = p;
    state->shouldRender =
        s->state == XR_SESSION_STATE_VISIBLE || s->state == XR_SESSION_STATE_FOCUSED ? XR_TRUE : XR_FALSE;
    return XR_SUCCESS;
}

XRAPI_ATTR XrResult XRAPI_CALL xrBeginFrame(XrSession h, const XrFrameBeginInfo* info) {
    Session* s = getSession(h);
    if (!s) return XR_ERROR_HANDLE_INVALID;
    if (info && info->type != XR_TYPE_FRAME_BEGIN_INFO) return XR_ERROR_VALIDATION_FAILURE;
    std::lock_guard lock(s->frameMutex);
    if (!s->running) return XR_ERROR_SESSION_NOT_RUNNING;
    if (s->waited == 0) return XR_ERROR_CALL_ORDER_INVALID;
    --s->waited;
    s->frameDisplayTime = s->waitedDisplayTimes.front();  // pipelined: the oldest waited frame is begun
    s->waitedDisplayTimes.pop_front();
    s->frameCv.notify_all();  // a pipelined xrWaitFrame may go on
    if (s->begun) {
        ++s->framesDiscarded;  // the previous frame was begun and never ended
        return XR_FRAME_DISCARDED;
    }
    s->begun = true;
    return XR_SUCCESS;
}

namespace {

/// Reads one submitted sub-image back (for recording).
Result<HostImage> readSubImage(const layers::SubImage& sub) {
    auto* sc = sub.swapchain;
    auto bytes = sc->read(uint32_t(sc->lastReleased()), sub.arrayIndex);
    if (!bytes) return bytes.error();
    HostImage full = HostImage::make(sc->info().format, sc->info().width, sc->info().height);
    full.data = std::move(*bytes);
    if (sub.rect.x == 0 && sub.rect.y == 0 && sub.rect.width == full.width && sub.rect.height == full.height)
        return full;
    return full.crop(uint32_t(sub.rect.x), uint32_t(sub.rect.y), sub.rect.width, sub.rect.height);
}

/// Appends a composited frame to the recording: what the application submitted, our gaze, and the
/// compositor's output (NNNNNN_{L,R}_output.png beside the sequence's files).
void recordFrame(Session* s, const layers::FrameEndInfo& f, bool withOutput) {
    const RuntimeConfig& c = s->instance->config;
    if (c.record.empty() || s->recordingStopped) return;
    auto stop = [&](const std::string& why) {
        logLine("recording stopped: " + why);
        s->recordingStopped = true;
    };
    const layers::ProjectionLayer& layer = f.layers[0];
    std::array<EyeSubmission, 2> eyes;
    const bool quad = layers::submittedFoveation(layer) == layers::SubmittedFoveation::Quad;
    std::array<std::optional<std::pair<HostImage, HostImage>>, 2> views;  // quad views: wide, inset (sRGB)
    for (int e = 0; e < 2 && quad; ++e) {
        // Quad views: the sequence's colour, depth and motion are what the four views compose to at the
        // output's size (the compose pass's CPU reference); the views themselves go beside them.
        const layers::ProjectionView& v = layer.views[e];
        QuadSources q;
        auto read = [&](const layers::SubImage& sub, HostImage& out) {
            auto img = readSubImage(sub);
            if (!img) {
                stop(img.error().message);
                return false;
            }
            out = std::move(*img);
            return true;
        };
        if (!read(v.color, q.wideColor) || !read(v.inset->color, q.insetColor)) return;
        if (v.depth) {
            q.wideDepth.emplace();
            q.insetDepth.emplace();
            if (!read(v.depth->subImage, *q.wideDepth) || !read(v.inset->depth->subImage, *q.insetDepth)) return;
        }
        if (v.motion) {
            q.wideMotion.emplace();
            q.insetMotion.emplace();
            if (!read(v.motion->subImage, *q.wideMotion) || !read(v.inset->motion->subImage, *q.insetMotion)) return;
        }
        if (q.wideColor.format == layers::Format::RGBA8_SRGB && q.insetColor.format == layers::Format::RGBA8_SRGB)
            views[e] = {q.wideColor, q.insetColor};
        const gpu::ComposeParams params =
            makeComposeParams(layer, layers::outputSize(layer), c.compositor.insetBlendPx);
        Reference::EyeInput in = composeQuadViews(params, uint32_t(e), q);
        eyes[e].color = std::move(in.color);
        eyes[e].depth = std::move(in.depth);
        eyes[e].motion = std::move(in.motion);
        eyes[e].fov = v.fov;
        eyes[e].gaze = f.gaze[e];
    }
    for (int e = 0; e < 2 && !quad; ++e) {
        const layers::ProjectionView& v = layer.views[e];
        auto color = readSubImage(v.color);
        if (!color) return stop(color.error().message);
        eyes[e].color = std::move(*color);
        if (v.depth) {
            auto depth = readSubImage(v.depth->subImage);
            if (!depth) return stop(depth.error().message);
            eyes[e].depth = std::move(*depth);
        }
        if (v.motion) {
            // Recorded in pixels: the submitted texels times the layer's scale (space warp: NDC).
            auto motion = readSubImage(v.motion->subImage);
            if (!motion) return stop(motion.error().message);
            HostImage m = std::move(*motion);
            for (uint32_t y = 0; y < m.height; ++y)
                for (uint32_t x = 0; x < m.width; ++x)
                    m.store(x, y, glm::vec4(glm::vec3(m.fetch(x, y)) * v.motion->scale, 0.0f));
            eyes[e].motion = std::move(m);
        }
        eyes[e].fov = v.fov;
        eyes[e].gaze = f.gaze[e];
    }
    if (!s->recorder) {
        eval::SequenceInfo info;
        info.width = eyes[0].color.width;
        info.height = eyes[0].color.height;
        info.frameCount = 999999;  // an upper bound: close() writes the real count
        info.fps = c.displayHz;
        info.color = eyes[0].color.format == layers::Format::RGBA8_SRGB ? eval::ColorFile::Png : eval::ColorFile::Exr;
        info.fov = {layer.views[0].fov, layer.views[1].fov};
        if (layer.views[0].depth) {
            const auto& d = *layer.views[0].depth;
            info.depth = eval::SequenceDepth{d.nearZ, d.farZ, d.reversedZ};
        }
        if (layer.views[0].motion) info.motion = eval::MotionUnits::Pixels;
        info.description = "recorded by the wrsfov OpenXR runtime from '" + s->instance->applicationName + "'";
        auto w = eval::SequenceWriter::create(c.record, info);
        if (!w) return stop(w.error().message);
        s->recorder = std::move(*w);
    }
    const uint32_t index = s->recorder->written();
    if (Status st = s->recorder->writeFrame(index, eyes); !st) return stop(st.message());
    for (int e = 0; e < 2; ++e)
        if (views[e])
            for (const auto& [img, name] :
                 {std::pair{&views[e]->first, "wide.png"}, std::pair{&views[e]->second, "inset.png"}})
                if (Status st = writePng(*img, c.record + "/" + eval::frameFileName(index, e, name)); !st)
                    return stop(st.message());
    for (int e = 0; e < 2 && withOutput; ++e) {
        auto out = s->compositor->readOutput(uint32_t(e));
        if (!out) return stop(out.error().message);
        if (Status st = writePng(*out, c.record + "/" + eval::frameFileName(index, e, "output.png")); !st)
            return stop(st.message());
    }
}

/// What xrEndFrame hands to the compositor besides the application's structures: the frame's
/// display time and the poses of the quad layers' spaces (read under the instance's lock first).
struct FramePlan {
    XrTime displayTime = 0;
    std::vector<std::optional<Pose>> layerSpaces;  // per layer: its space's pose at displayTime (quads only)
};

/// The poses of the quad layers' spaces (an action space's pose depends on the action state).
FramePlan planFrame(Session* s, const XrFrameEndInfo* info, XrTime displayTime) {
    FramePlan plan;
    plan.displayTime = displayTime;
    plan.layerSpaces.resize(info->layerCount);
    std::lock_guard lock(s->instance->mutex);
    for (uint32_t i = 0; i < info->layerCount; ++i) {
        if (info->layers[i]->type != XR_TYPE_COMPOSITION_LAYER_QUAD) continue;
        Pose space;
        if (spacePose(*getSpace(info->layers[i]->space), displayTime, space)) plan.layerSpaces[i] = space;
    }
    return plan;
}

/// Quad layers after the projection layer, in order, over the composited output (those before it
/// are hidden by the opaque projection).
void drawQuads(Session* s, const XrFrameEndInfo* info, uint32_t projIndex, const layers::FrameEndInfo& f,
               const FramePlan& plan) {
    std::vector<QuadDraw> draws;
    const XrTime t = plan.displayTime;
    for (uint32_t i = projIndex + 1; i < info->layerCount; ++i) {
        if (info->layers[i]->type != XR_TYPE_COMPOSITION_LAYER_QUAD) continue;
        auto* q = reinterpret_cast<const XrCompositionLayerQuad*>(info->layers[i]);
        if (q->size.width == 0.0f || q->size.height == 0.0f) continue;  // covers nothing
        if (!plan.layerSpaces[i]) continue;  // an untracked space: not shown
        const Pose quadInStage = *plan.layerSpaces[i] * fromXr(q->pose);
        Swapchain* sc = getSwapchain(q->subImage.swapchain);
        const XrRect2Di& r = q->subImage.imageRect;
        for (uint32_t e = 0; e < 2; ++e) {
            if ((q->eyeVisibility == XR_EYE_VISIBILITY_LEFT && e == 1) ||
                (q->eyeVisibility == XR_EYE_VISIBILITY_RIGHT && e == 0))
                continue;
            const Pose m = inverse(quadInStage) * eyeAt(*s, t, int(e));
            QuadDraw d;
            d.eye = e;
            d.quadFromEye = glm::translate(glm::mat4(1.0f), m.p) * glm::mat4_cast(m.q);
            const layers::Fov& fov = f.layers[0].views[e].fov;
            d.fovTan = glm::vec4(std::tan(fov.angleLeft), std::tan(fov.angleRight), std::tan(fov.angleUp),
                                 std::tan(fov.angleDown));
            d.uvRect = glm::vec4(float(r.offset.x) / float(sc->info.width), float(r.offset.y) / float(sc->info.height),
                                 float(r.extent.width) / float(sc->info.width),
                                 float(r.extent.height) / float(sc->info.height));
            d.size = glm::vec2(q->size.width, q->size.height);
            d.blendAlpha = q->layerFlags & XR_COMPOSITION_LAYER_BLEND_TEXTURE_SOURCE_ALPHA_BIT;
            d.unpremultiplied = q->layerFlags & XR_COMPOSITION_LAYER_UNPREMULTIPLIED_ALPHA_BIT;
            d.swapchain = static_cast<const VulkanSwapchain*>(sc->images.get());
            d.arrayIndex = q->subImage.imageArrayIndex;
            draws.push_back(d);
        }
    }
    if (Status st = s->quads->draw(*s->compositor, draws); !st && s->refusalsLogged.insert(-3).second)
        logLine("quad layers not drawn: " + st.message());
}

/// Runs the first stereo projection layer through the compositor: submits its passes, the quads and
/// the window's copy to the session's queue without waiting for them (with `record`, the read-backs
/// wait). Returns whether the window asked the application to stop. With gpuMutex held.
bool compose(Session* s, const XrFrameEndInfo* info, const FramePlan& plan, uint64_t frameIndex) {
    const XrCompositionLayerProjection* proj = nullptr;
    uint32_t projIndex = 0;
    for (uint32_t i = 0; i < info->layerCount; ++i)
        if (info->layers[i]->type == XR_TYPE_COMPOSITION_LAYER_PROJECTION && !proj) {
            proj = reinterpret_cast<const XrCompositionLayerProjection*>(info->layers[i]);
            projIndex = i;
        }
    if (!proj) {
        bool quads = false;
        for (uint32_t i = 0; i < info->layerCount; ++i) quads |= info->layers[i]->type == XR_TYPE_COMPOSITION_LAYER_QUAD;
        if (quads && s->refusalsLogged.insert(-1).second)
            logLine("quad layers without a projection layer are not shown (the display is the projection's output)");
        return false;
    }
    const RuntimeConfig& c = s->instance->config;
    LayerReading reading;
    reading.depthExt = s->instance->enabled(XR_KHR_COMPOSITION_LAYER_DEPTH_EXTENSION_NAME);
    reading.warpExt = s->instance->enabled(XR_FB_SPACE_WARP_EXTENSION_NAME);
    // Quad views: composed at the display's size (or the wide views' where an application renders
    // them larger); wide views rendered jittered about the located field of view are composed on its
    // grid, their samples where they were taken.
    reading.quadViews = proj->viewCount == 4;
    reading.displayWidth = c.width;
    reading.displayHeight = c.height;
    reading.located = std::array<layers::Fov, 2>{c.fov[0], c.fov[1]};
    // Every swapchain of a verified frame end is one of this session's.
    auto sub = [](const XrSwapchainSubImage& x) -> std::optional<layers::SubImage> {
        return layers::SubImage{getSwapchain(x.swapchain)->images.get(),
                                {x.imageRect.offset.x, x.imageRect.offset.y, uint32_t(x.imageRect.extent.width),
                                 uint32_t(x.imageRect.extent.height)},
                                x.imageArrayIndex};
    };
    LayerExtras ex;
    std::optional<layers::ProjectionLayer> layer = projectionLayer(*proj, sub, reading, &ex);
    if (!layer) return false;  // not reached: a verified frame end has the configuration's views
    if (ex.depthRangeUnused && s->refusalsLogged.insert(-2).second)
        logLine("depth with a range other than [0, 1] is not used (the compositor reads depth in [0, 1])");
    if (ex.quadDepthDropped && s->refusalsLogged.insert(-4).second)
        logLine(
            "quad views: depth or motion not given for all four views (or depth ranges that differ "
            "between a wide view and its inset) are not used");
    const bool locomotion = ex.locomotion;
    layers::FrameEndInfo f;
    f.frameIndex = frameIndex;
    f.time_s = s->instance->seconds(plan.displayTime);
    f.layers.push_back(std::move(*layer));
    const auto gaze = frameGaze(*s, plan.displayTime, f.layers[0].views[0]);
    f.gaze[0] = gaze[0];
    f.gaze[1] = gaze[1];
    {
        std::lock_guard lock(s->gazeMutex);
        s->lastGaze = gaze;
    }
    if (!s->instance->config.compose) {  // method = off: shown and recorded as submitted
        ++s->framesPassed;
        recordFrame(s, f, false);
        return false;
    }
    if (locomotion) s->compositor->resetHistory();
    FrameSubmission submission;
    submission.mode = FrameSubmission::Mode::Submit;  // the compositor thread waits (frameFence)
    Status st = s->compositor->endFrame(f, submission);
    if (!st) {
        ++s->framesRefused;
        if (s->refusalsLogged.insert(st.error().code).second)
            logLine("frame " + std::to_string(f.frameIndex) + " not composited: " + st.message() +
                    " (logged once per reason)");
        return false;
    }
    ++s->framesComposited;
    s->pipelinesMade += s->compositor->stats().pipelinesMade;
    s->pipelineMs += s->compositor->stats().pipelineMs;
    drawQuads(s, info, projIndex, f, plan);
    recordFrame(s, f, true);
    if (s->window) {
        const FrameStats& st = s->compositor->stats();
        char gpu[64];
        std::snprintf(gpu, sizeof gpu, "GPU %.2f ms", st.gpu.total);
        std::vector<std::string> items = {
            s->instance->applicationName, std::string(toString(c.compositor.method)),
            std::string(toString(c.compositor.foveation)),
            "fovea " + std::to_string(int(c.compositor.foveaDeg + 0.5f)) + " deg",
            "frame " + std::to_string(s->framesComposited), st.gpu.valid ? std::string(gpu) : std::string("GPU -"),
            st.gazeFallback[0] || st.gazeFallback[1] ? "gaze: fallback (view centre)" : "gaze: tracked"};
        if (Status p = s->window->present(*s->compositor, items); !p) {
            logLine("window: " + p.message() + "; headless from now on");
            s->window.reset();
        } else if (s->window->closeRequested()) {
            logLine("window closed: asking the application to stop");
            return true;
        }
    }
    return false;
}

/// Every swapchain image the frame reads, so that it stays the compositor's until the frame is
/// complete (xrWaitSwapchainImage, xrDestroySwapchain wait for that).
void markReadBy(Session* s, const XrFrameEndInfo* info, uint64_t frame) {
    auto mark = [&](const XrSwapchainSubImage& sub) {
        Swapchain* sc = getSwapchain(sub.swapchain);
        std::lock_guard lock(sc->mutex);
        sc->readByFrame[uint32_t(sc->images->lastReleased())] = frame;
    };
    const bool depthExt = s->instance->enabled(XR_KHR_COMPOSITION_LAYER_DEPTH_EXTENSION_NAME);
    const bool warpExt = s->instance->enabled(XR_FB_SPACE_WARP_EXTENSION_NAME);
    for (uint32_t i = 0; i < info->layerCount; ++i) {
        const XrCompositionLayerBaseHeader* l = info->layers[i];
        if (l->type == XR_TYPE_COMPOSITION_LAYER_QUAD) {
            mark(reinterpret_cast<const XrCompositionLayerQuad*>(l)->subImage);
            continue;
        }
        auto* p = reinterpret_cast<const XrCompositionLayerProjection*>(l);
        for (uint32_t v = 0; v < p->viewCount; ++v) {
            mark(p->views[v].subImage);
            if (auto* n = findNext(p->views[v].next, XR_TYPE_COMPOSITION_LAYER_DEPTH_INFO_KHR); n && depthExt)
                mark(reinterpret_cast<const XrCompositionLayerDepthInfoKHR*>(n)->subImage);
            if (auto* n = findNext(p->views[v].next, XR_TYPE_COMPOSITION_LAYER_SPACE_WARP_INFO_FB); n && warpExt) {
                mark(reinterpret_cast<const XrCompositionLayerSpaceWarpInfoFB*>(n)->motionVectorSubImage);
                mark(reinterpret_cast<const XrCompositionLayerSpaceWarpInfoFB*>(n)->depthSubImage);
            }
        }
    }
}

}  // namespace

XRAPI_ATTR XrResult XRAPI_CALL xrEndFrame(XrSession h, const XrFrameEndInfo* info) {
    Session* s = getSession(h);
    if (!s) return XR_ERROR_HANDLE_INVALID;
    if (!info || info->type != XR_TYPE_FRAME_END_INFO) return XR_ERROR_VALIDATION_FAILURE;
    XrTime displayTime;
    {
        std::lock_guard frame(s->frameMutex);
        if (!s->running) return XR_ERROR_SESSION_NOT_RUNNING;
        if (!s->begun) return XR_ERROR_CALL_ORDER_INVALID;
        displayTime = s->frameDisplayTime;
    }
    if (Refusal r = checkFrameEnd(s, info)) {
        logLine("xrEndFrame: " + describe(r));
        return r.result;
    }
    const FramePlan plan = planFrame(s, info, displayTime);

    std::lock_guard gpu(s->gpuMutex);
    uint64_t serial;
    {
        // The frame before must be complete: the compositor's buffers and frameFence are reused (one
        // frame in flight). xrWaitFrame's throttling has usually seen to that already.
        std::unique_lock frame(s->frameMutex);
        waitForFrame(s, frame, s->framesHandedOver, XR_INFINITE_DURATION);
        serial = s->framesHandedOver + 1;
    }
    if (VkResult r = vkResetFences(s->context->device(), 1, &s->frameFence); r != VK_SUCCESS) {
        logLine(std::string("xrEndFrame: vkResetFences failed: ") + vk::resultString(r));
        return XR_ERROR_RUNTIME_FAILURE;
    }
    const bool closed = compose(s, info, plan, s->framesEnded + 1);
    markReadBy(s, info, serial);
    // After everything the frame submitted (queue order): the compositor thread waits for this fence.
    const VkResult submitted = s->context->deviceLost()
                                   ? VK_ERROR_DEVICE_LOST
                                   : vkQueueSubmit(s->context->queue(), 0, nullptr, s->frameFence);

    std::lock_guard frame(s->frameMutex);
    s->framesHandedOver = serial;
    s->handedOverAt = nowXrTime();
    if (submitted != VK_SUCCESS) s->framesCompleted = serial;  // nothing to wait for on a lost device
    s->frameCv.notify_all();
    s->begun = false;
    ++s->framesEnded;
    const uint64_t limit = s->instance->config.frames;
    if (limit > 0 && s->framesEnded >= limit && !s->stopRequested) {
        logLine("frame limit reached (" + std::to_string(limit) + "): asking the application to stop");
        beginStopping(s);
    }
    if (closed) beginStopping(s);
    return XR_SUCCESS;
}

XRAPI_ATTR XrResult XRAPI_CALL xrLocateViews(XrSession h, const XrViewLocateInfo* info, XrViewState* viewState,
                                             uint32_t capacity, uint32_t* countOutput, XrView* views) {
    std::lock_guard lock(stateMutex(h));
    Session* s = getSession(h);
    if (!s) return XR_ERROR_HANDLE_INVALID;
    if (!info || info->type != XR_TYPE_VIEW_LOCATE_INFO || !viewState || viewState->type != XR_TYPE_VIEW_STATE ||
        !countOutput)
        return XR_ERROR_VALIDATION_FAILURE;
    if (XrResult r = checkViewConfiguration(*s->instance, info->viewConfigurationType); r != XR_SUCCESS) return r;
    if (info->displayTime <= 0) return XR_ERROR_TIME_INVALID;
    Space* base = getSpace(info->space);
    if (!base || base->session != s) return XR_ERROR_HANDLE_INVALID;
    const uint32_t n = viewCount(info->viewConfigurationType);
    *countOutput = n;
    if (capacity == 0) return XR_SUCCESS;
    if (capacity < n) return XR_ERROR_SIZE_INSUFFICIENT;
    if (!views) return XR_ERROR_VALIDATION_FAILURE;
    for (uint32_t i = 0; i < n; ++i)
        if (views[i].type != XR_TYPE_VIEW) return XR_ERROR_VALIDATION_FAILURE;
    Pose b;
    const bool located = spacePose(*base, info->displayTime, b);
    viewState->viewStateFlags = located ? XR_VIEW_STATE_ORIENTATION_VALID_BIT | XR_VIEW_STATE_POSITION_VALID_BIT |
                                              XR_VIEW_STATE_ORIENTATION_TRACKED_BIT | XR_VIEW_STATE_POSITION_TRACKED_BIT
                                        : 0;
    const RuntimeConfig& c = s->instance->config;
    for (uint32_t i = 0; i < n; ++i) {
        const int e = int(i % 2);  // quad views: 2 and 3 are the insets of eyes 0 and 1, at their poses
        views[i].pose = toXr(located ? inverse(b) * eyeAt(*s, info->displayTime, e) : Pose{});
        views[i].fov = {c.fov[e].angleLeft, c.fov[e].angleRight, c.fov[e].angleUp, c.fov[e].angleDown};
    }
    if (n == 4) {
        // The insets: on each eye's gaze at the display time when the application asks for foveated
        // views (XrViewLocateFoveatedRenderingVARJO) and the gaze is valid, else centred.
        auto* fr = reinterpret_cast<const XrViewLocateFoveatedRenderingVARJO*>(
            findNext(info->next, XR_TYPE_VIEW_LOCATE_FOVEATED_RENDERING_VARJO));
        const bool foveated =
            fr && fr->foveatedRenderingActive && s->instance->enabled(XR_VARJO_FOVEATED_RENDERING_EXTENSION_NAME);
        std::array<layers::EyeGaze, 2> gaze{};
        if (foveated) gaze = locateGaze(*s, info->displayTime);
        for (int e = 0; e < 2; ++e) {
            std::optional<glm::vec3> dir;
            if (gaze[e].valid) dir = gaze[e].dir;
            const layers::Fov f = insetFov(c.fov[e], c.insetDeg, dir);
            views[2 + e].fov = {f.angleLeft, f.angleRight, f.angleUp, f.angleDown};
        }
    }
    return XR_SUCCESS;
}

}  // namespace wrsfov::xr
