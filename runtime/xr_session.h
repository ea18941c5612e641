// The runtime's session: what its API files (xr_session.cpp, xr_api_space.cpp, xr_api_swapchain.cpp,
// xr_session_frame.cpp) call in each other. The objects themselves are in xr_objects.h.
#pragma once

#include <array>
#include <cmath>
#include <mutex>

#include "layers/frame.h"
#include "runtime/xr_objects.h"

namespace wrsfov::xr {

/// With the session's frameMutex held.
void setState(Session* s, XrSessionState state);

/// Walks the states down to STOPPING (FOCUSED -> VISIBLE -> SYNCHRONIZED -> STOPPING); with the
/// session's frameMutex held.
void beginStopping(Session* s);

/// The display's frame period.
inline XrDuration period(const Instance& inst) { return XrDuration(std::llround(1e9 / inst.config.displayHz)); }

/// Eye `eye`'s pose (0 left, 1 right) at `t`, in the stage space.
Pose eyeAt(const Session& s, XrTime t, int eye);

/// Both eyes' gaze for a frame shown at `t`, in each eye's space. The generator is cyclopean: both
/// eyes turn to one point (binocular vergence, so the left and right directions differ as in a real
/// HMD): where the left eye's ray along the generator's direction meets the submitted depth, or
/// `vergence_distance` along that direction without depth. A file or a tracker gives each eye as
/// measured; the mouse gives each eye the ray through the cursor's pixel.
std::array<layers::EyeGaze, 2> frameGaze(Session& s, XrTime t, const layers::ProjectionView& left);

/// With the session's frameMutex held (by `lock`): waits until frame `serial` is complete, at most
/// `timeout` (XR_INFINITE_DURATION: no limit). False when the time ran out. A wait of no time only
/// looks (and so never opens a held frame, see Session::holdFrames).
bool waitForFrame(Session* s, std::unique_lock<std::mutex>& lock, uint64_t serial, XrDuration timeout);

}  // namespace wrsfov::xr
