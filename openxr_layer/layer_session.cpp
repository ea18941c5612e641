// XR_APILAYER_WRSFOV_foveation: sessions (the application's Vulkan device adopted, the gaze action set attached).
#include "openxr_layer/layer_state.h"

namespace wrsfov::xrlayer {

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

}  // namespace wrsfov::xrlayer
