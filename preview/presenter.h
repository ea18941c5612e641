// Presentation: a Vulkan swapchain on the window's surface, the panel pass that builds the
// preview image (panels of the compositor's output, reference or error map, gaze marker and
// fovea circles, the stats strip) and the blit of that image into the swapchain image, with two
// frames in flight. Recreates the swapchain when the window changes size or the surface reports
// VK_ERROR_OUT_OF_DATE_KHR / VK_SUBOPTIMAL_KHR.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <opencv2/core.hpp>
#include <vector>

#include "compositor/compositor.h"
#include "compositor/vk_context.h"
#include "layers/status.h"
#include "preview/panel_params.h"
#include "preview/layout.h"

struct GLFWwindow;

namespace wrsfov::preview {

/// What the overlay of one eye shows: the gaze and fovea the compositor used for that eye.
struct EyeOverlay {
    glm::vec4 fovTan{0};  ///< tan left, right, up, down
    glm::vec4 gaze{0};    ///< xyz: unit direction; w: fovea radius r_f in degrees
    float midRadiusDeg = 7.5f;
    bool gazeValid = false;  ///< false: the compositor fell back to the view centre (no marker)
};

/// The overlays of both eyes from what `compositor` used in its last frame.
std::array<EyeOverlay, 2> eyeOverlays(const Compositor& compositor);

/// One preview image to compose and present.
struct ComposeFrame {
    const Layout* layout = nullptr;
    const vk::Image* output = nullptr;     ///< the compositor's output: 2 layers, GENERAL, RGBA8 sRGB-encoded
    const vk::Image* reference = nullptr;  ///< the reference's output (same size), or null
    std::array<EyeOverlay, 2> eyes;
    bool circles = true;  ///< fovea and mid-periphery circles
    bool marker = true;   ///< gaze marker
    float errorGain = 4.0f;
    /// FovVideoVDP's visible distortion of each eye in JOD units (CV_32F, one eye's size), for the
    /// visible-difference panels; null: those panels show black.
    std::array<const cv::Mat*, 2> visible{};
    float visibleGain = 0.2f;        ///< 1 / the JOD at the top of the ramp (5: the map's values reach about 5)
    const cv::Mat* strip = nullptr;  ///< CV_8UC4 premultiplied RGBA, layout->width x layout->stripHeight
};

enum class PresentOutcome : uint8_t {
    Presented,
    Skipped,  ///< the swapchain was out of date or the window has no area: recreated / waiting, nothing shown
};

class Presenter {
public:
    static constexpr uint32_t kFramesInFlight = 2;

    /// Creates the surface of `window` (on the context's instance) and its swapchain. Fails when
    /// the context's queue cannot present to it or the surface offers nothing a blit can write.
    static Result<std::unique_ptr<Presenter>> create(vk::Context& ctx, GLFWwindow* window);
    ~Presenter();
    Presenter(const Presenter&) = delete;
    Presenter& operator=(const Presenter&) = delete;

    Result<PresentOutcome> present(const ComposeFrame& frame);
    /// The window's framebuffer changed size: recreate before the next image.
    void framebufferResized() { resized_ = true; }

    /// The preview image composed last (its own resolution, not the window's), 8-bit BGR.
    Result<cv::Mat> lastImage();

    uint32_t swapchainRecreations() const { return recreations_; }
    /// Why the swapchain was last recreated: "window resized", "VK_ERROR_OUT_OF_DATE_KHR" or "VK_SUBOPTIMAL_KHR".
    const char* recreationReason() const { return reason_; }
    VkExtent2D extent() const { return extent_; }
    VkFormat surfaceFormat() const { return format_.format; }
    /// Where the preview image was drawn in the last presented swapchain image.
    const Placement& placement() const { return placement_; }

private:
    Presenter(vk::Context& ctx, GLFWwindow* window) : ctx_(ctx), window_(window) {}
    Status init();
    /// (Re)creates the swapchain for the window's framebuffer; false (no error) while it has no area.
    Result<bool> createSwapchain();
    void destroySwapchain();
    Status ensureTargets(const Layout& layout);

    struct Slot {
        VkCommandBuffer cmd = VK_NULL_HANDLE;
        VkSemaphore imageAvailable = VK_NULL_HANDLE;
        VkFence inFlight = VK_NULL_HANDLE;
        VkDescriptorSet set = VK_NULL_HANDLE;
        vk::Image target;    ///< the preview image this slot composes into (GENERAL)
        vk::Buffer strip;    ///< the stats strip, written by the CPU
        vk::Buffer visible;  ///< both eyes' visible distortion (float), written by the CPU
    };

    vk::Context& ctx_;
    GLFWwindow* window_;
    VkSurfaceKHR surface_ = VK_NULL_HANDLE;
    VkSwapchainKHR swapchain_ = VK_NULL_HANDLE;
    VkSurfaceFormatKHR format_{};
    VkExtent2D extent_{};
    std::vector<VkImage> images_;
    std::vector<VkSemaphore> renderFinished_;  // one per swapchain image
    bool resized_ = false;
    bool needRecreate_ = false;
    uint32_t recreations_ = 0;
    const char* reason_ = "";
    const char* pendingReason_ = "";
    Placement placement_;

    vk::DescriptorSetLayout setLayout_;
    vk::PipelineLayout pipelineLayout_;
    vk::DescriptorPool pool_;
    vk::ShaderModule module_;
    vk::Pipeline pipeline_;
    vk::Sampler sampler_;
    VkFormat targetFormat_ = VK_FORMAT_R8G8B8A8_UNORM;
    bool linearBlit_ = true;
    uint32_t targetWidth_ = 0, targetHeight_ = 0, stripHeight_ = 0, eyeWidth_ = 0, eyeHeight_ = 0;
    std::array<Slot, kFramesInFlight> slots_;
    uint32_t frame_ = 0;
    int lastSlot_ = -1;
};

}  // namespace wrsfov::preview
