// The action system: action sets and actions, interaction profiles and suggested bindings,
// attaching to a session, xrSyncActions, action states, bound sources and haptics. The simulated HMD
// has eyes and no controllers: only XR_EXT_eye_gaze_interaction's pose is ever bound.
#include <algorithm>
#include <cstring>

#include "runtime/xr_objects.h"
#include "runtime/xr_verify.h"

namespace wrsfov::xr {

namespace {

const char* const kEyeGazeProfile = "/interaction_profiles/ext/eye_gaze_interaction";
const char* const kEyeGazePose = "/user/eyes_ext/input/gaze_ext/pose";

/// One input or output of an interaction profile: its path under the top-level user path, and the
/// one user path that has it where only one does (the Touch controller's buttons).
struct Component {
    const char* path;
    const char* onlyUser = nullptr;
};

/// The interaction profiles of OpenXR 1.0 (and of XR_EXT_eye_gaze_interaction when it is enabled):
/// their top-level user paths and the components 1.0 gives them. Components that later versions or
/// extensions add (grip_surface, palm_ext, dpad, proximity, ...) are not here, so with an OpenXR 1.0
/// instance they are unsupported paths, as the specification requires.
struct Profile {
    const char* path;
    std::vector<const char*> users;
    std::vector<Component> components;
    const char* extension = nullptr;  // needed to use the profile at all
};

const std::vector<Profile>& profiles() {
    static const std::vector<const char*> hands = {"/user/hand/left", "/user/hand/right"};
    constexpr const char* left = "/user/hand/left";
    constexpr const char* right = "/user/hand/right";
    // One profile's components in a few lines rather than one per line.
    // clang-format off
    static const std::vector<Profile> p = {
        {"/interaction_profiles/khr/simple_controller",
         hands,
         {{"/input/select/click"}, {"/input/menu/click"}, {"/input/grip/pose"}, {"/input/aim/pose"},
          {"/output/haptic"}}},
        {"/interaction_profiles/google/daydream_controller",
         hands,
         {{"/input/select/click"}, {"/input/trackpad"}, {"/input/trackpad/x"}, {"/input/trackpad/y"},
          {"/input/trackpad/click"}, {"/input/trackpad/touch"}, {"/input/grip/pose"}, {"/input/aim/pose"}}},
        {"/interaction_profiles/htc/vive_controller",
         hands,
         {{"/input/system/click"}, {"/input/squeeze/click"}, {"/input/menu/click"}, {"/input/trigger/click"},
          {"/input/trigger/value"}, {"/input/trackpad"}, {"/input/trackpad/x"}, {"/input/trackpad/y"},
          {"/input/trackpad/click"}, {"/input/trackpad/touch"}, {"/input/grip/pose"}, {"/input/aim/pose"},
          {"/output/haptic"}}},
        {"/interaction_profiles/htc/vive_pro",
         {"/user/head"},
         {{"/input/system/click"}, {"/input/volume_up/click"}, {"/input/volume_down/click"},
          {"/input/mute_mic/click"}}},
        {"/interaction_profiles/microsoft/motion_controller",
         hands,
         {{"/input/menu/click"}, {"/input/squeeze/click"}, {"/input/trigger/value"}, {"/input/thumbstick"},
          {"/input/thumbstick/x"}, {"/input/thumbstick/y"}, {"/input/thumbstick/click"}, {"/input/trackpad"},
          {"/input/trackpad/x"}, {"/input/trackpad/y"}, {"/input/trackpad/click"}, {"/input/trackpad/touch"},
          {"/input/grip/pose"}, {"/input/aim/pose"}, {"/output/haptic"}}},
        {"/interaction_profiles/microsoft/xbox_controller",
         {"/user/gamepad"},
         {{"/input/menu/click"}, {"/input/view/click"}, {"/input/a/click"}, {"/input/b/click"}, {"/input/x/click"},
          {"/input/y/click"}, {"/input/dpad_down/click"}, {"/input/dpad_right/click"}, {"/input/dpad_up/click"},
          {"/input/dpad_left/click"}, {"/input/shoulder_left/click"}, {"/input/shoulder_right/click"},
          {"/input/thumbstick_left/click"}, {"/input/thumbstick_right/click"}, {"/input/trigger_left/value"},
          {"/input/trigger_right/value"}, {"/input/thumbstick_left"}, {"/input/thumbstick_left/x"},
          {"/input/thumbstick_left/y"}, {"/input/thumbstick_right"}, {"/input/thumbstick_right/x"},
          {"/input/thumbstick_right/y"}, {"/output/haptic_left"}, {"/output/haptic_right"},
          {"/output/haptic_left_trigger"}, {"/output/haptic_right_trigger"}}},
        {"/interaction_profiles/oculus/go_controller",
         hands,
         {{"/input/system/click"}, {"/input/trigger/click"}, {"/input/back/click"}, {"/input/trackpad"},
          {"/input/trackpad/x"}, {"/input/trackpad/y"}, {"/input/trackpad/click"}, {"/input/trackpad/touch"},
          {"/input/grip/pose"}, {"/input/aim/pose"}}},
        {"/interaction_profiles/oculus/touch_controller",
         hands,
         {{"/input/x/click", left}, {"/input/x/touch", left}, {"/input/y/click", left}, {"/input/y/touch", left},
          {"/input/menu/click", left}, {"/input/a/click", right}, {"/input/a/touch", right},
          {"/input/b/click", right}, {"/input/b/touch", right}, {"/input/system/click", right},
          {"/input/squeeze/value"}, {"/input/trigger/value"}, {"/input/trigger/touch"}, {"/input/thumbstick"},
          {"/input/thumbstick/x"}, {"/input/thumbstick/y"}, {"/input/thumbstick/click"},
          {"/input/thumbstick/touch"}, {"/input/thumbrest/touch"}, {"/input/grip/pose"}, {"/input/aim/pose"},
          {"/output/haptic"}}},
        {"/interaction_profiles/valve/index_controller",
         hands,
         {{"/input/system/click"}, {"/input/system/touch"}, {"/input/a/click"}, {"/input/a/touch"},
          {"/input/b/click"}, {"/input/b/touch"}, {"/input/squeeze/value"}, {"/input/squeeze/force"},
          {"/input/trigger/click"}, {"/input/trigger/value"}, {"/input/trigger/touch"}, {"/input/thumbstick"},
          {"/input/thumbstick/x"}, {"/input/thumbstick/y"}, {"/input/thumbstick/click"},
          {"/input/thumbstick/touch"}, {"/input/trackpad"}, {"/input/trackpad/x"}, {"/input/trackpad/y"},
          {"/input/trackpad/force"}, {"/input/trackpad/touch"}, {"/input/grip/pose"}, {"/input/aim/pose"},
          {"/output/haptic"}}},
        {kEyeGazeProfile, {"/user/eyes_ext"}, {{"/input/gaze_ext/pose"}}, XR_EXT_EYE_GAZE_INTERACTION_EXTENSION_NAME},
    };
    // clang-format on
    return p;
}

/// The top-level user paths an instance knows: those of its profiles (/user/eyes_ext only with
/// XR_EXT_eye_gaze_interaction enabled).
bool knownUserPath(const Instance& inst, const std::string& user) {
    for (const Profile& p : profiles())
        if (!p.extension || inst.enabled(p.extension))
            for (const char* u : p.users)
                if (user == u) return true;
    return false;
}

/// Whether `binding` is a source of `profile`: a top-level user path of the profile followed by one
/// of its components for that user path, or by an identifier alone (`/input/trigger`, which the
/// runtime resolves to the identifier's component). The action's type is not checked: the
/// specification lets an application suggest any action for any source (a pose or haptic source for
/// a boolean action, say); a source whose type cannot feed the action is simply never bound to it.
bool bindingFits(const Profile& profile, const std::string& binding) {
    for (const char* user : profile.users) {
        const std::string u = user;
        if (binding.size() <= u.size() || binding.compare(0, u.size(), u) != 0 || binding[u.size()] != '/') continue;
        const std::string rest = binding.substr(u.size());
        const bool identifier = std::count(rest.begin(), rest.end(), '/') == 2;  // "/input/trigger"
        for (const Component& c : profile.components) {
            if (c.onlyUser && u != c.onlyUser) continue;
            const std::string path = c.path;
            if (rest == path) return true;
            if (identifier && path.size() > rest.size() && path.compare(0, rest.size(), rest) == 0 &&
                path[rest.size()] == '/')
                return true;
        }
    }
    return false;
}

}  // namespace

XRAPI_ATTR XrResult XRAPI_CALL xrCreateActionSet(XrInstance h, const XrActionSetCreateInfo* info, XrActionSet* out) {
    std::lock_guard lock(stateMutex(h));
    Instance* inst = getInstance(h);
    if (!inst) return XR_ERROR_HANDLE_INVALID;
    if (!info || !out || info->type != XR_TYPE_ACTION_SET_CREATE_INFO) return XR_ERROR_VALIDATION_FAILURE;
    if (XrResult r = checkName(info->actionSetName, XR_MAX_ACTION_SET_NAME_SIZE); r != XR_SUCCESS) return r;
    if (strnlen(info->localizedActionSetName, XR_MAX_LOCALIZED_ACTION_SET_NAME_SIZE) == 0)
        return XR_ERROR_LOCALIZED_NAME_INVALID;
    for (auto& s : inst->actionSets) {
        if (s->destroyed) continue;  // its names were released with its handle
        if (s->name == info->actionSetName) return XR_ERROR_NAME_DUPLICATED;
        if (s->localizedName == info->localizedActionSetName) return XR_ERROR_LOCALIZED_NAME_DUPLICATED;
    }
    auto set = std::make_unique<ActionSet>();
    set->instance = inst;
    set->name = info->actionSetName;
    set->localizedName = info->localizedActionSetName;
    set->priority = info->priority;
    registerObject(set.get());
    *out = reinterpret_cast<XrActionSet>(set.get());
    inst->actionSets.push_back(std::move(set));
    return XR_SUCCESS;
}

XRAPI_ATTR XrResult XRAPI_CALL xrDestroyActionSet(XrActionSet h) {
    std::lock_guard lock(stateMutex(h));
    ActionSet* set = getActionSet(h);
    if (!set) return XR_ERROR_HANDLE_INVALID;
    // An attached set lives on in its sessions (the handle is gone; the spec lets the runtime keep it).
    auto& sets = set->instance->actionSets;
    for (auto& a : set->actions) {
        if (!a->destroyed) unregisterObject(a.get());
        a->destroyed = true;
    }
    unregisterObject(set);
    set->destroyed = true;
    if (!set->attached)
        for (auto it = sets.begin(); it != sets.end(); ++it)
            if (it->get() == set) {
                sets.erase(it);
                break;
            }
    return XR_SUCCESS;
}

XRAPI_ATTR XrResult XRAPI_CALL xrCreateAction(XrActionSet h, const XrActionCreateInfo* info, XrAction* out) {
    std::lock_guard lock(stateMutex(h));
    ActionSet* set = getActionSet(h);
    if (!set) return XR_ERROR_HANDLE_INVALID;
    if (!info || !out || info->type != XR_TYPE_ACTION_CREATE_INFO) return XR_ERROR_VALIDATION_FAILURE;
    if (set->attached) return XR_ERROR_ACTIONSETS_ALREADY_ATTACHED;
    switch (info->actionType) {
        case XR_ACTION_TYPE_BOOLEAN_INPUT:
        case XR_ACTION_TYPE_FLOAT_INPUT:
        case XR_ACTION_TYPE_VECTOR2F_INPUT:
        case XR_ACTION_TYPE_POSE_INPUT:
        case XR_ACTION_TYPE_VIBRATION_OUTPUT:
            break;
        default:
            return XR_ERROR_VALIDATION_FAILURE;
    }
    if (XrResult r = checkName(info->actionName, XR_MAX_ACTION_NAME_SIZE); r != XR_SUCCESS) return r;
    if (strnlen(info->localizedActionName, XR_MAX_LOCALIZED_ACTION_NAME_SIZE) == 0)
        return XR_ERROR_LOCALIZED_NAME_INVALID;
    for (auto& a : set->actions) {
        if (a->destroyed) continue;  // its names were released with its handle
        if (a->name == info->actionName) return XR_ERROR_NAME_DUPLICATED;
        if (a->localizedName == info->localizedActionName) return XR_ERROR_LOCALIZED_NAME_DUPLICATED;
    }
    if (info->countSubactionPaths > 0 && !info->subactionPaths) return XR_ERROR_VALIDATION_FAILURE;
    std::vector<XrPath> sub;
    for (uint32_t i = 0; i < info->countSubactionPaths; ++i) {
        const std::string p = set->instance->pathString(info->subactionPaths[i]);
        if (p.empty()) return XR_ERROR_PATH_INVALID;
        if (!knownUserPath(*set->instance, p)) return XR_ERROR_PATH_UNSUPPORTED;
        for (XrPath q : sub)
            if (q == info->subactionPaths[i]) return XR_ERROR_PATH_UNSUPPORTED;  // duplicated
        sub.push_back(info->subactionPaths[i]);
    }
    auto a = std::make_unique<Action>();
    a->set = set;
    a->name = info->actionName;
    a->localizedName = info->localizedActionName;
    a->actionType = info->actionType;
    a->subactionPaths = std::move(sub);
    registerObject(a.get());
    *out = reinterpret_cast<XrAction>(a.get());
    set->actions.push_back(std::move(a));
    return XR_SUCCESS;
}

XRAPI_ATTR XrResult XRAPI_CALL xrDestroyAction(XrAction h) {
    std::lock_guard lock(stateMutex(h));
    Action* a = getAction(h);
    if (!a) return XR_ERROR_HANDLE_INVALID;
    unregisterObject(a);  // the object stays with its set (bindings and spaces may refer to it)
    a->destroyed = true;  // its names may be used again
    return XR_SUCCESS;
}

XRAPI_ATTR XrResult XRAPI_CALL xrSuggestInteractionProfileBindings(
    XrInstance h, const XrInteractionProfileSuggestedBinding* suggested) {
    std::lock_guard lock(stateMutex(h));
    Instance* inst = getInstance(h);
    if (!inst) return XR_ERROR_HANDLE_INVALID;
    if (!suggested || suggested->type != XR_TYPE_INTERACTION_PROFILE_SUGGESTED_BINDING ||
        suggested->countSuggestedBindings == 0 || !suggested->suggestedBindings)
        return XR_ERROR_VALIDATION_FAILURE;
    const std::string profilePath = inst->pathString(suggested->interactionProfile);
    if (profilePath.empty()) return XR_ERROR_PATH_INVALID;
    const Profile* profile = nullptr;
    for (const auto& p : profiles())
        if (profilePath == p.path && (!p.extension || inst->enabled(p.extension))) profile = &p;
    if (!profile) return XR_ERROR_PATH_UNSUPPORTED;
    std::vector<XrActionSuggestedBinding> bindings;
    for (uint32_t i = 0; i < suggested->countSuggestedBindings; ++i) {
        const XrActionSuggestedBinding& b = suggested->suggestedBindings[i];
        Action* a = getAction(b.action);
        if (!a) return XR_ERROR_HANDLE_INVALID;
        if (a->set->attached) return XR_ERROR_ACTIONSETS_ALREADY_ATTACHED;
        const std::string binding = inst->pathString(b.binding);
        if (binding.empty()) return XR_ERROR_PATH_INVALID;
        if (!bindingFits(*profile, binding)) return XR_ERROR_PATH_UNSUPPORTED;
        bindings.push_back(b);
    }
    inst->suggested[suggested->interactionProfile] = std::move(bindings);
    return XR_SUCCESS;
}

XRAPI_ATTR XrResult XRAPI_CALL xrAttachSessionActionSets(XrSession h, const XrSessionActionSetsAttachInfo* info) {
    std::lock_guard lock(stateMutex(h));
    Session* s = getSession(h);
    if (!s) return XR_ERROR_HANDLE_INVALID;
    if (!info || info->type != XR_TYPE_SESSION_ACTION_SETS_ATTACH_INFO || info->countActionSets == 0 ||
        !info->actionSets)
        return XR_ERROR_VALIDATION_FAILURE;
    if (!s->attachedSets.empty()) return XR_ERROR_ACTIONSETS_ALREADY_ATTACHED;
    std::vector<ActionSet*> sets;
    for (uint32_t i = 0; i < info->countActionSets; ++i) {
        ActionSet* set = getActionSet(info->actionSets[i]);
        if (!set) return XR_ERROR_HANDLE_INVALID;
        sets.push_back(set);
    }
    Instance* inst = s->instance;
    for (ActionSet* set : sets) set->attached = true;
    s->attachedSets = sets;
    // Our simulated HMD has eyes and no controllers: only the eye-gaze profile can become current,
    // and only for a pose action (a binding of another type is suggested but never bound). It becomes
    // current at the next xrSyncActions, the one call in which the specification lets a runtime
    // change interaction profiles (and queue XR_TYPE_EVENT_DATA_INTERACTION_PROFILE_CHANGED).
    auto eyes = inst->pathIds.find(kEyeGazeProfile);
    if (eyes != inst->pathIds.end() && inst->suggested.count(eyes->second))
        for (const auto& b : inst->suggested[eyes->second])
            for (ActionSet* set : sets)
                for (auto& a : set->actions)
                    if (reinterpret_cast<XrAction>(a.get()) == b.action && a->actionType == XR_ACTION_TYPE_POSE_INPUT)
                        s->eyeGazeBound = true;
    return XR_SUCCESS;
}

XRAPI_ATTR XrResult XRAPI_CALL xrGetCurrentInteractionProfile(XrSession h, XrPath topLevelUserPath,
                                                              XrInteractionProfileState* state) {
    std::lock_guard lock(stateMutex(h));
    Session* s = getSession(h);
    if (!s) return XR_ERROR_HANDLE_INVALID;
    if (!state || state->type != XR_TYPE_INTERACTION_PROFILE_STATE) return XR_ERROR_VALIDATION_FAILURE;
    if (s->attachedSets.empty()) return XR_ERROR_ACTIONSET_NOT_ATTACHED;
    const std::string user = s->instance->pathString(topLevelUserPath);
    if (user.empty()) return XR_ERROR_PATH_INVALID;
    if (!knownUserPath(*s->instance, user)) return XR_ERROR_PATH_UNSUPPORTED;
    state->interactionProfile =
        user == "/user/eyes_ext" && s->eyeGazeCurrent ? s->instance->path(kEyeGazeProfile) : XR_NULL_PATH;
    return XR_SUCCESS;
}

XRAPI_ATTR XrResult XRAPI_CALL xrSyncActions(XrSession h, const XrActionsSyncInfo* info) {
    std::lock_guard lock(stateMutex(h));
    Session* s = getSession(h);
    if (!s) return XR_ERROR_HANDLE_INVALID;
    if (!info || info->type != XR_TYPE_ACTIONS_SYNC_INFO) return XR_ERROR_VALIDATION_FAILURE;
    if (info->countActiveActionSets > 0 && !info->activeActionSets) return XR_ERROR_VALIDATION_FAILURE;
    for (uint32_t i = 0; i < info->countActiveActionSets; ++i) {
        ActionSet* set = getActionSet(info->activeActionSets[i].actionSet);
        if (!set) return XR_ERROR_HANDLE_INVALID;
        if (std::find(s->attachedSets.begin(), s->attachedSets.end(), set) == s->attachedSets.end())
            return XR_ERROR_ACTIONSET_NOT_ATTACHED;
        const XrPath sub = info->activeActionSets[i].subactionPath;
        if (sub != XR_NULL_PATH) {
            const std::string p = s->instance->pathString(sub);
            if (p.empty()) return XR_ERROR_PATH_INVALID;
            if (!knownUserPath(*s->instance, p)) return XR_ERROR_PATH_UNSUPPORTED;
        }
    }
    if (s->eyeGazeBound && !s->eyeGazeCurrent) {
        s->eyeGazeCurrent = true;
        XrEventDataBuffer e{XR_TYPE_EVENT_DATA_BUFFER};
        auto* changed = reinterpret_cast<XrEventDataInteractionProfileChanged*>(&e);
        changed->type = XR_TYPE_EVENT_DATA_INTERACTION_PROFILE_CHANGED;
        changed->session = h;
        s->instance->pushEvent(e);
    }
    s->synced = sessionFocused(*s);
    return s->synced ? XR_SUCCESS : XR_SESSION_NOT_FOCUSED;
}

namespace {

/// Shared checks of the xrGetActionState* calls; on success `action` is set.
XrResult actionStateCheck(XrSession h, const XrActionStateGetInfo* info, XrActionType type, void* state,
                          XrStructureType stateType, Session*& session, Action*& action) {
    session = getSession(h);
    if (!session) return XR_ERROR_HANDLE_INVALID;
    if (!info || info->type != XR_TYPE_ACTION_STATE_GET_INFO || !state ||
        static_cast<XrBaseOutStructure*>(state)->type != stateType)
        return XR_ERROR_VALIDATION_FAILURE;
    action = getAction(info->action);
    if (!action) return XR_ERROR_HANDLE_INVALID;
    if (action->actionType != type) return XR_ERROR_ACTION_TYPE_MISMATCH;
    if (std::find(session->attachedSets.begin(), session->attachedSets.end(), action->set) ==
        session->attachedSets.end())
        return XR_ERROR_ACTIONSET_NOT_ATTACHED;
    if (XrResult r = checkSubaction(*action, info->subactionPath); r != XR_SUCCESS) return r;
    return XR_SUCCESS;
}

}  // namespace

XRAPI_ATTR XrResult XRAPI_CALL xrGetActionStateBoolean(XrSession h, const XrActionStateGetInfo* info,
                                                       XrActionStateBoolean* state) {
    std::lock_guard lock(stateMutex(h));
    Session* s;
    Action* a;
    if (XrResult r = actionStateCheck(h, info, XR_ACTION_TYPE_BOOLEAN_INPUT, state, XR_TYPE_ACTION_STATE_BOOLEAN, s, a);
        r != XR_SUCCESS)
        return r;
    state->currentState = XR_FALSE;
    state->changedSinceLastSync = XR_FALSE;
    state->lastChangeTime = 0;
    state->isActive = XR_FALSE;  // no controllers
    return XR_SUCCESS;
}

XRAPI_ATTR XrResult XRAPI_CALL xrGetActionStateFloat(XrSession h, const XrActionStateGetInfo* info,
                                                     XrActionStateFloat* state) {
    std::lock_guard lock(stateMutex(h));
    Session* s;
    Action* a;
    if (XrResult r = actionStateCheck(h, info, XR_ACTION_TYPE_FLOAT_INPUT, state, XR_TYPE_ACTION_STATE_FLOAT, s, a);
        r != XR_SUCCESS)
        return r;
    state->currentState = 0.0f;
    state->changedSinceLastSync = XR_FALSE;
    state->lastChangeTime = 0;
    state->isActive = XR_FALSE;
    return XR_SUCCESS;
}

XRAPI_ATTR XrResult XRAPI_CALL xrGetActionStateVector2f(XrSession h, const XrActionStateGetInfo* info,
                                                        XrActionStateVector2f* state) {
    std::lock_guard lock(stateMutex(h));
    Session* s;
    Action* a;
    if (XrResult r =
            actionStateCheck(h, info, XR_ACTION_TYPE_VECTOR2F_INPUT, state, XR_TYPE_ACTION_STATE_VECTOR2F, s, a);
        r != XR_SUCCESS)
        return r;
    state->currentState = {0.0f, 0.0f};
    state->changedSinceLastSync = XR_FALSE;
    state->lastChangeTime = 0;
    state->isActive = XR_FALSE;
    return XR_SUCCESS;
}

XRAPI_ATTR XrResult XRAPI_CALL xrGetActionStatePose(XrSession h, const XrActionStateGetInfo* info,
                                                    XrActionStatePose* state) {
    std::lock_guard lock(stateMutex(h));
    Session* s;
    Action* a;
    if (XrResult r = actionStateCheck(h, info, XR_ACTION_TYPE_POSE_INPUT, state, XR_TYPE_ACTION_STATE_POSE, s, a);
        r != XR_SUCCESS)
        return r;
    const std::string sub = s->instance->pathString(info->subactionPath);
    state->isActive = s->synced && boundToEyeGaze(*s, a) && (sub.empty() || sub == "/user/eyes_ext");
    return XR_SUCCESS;
}

XRAPI_ATTR XrResult XRAPI_CALL xrEnumerateBoundSourcesForAction(XrSession h,
                                                                const XrBoundSourcesForActionEnumerateInfo* info,
                                                                uint32_t capacity, uint32_t* countOutput,
                                                                XrPath* sources) {
    std::lock_guard lock(stateMutex(h));
    Session* s = getSession(h);
    if (!s) return XR_ERROR_HANDLE_INVALID;
    if (!info || info->type != XR_TYPE_BOUND_SOURCES_FOR_ACTION_ENUMERATE_INFO) return XR_ERROR_VALIDATION_FAILURE;
    Action* a = getAction(info->action);
    if (!a) return XR_ERROR_HANDLE_INVALID;
    if (s->attachedSets.empty()) return XR_ERROR_ACTIONSET_NOT_ATTACHED;
    std::vector<XrPath> bound;
    if (boundToEyeGaze(*s, a)) bound.push_back(s->instance->path(kEyeGazePose));
    return fillArray(capacity, countOutput, sources, bound);
}

XRAPI_ATTR XrResult XRAPI_CALL xrGetInputSourceLocalizedName(XrSession h, const XrInputSourceLocalizedNameGetInfo* info,
                                                             uint32_t capacity, uint32_t* countOutput, char* buffer) {
    std::lock_guard lock(stateMutex(h));
    Session* s = getSession(h);
    if (!s) return XR_ERROR_HANDLE_INVALID;
    if (!info || info->type != XR_TYPE_INPUT_SOURCE_LOCALIZED_NAME_GET_INFO || info->whichComponents == 0)
        return XR_ERROR_VALIDATION_FAILURE;
    if (s->attachedSets.empty()) return XR_ERROR_ACTIONSET_NOT_ATTACHED;
    const std::string path = s->instance->pathString(info->sourcePath);
    if (path.empty()) return XR_ERROR_PATH_INVALID;
    if (path != kEyeGazePose) return XR_ERROR_PATH_UNSUPPORTED;
    std::string name;
    auto add = [&](const char* part) { name += (name.empty() ? "" : " ") + std::string(part); };
    if (info->whichComponents & XR_INPUT_SOURCE_LOCALIZED_NAME_USER_PATH_BIT) add("Eyes");
    if (info->whichComponents & XR_INPUT_SOURCE_LOCALIZED_NAME_INTERACTION_PROFILE_BIT) add("Eye Gaze Interaction");
    if (info->whichComponents & XR_INPUT_SOURCE_LOCALIZED_NAME_COMPONENT_BIT) add("Gaze Pose");
    return fillString(capacity, countOutput, buffer, name);
}

namespace {

XrResult hapticCheck(XrSession h, const XrHapticActionInfo* info) {
    Session* s = getSession(h);
    if (!s) return XR_ERROR_HANDLE_INVALID;
    if (!info || info->type != XR_TYPE_HAPTIC_ACTION_INFO) return XR_ERROR_VALIDATION_FAILURE;
    Action* a = getAction(info->action);
    if (!a) return XR_ERROR_HANDLE_INVALID;
    if (a->actionType != XR_ACTION_TYPE_VIBRATION_OUTPUT) return XR_ERROR_ACTION_TYPE_MISMATCH;
    if (std::find(s->attachedSets.begin(), s->attachedSets.end(), a->set) == s->attachedSets.end())
        return XR_ERROR_ACTIONSET_NOT_ATTACHED;
    if (XrResult r = checkSubaction(*a, info->subactionPath); r != XR_SUCCESS) return r;
    return s->synced ? XR_SUCCESS : XR_SESSION_NOT_FOCUSED;
}

}  // namespace

XRAPI_ATTR XrResult XRAPI_CALL xrApplyHapticFeedback(XrSession h, const XrHapticActionInfo* info,
                                                     const XrHapticBaseHeader* feedback) {
    std::lock_guard lock(stateMutex(h));
    if (!feedback || feedback->type != XR_TYPE_HAPTIC_VIBRATION) return XR_ERROR_VALIDATION_FAILURE;
    return hapticCheck(h, info);  // no actuator: accepted and dropped
}

XRAPI_ATTR XrResult XRAPI_CALL xrStopHapticFeedback(XrSession h, const XrHapticActionInfo* info) {
    std::lock_guard lock(stateMutex(h));
    return hapticCheck(h, info);
}

}  // namespace wrsfov::xr
