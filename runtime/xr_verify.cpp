// The checks shared by the OpenXR calls: handle lookups, the one system, well-formed paths and
// names, subaction paths.
#include "runtime/xr_verify.h"

#include <cmath>
#include <cstring>
#include <sstream>
#include <string>
#include <tuple>

#include "xr_common/xr_frame.h"

namespace wrsfov::xr {

Instance* getInstance(XrInstance h) { return lookup<Instance>(h, ObjectType::Instance); }
Session* getSession(XrSession h) { return lookup<Session>(h, ObjectType::Session); }
ActionSet* getActionSet(XrActionSet h) { return lookup<ActionSet>(h, ObjectType::ActionSet); }
Action* getAction(XrAction h) { return lookup<Action>(h, ObjectType::Action); }
Space* getSpace(XrSpace h) { return lookup<Space>(h, ObjectType::Space); }
Swapchain* getSwapchain(XrSwapchain h) { return lookup<Swapchain>(h, ObjectType::Swapchain); }

namespace {
std::recursive_mutex& noObjectMutex() {
    static std::recursive_mutex m;
    return m;
}
std::recursive_mutex& of(Instance* inst) { return inst ? inst->mutex : noObjectMutex(); }
}  // namespace

std::recursive_mutex& stateMutex(XrInstance h) { return of(getInstance(h)); }
std::recursive_mutex& stateMutex(XrSession h) {
    Session* s = getSession(h);
    return of(s ? s->instance : nullptr);
}
std::recursive_mutex& stateMutex(XrActionSet h) {
    ActionSet* set = getActionSet(h);
    return of(set ? set->instance : nullptr);
}
std::recursive_mutex& stateMutex(XrAction h) {
    Action* a = getAction(h);
    return of(a ? a->set->instance : nullptr);
}
std::recursive_mutex& stateMutex(XrSpace h) {
    Space* sp = getSpace(h);
    return of(sp ? sp->session->instance : nullptr);
}

XrResult checkSystem(Instance* inst, XrSystemId id) {
    if (!inst) return XR_ERROR_HANDLE_INVALID;
    return id == kSystemId ? XR_SUCCESS : XR_ERROR_SYSTEM_INVALID;
}

bool wellFormedPath(const char* s) {
    if (!s || s[0] != '/') return false;
    std::size_t n = std::strlen(s);
    if (n >= XR_MAX_PATH_LENGTH || s[n - 1] == '/') return false;
    std::string component;
    for (std::size_t i = 1; i <= n; ++i) {
        const char c = s[i];
        if (c == '/' || c == '\0') {
            if (component.empty() || component == "." || component == "..") return false;
            component.clear();
            continue;
        }
        if (!((c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '-' || c == '_' || c == '.')) return false;
        component += c;
    }
    return true;
}

XrResult checkName(const char* s, std::size_t max) {
    const std::size_t n = strnlen(s, max);
    if (n == 0) return XR_ERROR_NAME_INVALID;
    if (n == max) return XR_ERROR_PATH_FORMAT_INVALID;
    for (std::size_t i = 0; i < n; ++i) {
        const char c = s[i];
        if (!((c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '-' || c == '_' || c == '.'))
            return XR_ERROR_PATH_FORMAT_INVALID;
    }
    return XR_SUCCESS;
}

XrResult checkSubaction(const Action& a, XrPath subaction) {
    if (subaction == XR_NULL_PATH) return XR_SUCCESS;
    if (a.set->instance->pathString(subaction).empty()) return XR_ERROR_PATH_INVALID;
    return std::find(a.subactionPaths.begin(), a.subactionPaths.end(), subaction) != a.subactionPaths.end()
               ? XR_SUCCESS
               : XR_ERROR_PATH_UNSUPPORTED;
}

std::string describe(const Refusal& r) {
    const char* name = resultName(r.result);
    return (name ? std::string(name) : std::to_string(int(r.result))) + ": " + r.message;
}

// ---------------------------------------------------------------------------------------------
// Frame end

namespace {

constexpr uint32_t kMaxLayers = 16;

std::string num(double v) {
    std::ostringstream o;
    o << v;
    return o.str();
}

std::string poseText(const XrPosef& p) {
    return "{{" + num(p.orientation.x) + ", " + num(p.orientation.y) + ", " + num(p.orientation.z) + ", " +
           num(p.orientation.w) + "}, {" + num(p.position.x) + ", " + num(p.position.y) + ", " + num(p.position.z) +
           "}}";
}

std::string rectText(const XrRect2Di& r) {
    return "{{" + std::to_string(r.offset.x) + ", " + std::to_string(r.offset.y) + "}, {" +
           std::to_string(r.extent.width) + ", " + std::to_string(r.extent.height) + "}}";
}

Refusal refuse(XrResult r, std::string message) { return {r, std::move(message)}; }

/// A sub-image reference of the frame end (`field` names it): handle, released image, array index,
/// rectangle.
Refusal checkSubImage(Session* s, const XrSwapchainSubImage& sub, const std::string& field) {
    Swapchain* sc = getSwapchain(sub.swapchain);
    if (!sc || sc->session != s)
        return refuse(XR_ERROR_HANDLE_INVALID, "(" + field + ".swapchain) is not a swapchain of this session");
    {
        std::lock_guard lock(sc->mutex);
        if (sc->images->lastReleased() < 0)
            return refuse(XR_ERROR_LAYER_INVALID, "(" + field + ".swapchain) has no released image");
    }
    if (sub.imageArrayIndex >= sc->info.arraySize)
        return refuse(XR_ERROR_VALIDATION_FAILURE,
                      "(" + field + ".imageArrayIndex == " + std::to_string(sub.imageArrayIndex) +
                          ") is not below the array size " + std::to_string(sc->info.arraySize));
    const XrRect2Di& r = sub.imageRect;
    if (r.offset.x < 0 || r.offset.y < 0 || r.extent.width <= 0 || r.extent.height <= 0 ||
        int64_t(r.offset.x) + r.extent.width > int64_t(sc->info.width) ||
        int64_t(r.offset.y) + r.extent.height > int64_t(sc->info.height))
        return refuse(XR_ERROR_SWAPCHAIN_RECT_INVALID,
                      "(" + field + ".imageRect == " + rectText(r) + ") is empty or outside the image (" +
                          std::to_string(sc->info.width) + ", " + std::to_string(sc->info.height) + ")");
    return {};
}

Refusal checkFov(const XrFovf& f, const std::string& field) {
    const float lim = 1.5707963f;
    const std::pair<const char*, float> angles[] = {
        {"angleLeft", f.angleLeft}, {"angleRight", f.angleRight}, {"angleUp", f.angleUp}, {"angleDown", f.angleDown}};
    for (const auto& [name, a] : angles)
        if (!std::isfinite(a) || std::abs(a) >= lim)
            return refuse(XR_ERROR_VALIDATION_FAILURE,
                          "(" + field + "." + name + " == " + num(a) + ") is not inside (-pi/2, pi/2)");
    if (!(f.angleLeft < f.angleRight))
        return refuse(XR_ERROR_VALIDATION_FAILURE, "(" + field + ".angleLeft == " + num(f.angleLeft) +
                                                       ") is not left of angleRight " + num(f.angleRight));
    if (!(f.angleDown < f.angleUp))
        return refuse(XR_ERROR_VALIDATION_FAILURE,
                      "(" + field + ".angleDown == " + num(f.angleDown) + ") is not below angleUp " + num(f.angleUp));
    return {};
}

Refusal checkDepthRange(float minDepth, float maxDepth, float nearZ, float farZ, const std::string& field) {
    if (!(minDepth >= 0.0f && minDepth < maxDepth && maxDepth <= 1.0f))
        return refuse(XR_ERROR_VALIDATION_FAILURE, "(" + field + ".minDepth == " + num(minDepth) + ", maxDepth == " +
                                                       num(maxDepth) + ") is not 0 <= minDepth < maxDepth <= 1");
    auto ok = [](float z) { return z > 0.0f && !std::isnan(z); };  // +inf allowed
    if (!ok(nearZ) || !ok(farZ) || nearZ == farZ)
        return refuse(XR_ERROR_VALIDATION_FAILURE, "(" + field + ".nearZ == " + num(nearZ) + ", farZ == " + num(farZ) +
                                                       ") needs two different positive distances");
    return {};
}

Refusal checkDepthInfo(Session* s, const XrCompositionLayerDepthInfoKHR& d, const std::string& field) {
    if (Refusal r = checkSubImage(s, d.subImage, field + ".subImage")) return r;
    return checkDepthRange(d.minDepth, d.maxDepth, d.nearZ, d.farZ, field);
}

Refusal checkSpaceWarp(Session* s, const XrCompositionLayerSpaceWarpInfoFB& w, const std::string& field) {
    // XR_COMPOSITION_LAYER_SPACE_WARP_INFO_FRAME_SKIP_BIT_FB (0x1) of later headers; 1.0.20 has no bits yet.
    constexpr XrCompositionLayerSpaceWarpInfoFlagsFB kFrameSkip = 0x1;
    if (w.layerFlags & ~kFrameSkip)
        return refuse(XR_ERROR_VALIDATION_FAILURE,
                      "(" + field + ".layerFlags == " + std::to_string(w.layerFlags) + ") has unknown bits");
    if (Refusal r = checkSubImage(s, w.motionVectorSubImage, field + ".motionVectorSubImage")) return r;
    if (Refusal r = checkSubImage(s, w.depthSubImage, field + ".depthSubImage")) return r;
    if (!isValidPose(spaceWarpDeltaPose(w.appSpaceDeltaPose)))
        return refuse(XR_ERROR_POSE_INVALID,
                      "(" + field + ".appSpaceDeltaPose == " + poseText(w.appSpaceDeltaPose) + ") is not a valid pose");
    return checkDepthRange(w.minDepth, w.maxDepth, w.nearZ, w.farZ, field);
}

/// Quad views: the inset (view 2 + eye) has its wide view's pose, and its field of view inside the
/// wide view's (a few micro-radians of slack for angles that went through tan and atan, as the
/// compositor allows).
Refusal checkInset(const XrCompositionLayerProjection& p, uint32_t eye, const std::string& layer) {
    const XrCompositionLayerProjectionView& wide = p.views[eye];
    const XrCompositionLayerProjectionView& inset = p.views[eye + 2];
    const std::string insetField = layer + "->views[" + std::to_string(eye + 2) + "]";
    const std::string wideName = "views[" + std::to_string(eye) + "]";
    const XrPosef& a = inset.pose;
    const XrPosef& b = wide.pose;
    auto quat = [](const XrQuaternionf& q) { return glm::dvec4(q.x, q.y, q.z, q.w); };
    const glm::dvec4 qa = quat(a.orientation), qb = quat(b.orientation);
    const double dq = std::abs(glm::dot(qa, qb)) / (glm::length(qa) * glm::length(qb));
    const double dp = std::abs(double(a.position.x) - b.position.x) + std::abs(double(a.position.y) - b.position.y) +
                      std::abs(double(a.position.z) - b.position.z);
    // The same pose (XR_VARJO_quad_views: the runtime gives views 0 and 2, 1 and 3 identical poses),
    // within the noise of a copy that went through the application's own float math: 0.1 mm, 0.16 degrees.
    if (dp > 1e-4 || dq < 1.0 - 1e-6)
        return refuse(XR_ERROR_POSE_INVALID, "(" + insetField + ".pose == " + poseText(a) + ") differs from " +
                                                 wideName + ".pose " + poseText(b) +
                                                 ": an inset has its wide view's pose");
    const float slack = 1e-5f;
    const std::tuple<const char*, float, float, bool> sides[] = {
        {"angleLeft", inset.fov.angleLeft, wide.fov.angleLeft, inset.fov.angleLeft < wide.fov.angleLeft - slack},
        {"angleRight", inset.fov.angleRight, wide.fov.angleRight, inset.fov.angleRight > wide.fov.angleRight + slack},
        {"angleUp", inset.fov.angleUp, wide.fov.angleUp, inset.fov.angleUp > wide.fov.angleUp + slack},
        {"angleDown", inset.fov.angleDown, wide.fov.angleDown, inset.fov.angleDown < wide.fov.angleDown - slack}};
    for (const auto& [name, in, out, outside] : sides)
        if (outside)
            return refuse(XR_ERROR_VALIDATION_FAILURE, "(" + insetField + ".fov." + name + " == " + num(in) +
                                                           ") is outside " + wideName + ".fov." + name + " " +
                                                           num(out) + ": an inset lies inside its wide view");
    return {};
}

Refusal checkProjection(Session* s, const XrCompositionLayerProjection& p, const std::string& layer) {
    const bool depthExt = s->instance->enabled(XR_KHR_COMPOSITION_LAYER_DEPTH_EXTENSION_NAME);
    const bool warpExt = s->instance->enabled(XR_FB_SPACE_WARP_EXTENSION_NAME);
    XrViewConfigurationType config;
    {
        std::lock_guard frame(s->frameMutex);
        config = s->viewConfiguration;
    }
    const uint32_t views = viewCount(config);
    if (p.viewCount != views)
        return refuse(XR_ERROR_VALIDATION_FAILURE, "(" + layer + "->viewCount == " + std::to_string(p.viewCount) +
                                                       ") is not the " + std::to_string(views) +
                                                       " views of the session's view configuration " +
                                                       (config == XR_VIEW_CONFIGURATION_TYPE_PRIMARY_QUAD_VARJO
                                                            ? "XR_VIEW_CONFIGURATION_TYPE_PRIMARY_QUAD_VARJO"
                                                            : "XR_VIEW_CONFIGURATION_TYPE_PRIMARY_STEREO"));
    if (!p.views) return refuse(XR_ERROR_VALIDATION_FAILURE, "(" + layer + "->views) is null");
    for (uint32_t v = 0; v < views; ++v) {
        const XrCompositionLayerProjectionView& view = p.views[v];
        const std::string field = layer + "->views[" + std::to_string(v) + "]";
        if (view.type != XR_TYPE_COMPOSITION_LAYER_PROJECTION_VIEW)
            return refuse(XR_ERROR_VALIDATION_FAILURE, "(" + field + ".type == " + std::to_string(int(view.type)) +
                                                           ") is not XR_TYPE_COMPOSITION_LAYER_PROJECTION_VIEW");
        if (!isValidPose(view.pose))
            return refuse(XR_ERROR_POSE_INVALID, "(" + field + ".pose == " + poseText(view.pose) +
                                                     ") is not a valid pose (finite, unit quaternion)");
        if (Refusal r = checkFov(view.fov, field + ".fov")) return r;
        if (Refusal r = checkSubImage(s, view.subImage, field + ".subImage")) return r;
        if (auto* d = findNext(view.next, XR_TYPE_COMPOSITION_LAYER_DEPTH_INFO_KHR); d && depthExt)
            if (Refusal r = checkDepthInfo(s, *reinterpret_cast<const XrCompositionLayerDepthInfoKHR*>(d),
                                           field + ".next<XrCompositionLayerDepthInfoKHR>"))
                return r;
        if (auto* w = findNext(view.next, XR_TYPE_COMPOSITION_LAYER_SPACE_WARP_INFO_FB); w && warpExt)
            if (Refusal r = checkSpaceWarp(s, *reinterpret_cast<const XrCompositionLayerSpaceWarpInfoFB*>(w),
                                           field + ".next<XrCompositionLayerSpaceWarpInfoFB>"))
                return r;
    }
    if (views == 4)
        for (uint32_t eye = 0; eye < 2; ++eye)
            if (Refusal r = checkInset(p, eye, layer)) return r;
    return {};
}

}  // namespace

Refusal checkFrameEnd(Session* s, const XrFrameEndInfo* info) {
    if (info->displayTime <= 0)
        return refuse(XR_ERROR_TIME_INVALID,
                      "(frameEndInfo->displayTime == " + std::to_string(info->displayTime) + ") is not a valid time");
    if (info->environmentBlendMode != XR_ENVIRONMENT_BLEND_MODE_OPAQUE)
        return refuse(info->environmentBlendMode >= XR_ENVIRONMENT_BLEND_MODE_OPAQUE &&
                              info->environmentBlendMode <= XR_ENVIRONMENT_BLEND_MODE_ALPHA_BLEND
                          ? XR_ERROR_ENVIRONMENT_BLEND_MODE_UNSUPPORTED
                          : XR_ERROR_VALIDATION_FAILURE,
                      "(frameEndInfo->environmentBlendMode == " + std::to_string(int(info->environmentBlendMode)) +
                          ") is not XR_ENVIRONMENT_BLEND_MODE_OPAQUE, the only one offered");
    if (info->layerCount > kMaxLayers)
        return refuse(XR_ERROR_LAYER_LIMIT_EXCEEDED,
                      "(frameEndInfo->layerCount == " + std::to_string(info->layerCount) + ") is above " +
                          std::to_string(kMaxLayers));
    if (info->layerCount > 0 && !info->layers)
        return refuse(XR_ERROR_VALIDATION_FAILURE,
                      "(frameEndInfo->layers) is null with layerCount " + std::to_string(info->layerCount));
    for (uint32_t i = 0; i < info->layerCount; ++i) {
        const XrCompositionLayerBaseHeader* l = info->layers[i];
        const std::string field = "frameEndInfo->layers[" + std::to_string(i) + "]";
        if (!l) return refuse(XR_ERROR_LAYER_INVALID, "(" + field + ") is null");
        const XrCompositionLayerFlags known = XR_COMPOSITION_LAYER_CORRECT_CHROMATIC_ABERRATION_BIT |
                                              XR_COMPOSITION_LAYER_BLEND_TEXTURE_SOURCE_ALPHA_BIT |
                                              XR_COMPOSITION_LAYER_UNPREMULTIPLIED_ALPHA_BIT;
        if (l->layerFlags & ~known)
            return refuse(XR_ERROR_VALIDATION_FAILURE,
                          "(" + field + "->layerFlags == " + std::to_string(l->layerFlags) + ") has unknown bits");
        Space* sp = getSpace(l->space);
        if (!sp || sp->session != s)
            return refuse(XR_ERROR_HANDLE_INVALID, "(" + field + "->space) is not a space of this session");
        if (l->type == XR_TYPE_COMPOSITION_LAYER_PROJECTION) {
            if (Refusal r = checkProjection(s, *reinterpret_cast<const XrCompositionLayerProjection*>(l), field))
                return r;
        } else if (l->type == XR_TYPE_COMPOSITION_LAYER_QUAD) {
            auto* q = reinterpret_cast<const XrCompositionLayerQuad*>(l);
            if (q->eyeVisibility > XR_EYE_VISIBILITY_RIGHT)
                return refuse(XR_ERROR_VALIDATION_FAILURE,
                              "(" + field + "->eyeVisibility == " + std::to_string(int(q->eyeVisibility)) +
                                  ") is not an XrEyeVisibility");
            // A quad of size {0, 0} (or of zero width or height) is valid and covers nothing.
            if (!std::isfinite(q->size.width) || !std::isfinite(q->size.height) || q->size.width < 0.0f ||
                q->size.height < 0.0f)
                return refuse(XR_ERROR_VALIDATION_FAILURE, "(" + field + "->size == {" + num(q->size.width) + ", " +
                                                               num(q->size.height) + "}) is not finite and >= 0");
            if (!isValidPose(q->pose))
                return refuse(XR_ERROR_POSE_INVALID,
                              "(" + field + "->pose == " + poseText(q->pose) + ") is not a valid pose");
            if (Refusal r = checkSubImage(s, q->subImage, field + "->subImage")) return r;
        } else {
            return refuse(XR_ERROR_LAYER_INVALID, "(" + field + "->type == " + std::to_string(int(l->type)) +
                                                      ") is not a projection or quad layer (the layer types offered)");
        }
    }
    return {};
}

}  // namespace wrsfov::xr
