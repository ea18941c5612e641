// The preview's application side: makes each frame of a built-in scene (text, atrium, dynamic, photo) and
// submits it, with the frame's gaze, to one or more compositors (the method shown and, when the
// view needs it, the unfoveated reference), each through its own swapchains.
#pragma once

#include <array>
#include <map>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>

#include "compositor/compositor.h"
#include "compositor/host_app.h"
#include "layers/frame.h"
#include "scenes/atrium.h"
#include "scenes/photo.h"
#include "scenes/text.h"

namespace wrsfov::preview {

/// The built-in scenes the preview shows (scenes/).
enum class SceneKind : uint8_t { Text, Atrium, Dynamic, Photo };
std::string_view toString(SceneKind s);
std::optional<SceneKind> parseScene(std::string_view name);
SceneKind nextScene(SceneKind s);

struct SceneFeedOptions {
    SceneKind scene = SceneKind::Text;
    scenes::CameraPath path = scenes::CameraPath::Lateral;  ///< atrium and dynamic only
    uint32_t width = 0, height = 0;                         ///< per eye
    uint32_t seed = 1;
    /// Scene photo (scenes/photo.h): the image (a file, or grass / wood), the head's motion and speed
    /// (pixels per frame at 90 Hz at the view's centre).
    std::string photoImage = "grass";
    scenes::PhotoMotion photoMotion = scenes::PhotoMotion::Pan;
    float photoSpeed = 0.37f;
};

class SceneFeed {
public:
    static Result<std::unique_ptr<SceneFeed>> create(vk::Context& ctx, const SceneFeedOptions& options);

    /// Makes the frame at scene time `t` (motion from `prevT`) and ends frame `frameIndex` on each
    /// target with `gaze`. Every target sees the same images.
    Status submit(std::span<Compositor* const> targets, uint64_t frameIndex, double t, double prevT,
                  const std::array<layers::EyeGaze, 2>& gaze);

    layers::Fov fov(int eye) const;
    const SceneFeedOptions& options() const { return options_; }
    /// The text scene's layout (what the reading generator follows); the default layout otherwise.
    scenes::TextLayout textLayout() const;

private:
    explicit SceneFeed(const SceneFeedOptions& o) : options_(o) {}
    Result<HostStereoApp*> app(Compositor& target);

    SceneFeedOptions options_;
    std::unique_ptr<scenes::TextScene> text_;
    std::unique_ptr<scenes::AtriumRenderer> atrium_;
    std::unique_ptr<scenes::PhotoScene> photo_;
    std::map<Compositor*, std::unique_ptr<HostStereoApp>> apps_;  // one set of swapchains per target
};

}  // namespace wrsfov::preview
