// The runtime's reference and action spaces.
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

}  // namespace wrsfov::xr
