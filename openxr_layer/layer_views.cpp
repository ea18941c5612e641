// XR_APILAYER_WRSFOV_foveation: the gaze, and quad views on a runtime without them (view configurations,
// views, reference spaces).
#include "openxr_layer/layer_state.h"

namespace wrsfov::xrlayer {

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

namespace {

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

}  // namespace

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

namespace {

/// The next link of an instance that offers the combined-eye space, for the calls on spaces (a space
/// does not name its instance; the next link's functions are the same for every instance of a
/// process). The layer intercepts them only for such instances.
const Next& anyNext() {
    static const Next none;
    for (const auto& [h, st] : g_instances)
        if (st.foveatedRendering) return st.next;
    return none;
}

}  // namespace

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

namespace {

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

}  // namespace

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

}  // namespace wrsfov::xrlayer
