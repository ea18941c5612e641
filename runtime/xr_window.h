// The simulated HMD's desktop window (internal to runtime/): both eyes of the compositor's output
// with the preview's overlays (gaze marker, fovea and mid-periphery circles, a stats strip), drawn by
// the preview's Presenter on the application's device; the cursor over an eye is the mouse gaze.
#pragma once

#include <array>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "compositor/compositor.h"
#include "preview/layout.h"
#include "preview/presenter.h"

struct GLFWwindow;

namespace wrsfov::xr {

class XrWindow {
public:
    /// Initialises GLFW (once per process) and returns the instance extensions a window surface
    /// needs; fails when there is no display or no Vulkan surface support.
    static Result<std::vector<std::string>> instanceExtensions();
    /// Whether `queueFamily` of `device` can present to a window.
    static bool canPresent(VkInstance instance, VkPhysicalDevice device, uint32_t queueFamily);
    /// A window for eyes of this size, on the context's instance and queue (which must have the
    /// surface and swapchain extensions).
    static Result<std::unique_ptr<XrWindow>> create(vk::Context& ctx, uint32_t eyeWidth, uint32_t eyeHeight,
                                                    const std::string& title);
    ~XrWindow();

    /// Composes and presents the compositor's last output with `stats` in the strip; polls events.
    Status present(const Compositor& compositor, const std::vector<std::string>& stats);
    /// The user closed the window.
    bool closeRequested() const;
    /// The cursor's position in an eye image (continuous pixels, y down) when it is over an eye.
    std::optional<std::array<float, 2>> cursor() const;
    /// The last composed window image (BGR), for screenshots.
    Result<cv::Mat> lastImage() { return presenter_->lastImage(); }

private:
    XrWindow() = default;
    GLFWwindow* window_ = nullptr;
    std::unique_ptr<preview::Presenter> presenter_;
    preview::Layout layout_;
    uint32_t eyeWidth_ = 0, eyeHeight_ = 0;
};

}  // namespace wrsfov::xr
