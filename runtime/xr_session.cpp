// The runtime's sessions: the state machine, the simulated head and eyes, the gaze, the compositor
// thread and xrLocateViews. Spaces, swapchains and the frame loop are beside it (xr_api_space.cpp,
// xr_api_swapchain.cpp, xr_session_frame.cpp).
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
#include "runtime/xr_session.h"

namespace wrsfov::xr {

namespace {
constexpr float kStandingHeight = 1.6f;  // LOCAL's origin above STAGE's (scenes::HeadPose)
}  // namespace

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

namespace {

Pose headAt(const Session& s, XrTime t) {
    const scenes::HeadPose h = scenes::headPose(s.instance->config.head, s.instance->seconds(t));
    return {glm::angleAxis(h.yaw, glm::vec3(0, 1, 0)), h.position};
}

}  // namespace

Pose eyeAt(const Session& s, XrTime t, int eye) {
    return headAt(s, t) * Pose{glm::quat(1, 0, 0, 0), {(eye == 0 ? -0.5f : 0.5f) * s.instance->config.ipd_m, 0, 0}};
}

namespace {

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

}  // namespace

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

namespace {

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

}  // namespace

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
