// The checks shared by the OpenXR calls: handle lookups, the one system, well-formed paths and
// names, subaction paths.
#include "runtime/xr_verify.h"

#include <cstring>
#include <string>

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

}  // namespace wrsfov::xr
