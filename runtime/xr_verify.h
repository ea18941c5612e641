// The checks shared by the OpenXR calls of xr_api_*.cpp (internal to runtime/): handle lookups,
// the one system, well-formed paths and names. Each returns what the specification asks of a call
// that fails it; the calls do their work only after them.
#pragma once

#include <cstddef>
#include <string>

#include "runtime/xr_objects.h"

namespace wrsfov::xr {

constexpr XrSystemId kSystemId = 1;

Instance* getInstance(XrInstance h);
Session* getSession(XrSession h);
ActionSet* getActionSet(XrActionSet h);
Action* getAction(XrAction h);
Space* getSpace(XrSpace h);
Swapchain* getSwapchain(XrSwapchain h);

/// The state lock (Instance::mutex) of the instance a handle belongs to, taken before the call's own
/// lookup; for a handle that is not live, a lock of no object (the lookup then fails the call).
std::recursive_mutex& stateMutex(XrInstance h);
std::recursive_mutex& stateMutex(XrSession h);
std::recursive_mutex& stateMutex(XrActionSet h);
std::recursive_mutex& stateMutex(XrAction h);
std::recursive_mutex& stateMutex(XrSpace h);

/// HANDLE_INVALID without an instance, SYSTEM_INVALID for another system than kSystemId.
XrResult checkSystem(Instance* inst, XrSystemId id);

/// OpenXR path syntax: absolute, components of [a-z0-9-_.] that are not "." or "..", no empty one.
bool wellFormedPath(const char* s);

/// Action and action-set names: NAME_INVALID when empty, PATH_FORMAT_INVALID when not one well-formed
/// path component (lower case, digits, '-', '_', '.'; terminated within the array).
XrResult checkName(const char* s, std::size_t max);

/// A refused call: the specification's result, and the field and value that were wrong, e.g.
/// `(frameEndInfo->layers[0]->views[2].fov.angleLeft == -0.95) is outside views[0]'s -0.87`.
struct Refusal {
    XrResult result = XR_SUCCESS;
    std::string message;
    explicit operator bool() const { return result != XR_SUCCESS; }
};
/// "XR_ERROR_VALIDATION_FAILURE: <message>", for the log.
std::string describe(const Refusal& r);

/// Everything the specification requires of a frame end, before anything is composited: display
/// time, blend mode, layer count, each layer's type, flags and space, projection views (as many as
/// the session's view configuration has; for quad views each inset inside its wide view with the same
/// pose), poses, fields of view, sub-images (a released image, array index, rectangle), depth and
/// space-warp infos, quad sizes.
Refusal checkFrameEnd(Session* s, const XrFrameEndInfo* info);

}  // namespace wrsfov::xr
