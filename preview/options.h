// Command line of wrsfov-preview and the settings the keys change.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "compositor/compositor.h"
#include "layers/status.h"
#include "preview/gaze_input.h"
#include "preview/layout.h"
#include "preview/scene_feed.h"
#include "scenes/atrium.h"

namespace wrsfov::preview {

/// What the main compositor runs: the unfoveated reference or one of the methods.
enum class PreviewMethod : uint8_t { Reference, Fov, FovTaa, WrsPaper, Wrs };
std::string_view toString(PreviewMethod m);
std::optional<PreviewMethod> parseMethod(std::string_view name);
PreviewMethod nextMethod(PreviewMethod m);

scenes::CameraPath nextPath(scenes::CameraPath p);

/// The fovea sizes the F key steps through (diameters, degrees).
inline constexpr float kFoveaSteps[] = {5.0f, 7.5f, 10.0f};
/// The next of kFoveaSteps after `deg` (wrapping to the first).
float nextFovea(float deg);

/// The compositor configuration of a method: the reference is `fov` without foveation.
CompositorConfig compositorConfig(PreviewMethod method, FoveationMode mode, float foveaDeg, uint32_t seed,
                                  bool skipTiles = true);

struct PreviewOptions {
    uint32_t width = 320, height = 288;   ///< per eye
    SceneKind scene = SceneKind::Atrium;  ///< text needs about 1400 px per eye to be legible
    scenes::CameraPath path = scenes::CameraPath::Lateral;
    std::string photoImage = "grass";  ///< scene photo (--photo, --photo-motion, --photo-speed)
    scenes::PhotoMotion photoMotion = scenes::PhotoMotion::Pan;
    float photoSpeed = 0.37f;
    PreviewMethod method = PreviewMethod::Wrs;
    float foveaDeg = 5.0f;
    FoveationMode mode = FoveationMode::Mip;
    GazeSpec gaze;
    uint32_t seed = 1;
    View view = View::Stereo;
    bool overlay = true;     ///< gaze marker and fovea / mid-periphery circles
    bool skipTiles = true;   ///< CompositorConfig::skipTiles (--no-skip: off)
    int frames = 0;          ///< composite this many frames, then exit (0: until the window is closed)
    std::string screenshot;  ///< with --frames: PNG of the preview image after the last frame
    /// Test hooks: resize the window after frame `resizeFrame`; move the pointer at start.
    int resizeFrame = -1;
    uint32_t resizeWidth = 0, resizeHeight = 0;
    std::optional<std::array<double, 2>> cursor;
    /// Test hook: key presses (names as in keyHelp: a letter, a digit, space, right, escape) at loop
    /// iterations, as if typed.
    std::vector<std::pair<int, std::string>> keys;
    bool help = false;     ///< --help: print `text` (the options, then the keys) and exit
    bool version = false;  ///< --version: print `text` and exit
    std::string text;
};

/// Parses the command line (argv[0] is skipped) with CLI11, or a --config file. Errors name the option
/// and the value; their code is 2 (a usage error) or 1 (a --config file that cannot be read).
Result<PreviewOptions> parseArguments(int argc, const char* const* argv);
/// The --help text: the options with their defaults, the environment, the keys.
std::string usage();
/// The keys, one per line.
std::string keyHelp();

}  // namespace wrsfov::preview
