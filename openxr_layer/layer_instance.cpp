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
#include "openxr_layer/layer_state.h"

namespace wrsfov::xrlayer {

// ---- Instance ---------------------------------------------------------------------------------

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

// ---- Dispatch ---------------------------------------------------------------------------------

namespace {

struct Entry {
    const char* name;
    PFN_xrVoidFunction fn;
};

}  // namespace
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

}  // namespace wrsfov::xrlayer

#define WRSFOV_LAYER_EXPORT extern "C" __attribute__((visibility("default")))

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

