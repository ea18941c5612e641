// wrsfov-preview: a GLFW window presenting, through a Vulkan swapchain, the compositor's output for
// both eyes with the gaze, the fovea and the per-pass GPU time; keys switch method, fovea size,
// foveation mode, scene, camera path, view and gaze source (options.h).
#pragma once

#include "preview/options.h"

namespace wrsfov::preview {

/// Exit statuses of runPreview.
inline constexpr int kExitOk = 0;
inline constexpr int kExitFailure =
    1;  ///< no display, no Vulkan device that can present, a scene or gaze source failed
inline constexpr int kExitBadArguments = 2;
inline constexpr int kExitValidation = 3;  ///< the Khronos validation layer reported errors (WRSFOV_VALIDATION=1)

/// Opens the window and runs until it is closed (or `options.frames` frames were composited, then
/// writes `options.screenshot`). Messages go to stdout, errors to stderr.
int runPreview(const PreviewOptions& options);

}  // namespace wrsfov::preview
