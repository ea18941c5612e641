// Configuration of the simulated-HMD OpenXR runtime: a small key = value file named by
// WRSFOV_XR_CONFIG, then environment variables WRSFOV_XR_<KEY> (upper case) over it. Every key,
// its default and its meaning are in docs/openxr-runtime.md; an unknown key or a bad value fails
// xrCreateInstance with the key named.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <string_view>

#include "compositor/compositor.h"
#include "gaze/generator.h"
#include "gaze/source.h"
#include "layers/frame.h"
#include "layers/status.h"
#include "scenes/atrium.h"

namespace wrsfov::xr {

/// Where the eyes look.
enum class GazeKind : uint8_t {
    Generator,  ///< the synthetic eye-movement generator (`gaze_mode`, `gaze_seed`)
    File,       ///< a recorded gaze file (`gaze_file`)
    Hid,        ///< a HID eye tracker (usage page 0x12)
    Mouse,      ///< the cursor over an eye in the window (headless: no gaze)
    None,       ///< no gaze: the compositor's fallback (view centre, larger fovea)
};

/// Where the composited frames go besides a recording.
enum class Output : uint8_t {
    Auto,      ///< a window when a display is there (DISPLAY or WAYLAND_DISPLAY), else headless
    Window,    ///< a window (headless, with a log line, when none can be made)
    Headless,  ///< no window
};

struct RuntimeConfig {
    CompositorConfig compositor;          ///< method, fovea, foveation (keys `method`, `fovea`, `foveation`)
    bool compose = true;                  ///< method = off: frames are shown and recorded as submitted
    uint32_t width = 1024, height = 1024;  ///< the display's per-eye size (the stereo views' recommended size)
    /// XR_VARJO_quad_views and XR_VARJO_foveated_rendering offered (key `quad_views`): the wide views at
    /// 1 / 2.5 of the display's density, an inset of `insetDeg` across at the display's density.
    bool quadViews = true;
    float insetDeg = 30.0f;  ///< the inset's angular size across, both axes (key `inset_deg`)
    /// Swapchains as other runtimes have been seen to make them (key `swapchains = strict`; `own` is
    /// the default): XR_SWAPCHAIN_USAGE_MUTABLE_FORMAT_BIT ignored (as Monado 21 on Linux does), so
    /// sRGB images are never MUTABLE_FORMAT; 8-bit colour offered as sRGB only (no R8G8B8A8_UNORM); four
    /// images per swapchain rather than three. What an API layer over another runtime must not assume.
    bool strictSwapchains = false;
    /// Per-eye field of view: the HMD's asymmetric 92° x 93° (hmdFov) unless `fov` gives a symmetric
    /// square one in degrees.
    layers::Fov fov[2];
    float ipd_m = 0.063f;
    double displayHz = 90.0;
    /// realtime: xrWaitFrame sleeps to the display rate; free: no sleeping, each frame's display time
    /// is one period after the last (deterministic recordings, fast tests).
    bool pace = true;
    uint64_t frames = 0;  ///< > 0: the session is asked to stop after this many frames
    std::string record;   ///< sequence directory to record into (colour, depth, motion, gaze, output)
    scenes::CameraPath head = scenes::CameraPath::Static;
    GazeKind gaze = GazeKind::Generator;
    gaze::Mode gazeMode = gaze::Mode::Scene;
    uint64_t gazeSeed = 1;
    std::string gazeFile;
    /// Distance of the fixated point when the frame has no depth (metres, along the cyclopean gaze).
    float vergenceDistance_m = 1.5f;
    /// Count Vulkan validation messages on the instance the runtime creates (XR_KHR_vulkan_enable2):
    /// enables VK_LAYER_KHRONOS_validation there. Default: WRSFOV_VALIDATION=1.
    bool validation = false;
    bool verbose = false;
    Output output = Output::Auto;
    std::string screenshot;  ///< window: the last window image is written here (PNG) when the session ends
};

/// Reads the file named by WRSFOV_XR_CONFIG (if set) and the WRSFOV_XR_* variables (`getenv` is
/// injectable for tests). The error message names the file, line or variable and the key.
Result<RuntimeConfig> loadRuntimeConfig(const std::function<const char*(const char*)>& getenv = nullptr);
/// The same keys under another prefix: `prefix` + "CONFIG" names the file, `prefix` + KEY the
/// variables (the API layer reads WRSFOV_LAYER_*).
Result<RuntimeConfig> loadConfig(const std::string& prefix, const std::function<const char*(const char*)>& getenv = nullptr);

/// The gaze source `config` names (generator, file or HID tracker); null for `mouse` and `none`. The
/// error names the source and why it could not be opened.
Result<std::unique_ptr<gaze::GazeSource>> openGazeSource(const RuntimeConfig& config);

/// Applies one key (file or environment) to `config`; the message names the key and the accepted values.
Status applyConfigKey(RuntimeConfig& config, std::string_view key, std::string_view value);

}  // namespace wrsfov::xr
